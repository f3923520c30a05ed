// causal::config::Section (common/config): strict YAML access. Every error must be a ConfigError whose message
// names the file and the dotted key path, so an operator can fix the parameter file without reading code.
#include "causal/config/yaml_fields.hpp"

#include "config_test_util.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

namespace {

using causal::config::ConfigError;
using causal::config::Section;
using causal::test::config_error;
using causal::test::write_yaml;

const char* kDoc = R"(
top:
  count: 7
  ratio: 0.25
  zero: 0
  negative: -1.5
  flag: true
  name: rms
  text_number: abc
  fraction_int: 1.5
  huge: 99999999999999999999999
  not_a_bool: maybe
  nan_value: .nan
  inf_value: .inf
  empty:
  list: [1, 2, 3]
  nested:
    deeper:
      leaf: 3
other:
  a: 1
)";

class SectionTest : public ::testing::Test {
 protected:
  void SetUp() override { path_ = write_yaml("fields.yaml", kDoc); }
  Section top() const { return Section::load_file(path_).child("top"); }
  std::string path_;
};

TEST_F(SectionTest, ReadsValidValues) {
  const Section s = top();
  EXPECT_EQ(s.integer("count", 1, 10), 7);
  EXPECT_DOUBLE_EQ(s.number("ratio"), 0.25);
  EXPECT_DOUBLE_EQ(s.positive("ratio"), 0.25);
  EXPECT_DOUBLE_EQ(s.non_negative("zero"), 0.0);
  EXPECT_DOUBLE_EQ(s.number("negative"), -1.5);
  EXPECT_TRUE(s.boolean("flag"));
  EXPECT_EQ(s.text("name"), "rms");
  EXPECT_EQ(s.one_of("name", {"meanabs", "rms"}), "rms");
  EXPECT_EQ(s.child("nested").child("deeper").integer("leaf", 3, 3), 3);  // bounds are inclusive
  EXPECT_TRUE(s.has("count"));
  EXPECT_FALSE(s.has("absent"));
  EXPECT_FALSE(s.has("empty"));  // a key with no value counts as missing
}

TEST_F(SectionTest, MissingKeyNamesFileAndDottedPath) {
  const std::string msg = config_error([&] { top().number("absent"); });
  EXPECT_HAS(msg, path_);
  EXPECT_HAS(msg, "top.absent");
  EXPECT_HAS(msg, "missing");
}

TEST_F(SectionTest, EmptyValueIsMissing) {
  const std::string msg = config_error([&] { top().integer("empty", 0, 10); });
  EXPECT_HAS(msg, "top.empty");
  EXPECT_HAS(msg, "missing");
}

TEST_F(SectionTest, NestedPathIsFullyDotted) {
  const std::string msg = config_error([&] { top().child("nested").child("deeper").positive("nope"); });
  EXPECT_HAS(msg, path_ + ": top.nested.deeper.nope: ");
  const std::string range = config_error([&] { top().child("nested").child("deeper").integer("leaf", 4, 9); });
  EXPECT_HAS(range, "top.nested.deeper.leaf");
  EXPECT_HAS(range, "4..9");
}

TEST_F(SectionTest, MissingChildSectionAndScalarAsSection) {
  EXPECT_HAS(config_error([&] { top().child("absent"); }), "top.absent");
  const std::string msg = config_error([&] { top().child("count"); });
  EXPECT_HAS(msg, "top.count");
  EXPECT_HAS(msg, "section");
}

TEST_F(SectionTest, WrongTypes) {
  const std::string number = config_error([&] { top().number("text_number"); });
  EXPECT_HAS(number, "top.text_number");
  EXPECT_HAS(number, "abc");
  EXPECT_HAS(config_error([&] { top().number("list"); }), "top.list");
  EXPECT_HAS(config_error([&] { top().positive("text_number"); }), "top.text_number");

  const std::string whole = config_error([&] { top().integer("fraction_int", 0, 10); });
  EXPECT_HAS(whole, "top.fraction_int");
  EXPECT_HAS(whole, "whole number");
  EXPECT_HAS(config_error([&] { top().integer("text_number", 0, 10); }), "top.text_number");
  // Does not fit a long: must be refused, not wrapped around.
  EXPECT_HAS(config_error([&] { top().integer("huge", 0, 1000000); }), "top.huge");

  const std::string b = config_error([&] { top().boolean("not_a_bool"); });
  EXPECT_HAS(b, "top.not_a_bool");
  EXPECT_HAS(b, "maybe");
  EXPECT_HAS(config_error([&] { top().boolean("count"); }), "top.count");

  EXPECT_HAS(config_error([&] { top().text("list"); }), "top.list");
  EXPECT_HAS(config_error([&] { top().text("nested"); }), "top.nested");
}

TEST_F(SectionTest, NonFiniteNumbersAreRefused) {
  EXPECT_HAS(config_error([&] { top().number("nan_value"); }), "top.nan_value");
  EXPECT_HAS(config_error([&] { top().number("inf_value"); }), "top.inf_value");
  EXPECT_HAS(config_error([&] { top().positive("inf_value"); }), "top.inf_value");
}

TEST_F(SectionTest, SignChecks) {
  EXPECT_HAS(config_error([&] { top().positive("zero"); }), "top.zero");
  EXPECT_HAS(config_error([&] { top().positive("negative"); }), "top.negative");
  const std::string msg = config_error([&] { top().non_negative("negative"); });
  EXPECT_HAS(msg, "top.negative");
  EXPECT_HAS(msg, ">= 0");
}

TEST_F(SectionTest, IntegerRangeBoundaries) {
  EXPECT_EQ(top().integer("count", 7, 7), 7);
  const std::string above = config_error([&] { top().integer("count", 1, 6); });
  EXPECT_HAS(above, "top.count");
  EXPECT_HAS(above, "1..6");
  EXPECT_HAS(above, "got 7");
  const std::string below = config_error([&] { top().integer("count", 8, 100); });
  EXPECT_HAS(below, "8..100");
  EXPECT_HAS(below, "got 7");
  // Negative literal below a non-negative range.
  const std::string p = write_yaml("neg_int.yaml", "s:\n  n: -3\n");
  EXPECT_HAS(config_error([&] { Section::load_file(p).child("s").integer("n", 0, 10); }), "s.n");
}

TEST_F(SectionTest, OneOfListsTheAllowedValues) {
  const std::string msg = config_error([&] { top().one_of("name", {"fixed", "automatic"}); });
  EXPECT_HAS(msg, "top.name");
  EXPECT_HAS(msg, "fixed, automatic");
  EXPECT_HAS(msg, "'rms'");
  // Matching is exact (no case folding): "RMS" is not "rms".
  const std::string p = write_yaml("case.yaml", "s:\n  mode: RMS\n");
  EXPECT_HAS(config_error([&] { Section::load_file(p).child("s").one_of("mode", {"rms"}); }), "s.mode");
}

TEST_F(SectionTest, OnlyRejectsUnknownKeys) {
  const Section other = Section::load_file(path_).child("other");
  EXPECT_NO_THROW(other.only({"a"}));
  EXPECT_NO_THROW(other.only({"a", "b"}));  // known but absent keys are fine
  const std::string msg = config_error([&] { other.only({"b", "c"}); });
  EXPECT_HAS(msg, path_);
  EXPECT_HAS(msg, "other.a");
  EXPECT_HAS(msg, "unknown key");
  EXPECT_HAS(msg, "b, c");
  // At the top level the path is just the key.
  const std::string root = config_error([&] { Section::load_file(path_).only({"top"}); });
  EXPECT_HAS(root, path_ + ": other: unknown key");
}

TEST_F(SectionTest, FailFormatsFileAndPath) {
  const std::string msg = config_error([&] { top().child("nested").fail("k", "custom problem"); });
  EXPECT_EQ(msg, path_ + ": top.nested.k: custom problem");
}

TEST(SectionLoad, MissingFile) {
  const std::string p = (std::filesystem::path(::testing::TempDir()) / "no_such_dir_xyz" / "absent.yaml").string();
  const std::string msg = config_error([&] { Section::load_file(p); });
  EXPECT_HAS(msg, p);
  EXPECT_HAS(msg, "cannot open");
}

TEST(SectionLoad, InvalidYaml) {
  const std::string p = write_yaml("broken.yaml", "a: [1, 2\nb: {\n");
  const std::string msg = config_error([&] { Section::load_file(p); });
  EXPECT_HAS(msg, p);
  EXPECT_HAS(msg, "invalid YAML");
}

TEST(SectionLoad, TopLevelMustBeAMap) {
  const std::string p = write_yaml("list.yaml", "- 1\n- 2\n");
  const std::string msg = config_error([&] { Section::load_file(p); });
  EXPECT_HAS(msg, p);
  EXPECT_HAS(msg, "map");
  const std::string e = write_yaml("empty.yaml", "");
  EXPECT_HAS(config_error([&] { Section::load_file(e); }), e);
}

}  // namespace
