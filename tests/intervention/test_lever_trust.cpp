// Lever trust (T1): a miss in the first check keeps the claim, two misses withdraw it, hits restore it.
#include "causal/intervention/lever_trust.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

using causal::intervention::LeverTrust;
using causal::intervention::LeverTrustParams;

TEST(LeverTrust, OutcomesThatMissWithdrawTheClaim) {
  LeverTrust t;
  EXPECT_DOUBLE_EQ(t.trust("g", 1, 0), 2.0 / 3.0);
  EXPECT_TRUE(t.claimed("g", 1, 0));
  t.record("g", 1, 0, false, true);
  EXPECT_DOUBLE_EQ(t.trust("g", 1, 0), 2.0 / 4.0);
  EXPECT_TRUE(t.claimed("g", 1, 0));
  t.record("g", 1, 0, false, false);
  EXPECT_DOUBLE_EQ(t.trust("g", 1, 0), 2.0 / 5.0);
  EXPECT_FALSE(t.claimed("g", 1, 0));
  EXPECT_TRUE(t.claimed("g", 2, 0)) << "another lever keeps its own record";
  EXPECT_TRUE(t.claimed("h", 1, 0)) << "another group too";
  t.record("g", 1, 0, true, true);
  EXPECT_DOUBLE_EQ(t.trust("g", 1, 0), 3.0 / 6.0);
  EXPECT_TRUE(t.claimed("g", 1, 0));
  EXPECT_EQ(t.record_of("g", 1, 0).checks, 3u);
  EXPECT_EQ(t.record_of("g", 1, 0).improved, 2u);
}

TEST(LeverTrust, RejectsInconsistentPriors) {
  EXPECT_THROW(LeverTrust(LeverTrustParams{4.0, 3.0, 0.5}), std::invalid_argument);
  EXPECT_THROW(LeverTrust(LeverTrustParams{1.0, 0.0, 0.5}), std::invalid_argument);
  EXPECT_THROW(LeverTrust(LeverTrustParams{1.0, 2.0, 1.5}), std::invalid_argument);
}
