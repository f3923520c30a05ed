// Factor-name parsing follows the naming convention of COMMON_RULES (1-based names, 0-based result).
#include <gtest/gtest.h>

#include "causal/alarms/factor_names.hpp"

using causal::alarms::FactorRef;
using causal::alarms::parse_factor_name;

namespace {
void expect_ref(const std::string& name, int g, int k, int j, int lag) {
  const FactorRef r = parse_factor_name(name, g);
  EXPECT_TRUE(r.valid()) << name;
  EXPECT_EQ(r.outcome, k) << name;
  EXPECT_EQ(r.regressor, j) << name;
  EXPECT_EQ(r.lag, lag) << name;
}
}  // namespace

TEST(FactorNames, SmallGroups) {
  expect_ref("x12", 4, 0, 1, 0);
  expect_ref("x43", 4, 3, 2, 0);
  expect_ref("xL12", 4, 0, 1, 1);
  expect_ref("xL234", 4, 2, 3, 2);
  expect_ref("xL321", 4, 1, 0, 3);
  expect_ref("xL11", 4, 0, 0, 1);  // self lag (ModelSpec::include_self_lags)
}

TEST(FactorNames, LargeGroupsUseUnderscore) {
  expect_ref("x10_2", 12, 9, 1, 0);
  expect_ref("xL10_2", 12, 9, 1, 1);
  expect_ref("xL210_2", 12, 9, 1, 2);
  expect_ref("x1_12", 12, 0, 11, 0);
  expect_ref("xL2_10_2", 12, 9, 1, 2);   // causal_core's spelling for lag >= 2
  expect_ref("xL3_1_12", 12, 0, 11, 3);
}

TEST(FactorNames, RejectsMalformed) {
  for (const char* bad : {"", "y12", "x11", "x15", "x1", "xL1", "x1_2", "xab", "xL0x"}) {
    EXPECT_FALSE(parse_factor_name(bad, 4).valid()) << bad;
  }
  EXPECT_FALSE(parse_factor_name("x12", 12).valid());  // G >= 10 needs the underscore
}
