// SvarLayout: factor order and names (COMMON_RULES naming), masks, invalid specs.
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "causal/estimation/svar_layout.hpp"

namespace causal {
namespace {

using Names = std::vector<std::string>;

TEST(SvarLayout, FourChannelsLagOneNamesAndOrder) {
  estimation::ModelSpec spec;  // G = 4, M = 1
  estimation::SvarLayout layout(spec);
  const Names expected = {"x12",  "x13",  "x14",  "xL12", "xL13", "xL14", "x21",  "x23",
                          "x24",  "xL21", "xL23", "xL24", "x31",  "x32",  "x34",  "xL31",
                          "xL32", "xL34", "x41",  "x42",  "x43",  "xL41", "xL42", "xL43"};
  EXPECT_EQ(layout.factor_names(), expected);
  EXPECT_EQ(layout.total_factors(), 24);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(layout.factor_count(k), 6);
    EXPECT_EQ(layout.offset(k), 6 * k);
  }
  // Outcome 2 (k = 1): instantaneous y1, y3, y4 then lag-1 y1, y3, y4.
  const auto& regs = layout.regressors(1);
  ASSERT_EQ(regs.size(), 6u);
  EXPECT_EQ(regs[0].channel, 0);
  EXPECT_EQ(regs[0].lag, 0);
  EXPECT_EQ(regs[2].channel, 3);
  EXPECT_EQ(regs[3].channel, 0);
  EXPECT_EQ(regs[3].lag, 1);
  EXPECT_EQ(layout.factor_index(1, 2, 1), 4);  // xL23
  EXPECT_EQ(layout.factor_index(1, 1, 1), -1);  // no self lag
}

TEST(SvarLayout, ThreeChannelsLagTwoNames) {
  estimation::ModelSpec spec;
  spec.channels = 3;
  spec.lag_order = 2;
  estimation::SvarLayout layout(spec);
  const Names expected = {"x12", "x13", "xL12", "xL13", "xL212", "xL213",
                          "x21", "x23", "xL21", "xL23", "xL221", "xL223",
                          "x31", "x32", "xL31", "xL32", "xL231", "xL232"};
  EXPECT_EQ(layout.factor_names(), expected);
}

TEST(SvarLayout, SelfLagsAreInJOrderWithinEachLag) {
  estimation::ModelSpec spec;
  spec.channels = 3;
  spec.lag_order = 2;
  spec.include_self_lags = true;
  estimation::SvarLayout layout(spec);
  const Names expected = {"x21", "x23", "xL21", "xL22", "xL23", "xL221", "xL222", "xL223"};
  Names got;
  for (int i = 0; i < layout.factor_count(1); ++i) got.push_back(layout.factor_name(1, i));
  EXPECT_EQ(got, expected);
  EXPECT_EQ(layout.total_factors(), 3 * 8);
}

TEST(SvarLayout, TwelveChannelsUseUnderscores) {
  estimation::ModelSpec spec;
  spec.channels = 12;
  spec.lag_order = 2;
  estimation::SvarLayout layout(spec);
  EXPECT_EQ(layout.factor_count(0), 11 * 3);
  EXPECT_EQ(layout.factor_name(0, 0), "x1_2");
  EXPECT_EQ(layout.factor_name(0, 10), "x1_12");
  EXPECT_EQ(layout.factor_name(0, 11), "xL1_2");
  EXPECT_EQ(layout.factor_name(0, 22), "xL2_1_2");
  EXPECT_EQ(layout.factor_name(9, 1), "x10_2");
  EXPECT_EQ(layout.factor_name(9, layout.factor_index(9, 1, 1)), "xL10_2");
  EXPECT_EQ(layout.factor_name(9, layout.factor_index(9, 1, 2)), "xL2_10_2");
  EXPECT_EQ(layout.factor_name(11, layout.factor_index(11, 10, 0)), "x12_11");
  const Names names = layout.factor_names();
  EXPECT_EQ(names.size(), static_cast<std::size_t>(12 * 33));
  EXPECT_EQ(names.back(), "xL2_12_11");
}

TEST(SvarLayout, AllowedMaskRemovesAllLinksOfAPair) {
  estimation::ModelSpec spec;  // G = 4, M = 1
  spec.allowed.assign(4, std::vector<bool>(4, true));
  spec.allowed[0][2] = false;  // no 3 -> 1: x13, xL13 absent
  spec.allowed[3][0] = false;  // no 1 -> 4: x41, xL41 absent
  spec.allowed[1][1] = false;  // diagonal ignored
  estimation::SvarLayout layout(spec);
  EXPECT_EQ(layout.total_factors(), 20);
  const Names names = layout.factor_names();
  for (const char* absent : {"x13", "xL13", "x41", "xL41"}) {
    EXPECT_EQ(std::count(names.begin(), names.end(), absent), 0) << absent;
  }
  const Names first = {"x12", "x14", "xL12", "xL14"};
  EXPECT_EQ(Names(names.begin(), names.begin() + 4), first);
  EXPECT_EQ(layout.offset(1), 4);
  EXPECT_EQ(layout.factor_index(0, 2, 0), -1);
}

TEST(SvarLayout, InstantaneousMaskOnlyRemovesInstantaneousLinks) {
  estimation::ModelSpec spec;
  spec.channels = 3;
  // Causal order 1 -> 2 -> 3 for instantaneous links (lower triangular), lags unrestricted.
  spec.instantaneous_allowed = {{false, false, false}, {true, false, false}, {true, true, false}};
  estimation::SvarLayout layout(spec);
  const Names expected = {"xL12", "xL13", "x21", "xL21", "xL23", "x31", "x32", "xL31", "xL32"};
  EXPECT_EQ(layout.factor_names(), expected);
  // Both masks: instantaneous link needs both.
  spec.allowed = {{true, true, true}, {true, true, true}, {false, true, true}};
  estimation::SvarLayout both(spec);
  const Names expected_both = {"xL12", "xL13", "x21", "xL21", "xL23", "x32", "xL32"};
  EXPECT_EQ(both.factor_names(), expected_both);
}

TEST(SvarLayout, FullyMaskedOutcomeHasNoFactors) {
  estimation::ModelSpec spec;
  spec.channels = 2;
  spec.allowed = {{true, false}, {true, true}};
  estimation::SvarLayout layout(spec);
  EXPECT_EQ(layout.factor_count(0), 0);
  EXPECT_EQ(layout.factor_count(1), 2);
  EXPECT_EQ(layout.offset(1), 0);
}

void expect_invalid(const estimation::ModelSpec& spec, const std::string& fragment) {
  try {
    estimation::SvarLayout layout(spec);
    ADD_FAILURE() << "expected std::invalid_argument containing '" << fragment << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(SvarLayout, InvalidSpecsThrowClearMessages) {
  estimation::ModelSpec spec;
  spec.channels = 1;
  expect_invalid(spec, "channels must be >= 2 (got 1)");
  spec = estimation::ModelSpec{};
  spec.lag_order = 0;
  expect_invalid(spec, "lag_order must be >= 1 (got 0)");
  spec = estimation::ModelSpec{};
  spec.allowed.assign(3, std::vector<bool>(4, true));
  expect_invalid(spec, "allowed must be empty or 4 x 4");
  spec = estimation::ModelSpec{};
  spec.instantaneous_allowed.assign(4, std::vector<bool>(4, true));
  spec.instantaneous_allowed[2].pop_back();
  expect_invalid(spec, "instantaneous_allowed row 2 has 3 entries");
  spec = estimation::ModelSpec{};
  spec.channels = 2;
  spec.allowed = {{true, false}, {false, true}};
  expect_invalid(spec, "no state");
}

}  // namespace
}  // namespace causal
