// YAML files the services and causal-plant-profiles read (common/config: yaml_bounds.hpp) are bounded before
// yaml-cpp builds a tree: nesting (32 levels), size (1 MiB), node count (100,000), and no anchors or aliases
// ("billion laughs": nine lines expand to 10^9 nodes for any code that walks them). Each refusal is a ConfigError
// naming the file and the line; each is answered at once and the process stays small.
#include "causal/config/yaml_bounds.hpp"
#include "causal/config/yaml_fields.hpp"

#include "config_test_util.hpp"

#include <gtest/gtest.h>

#include <sys/resource.h>

#include <chrono>
#include <string>

namespace {

using causal::config::kMaxYamlBytes;
using causal::config::Section;
using causal::test::config_error;
using causal::test::write_yaml;

// Loads `path`, expects a ConfigError within a second, returns its message.
std::string refused(const std::string& path) {
  const auto start = std::chrono::steady_clock::now();
  const std::string message = config_error([&] { Section::load_file(path); });
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1)) << message;
  return message;
}

long peak_rss_kb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

// {a: {a: ... 1 ...}} with `levels` maps, under the key top (the file's own map is one more level).
std::string nested_maps(std::size_t levels) {
  std::string s = "top: ";
  for (std::size_t i = 0; i < levels; ++i) s += "{a: ";
  s += "1";
  for (std::size_t i = 0; i < levels; ++i) s += "}";
  return s + "\n";
}

TEST(YamlBounds, NestingIsBoundedAt32Levels) {
  const std::string ok = write_yaml("nested_ok.yaml", nested_maps(31));  // 32 with the top-level map
  EXPECT_NO_THROW(Section::load_file(ok));
  const std::string message = refused(write_yaml("nested_33.yaml", nested_maps(32)));
  EXPECT_HAS(message, "nested_33.yaml: line 1: nested deeper than 32 levels");
  // 100,000 open brackets: refused at level 33, long before yaml-cpp's own guard (2000) or the stack.
  const std::string deep = refused(write_yaml("brackets.yaml", "top: " + std::string(100000, '[') + "\n"));
  EXPECT_HAS(deep, "nested deeper than 32 levels");
}

TEST(YamlBounds, HugeFilesAndScalarsAreRefusedBySize) {
  const std::string big_scalar = "top: \"" + std::string(kMaxYamlBytes - 100, 'x') + "\"\n";
  EXPECT_NO_THROW(Section::load_file(write_yaml("scalar_ok.yaml", big_scalar)));
  const std::string message =
      refused(write_yaml("scalar_huge.yaml", "top: \"" + std::string(4 * kMaxYamlBytes, 'x') + "\"\n"));
  EXPECT_HAS(message, "scalar_huge.yaml: larger than 1024 KiB (not a parameter file)");
}

TEST(YamlBounds, AnchorsAndAliasesAreRefused) {
  // The billion laughs: lol9 is 10^9 "lol" strings for a walker of the tree.
  std::string laughs = "lol0: &lol0 lol\n";
  for (int i = 1; i <= 9; ++i) {
    laughs += "lol" + std::to_string(i) + ": &lol" + std::to_string(i) + " [";
    for (int k = 0; k < 10; ++k) laughs += std::string(k ? ", " : "") + "*lol" + std::to_string(i - 1);
    laughs += "]\n";
  }
  EXPECT_HAS(refused(write_yaml("laughs.yaml", laughs)),
             "laughs.yaml: line 1: anchors (&name) are not allowed in a parameter file");
  // An anchored section merged into another (<<: *base) is refused the same way.
  EXPECT_HAS(refused(write_yaml("merge.yaml", "base: &base {count: 1}\ntop:\n  <<: *base\n")),
             "merge.yaml: line 1: anchors (&name) are not allowed");
  EXPECT_HAS(refused(write_yaml("alias.yaml", "top:\n  count: 1\nother: [1, *nowhere]\n")), "alias.yaml");
}

TEST(YamlBounds, NodeFloodsAreRefused) {
  std::string flood = "top:\n";
  for (int i = 0; i < 150000; ++i) flood += "- 1\n";  // 600 kB: under the size bound
  ASSERT_LT(flood.size(), kMaxYamlBytes);
  EXPECT_HAS(refused(write_yaml("flood.yaml", flood)), "more than 100000 values");
}

TEST(YamlBounds, UnknownKeysAreStillRefusedByTheSection) {
  const Section root = Section::load_file(write_yaml("unknown.yaml", "top:\n  count: 1\n  cuont: 2\n"));
  EXPECT_HAS(config_error([&] { root.child("top").only({"count"}); }), "unknown.yaml: top.cuont");
}

TEST(YamlBounds, TheProcessStaysSmall) {
  // After every case above in this process (ctest runs each case alone; run the whole binary to see them all).
  EXPECT_LT(peak_rss_kb(), 100 * 1024) << "peak RSS " << peak_rss_kb() << " kB";
}

}  // namespace
