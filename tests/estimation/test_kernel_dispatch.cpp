// kernel_instruction_set() against the CPU flags the kernel reports in /proc/cpuinfo (an independent source):
// the variant named must be the best one the flags allow.
#include "causal/estimation/kernel_dispatch.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace {

std::set<std::string> cpu_flags() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("flags", 0) != 0) continue;
    std::istringstream words(line.substr(line.find(':') + 1));
    std::set<std::string> flags;
    for (std::string w; words >> w;) flags.insert(w);
    return flags;
  }
  return {};
}

bool has_all(const std::set<std::string>& flags, std::initializer_list<const char*> want) {
  for (const char* w : want) {
    if (flags.count(w) == 0) return false;
  }
  return true;
}

}  // namespace

TEST(KernelDispatch, NamesTheBestVariantTheCpuFlagsAllow) {
#if !defined(__x86_64__) || !defined(__GNUC__) || defined(__clang__) || defined(CAUSAL_CORE_NO_CLONES)
  EXPECT_STREQ(causal::estimation::kernel_instruction_set(), "baseline");
#else
  const std::set<std::string> flags = cpu_flags();
  if (flags.empty()) GTEST_SKIP() << "no /proc/cpuinfo flags";
  // x86-64 psABI micro-architecture levels.
  const bool v3 = has_all(flags, {"avx", "avx2", "bmi1", "bmi2", "f16c", "fma", "abm", "movbe", "xsave"});
  const bool v4 = v3 && has_all(flags, {"avx512f", "avx512bw", "avx512cd", "avx512dq", "avx512vl"});
  const std::string expect = v4 ? "x86-64-v4" : v3 ? "x86-64-v3" : "baseline";
  EXPECT_EQ(causal::estimation::kernel_instruction_set(), expect);
#endif
}
