#include "causal/estimation/kernel_dispatch.hpp"

#include "kernels.hpp"

namespace causal::estimation {

const char* kernel_instruction_set() {
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(CAUSAL_CORE_NO_CLONES)
  // The same predicates the target_clones resolver evaluates, in the same order of preference.
  __builtin_cpu_init();
  if (__builtin_cpu_supports("x86-64-v4")) return "x86-64-v4";
  if (__builtin_cpu_supports("x86-64-v3")) return "x86-64-v3";
#endif
  return "baseline";
}

}  // namespace causal::estimation
