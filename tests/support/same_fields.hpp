// EXPECT_SAME_FIELDS(a, b, f1, f2, ...): EXPECT_EQ((a).f, (b).f) for every named member, in the order given,
// so that a test comparing two records field by field names each field once instead of writing one EXPECT_EQ per
// line (a failure prints both expressions, so it names the member). a and b may be of different types that share
// the member names (a DDS message and the report it was made from). Up to 16 members per call.
#pragma once

#include <gtest/gtest.h>

#define CAUSAL_SF_EQ(a, b, f) EXPECT_EQ((a).f, (b).f);
#define CAUSAL_SF_1(a, b, f) CAUSAL_SF_EQ(a, b, f)
#define CAUSAL_SF_2(a, b, f, ...) CAUSAL_SF_EQ(a, b, f) CAUSAL_SF_1(a, b, __VA_ARGS__)
#define CAUSAL_SF_3(a, b, f, ...) CAUSAL_SF_EQ(a, b, f) CAUSAL_SF_2(a, b, __VA_ARGS__)
#define CAUSAL_SF_4(a, b, f, ...) CAUSAL_SF_EQ(a, b, f) CAUSAL_SF_3(a, b, __VA_ARGS__)
#define CAUSAL_SF_5(a, b, f, ...) CAUSAL_SF_EQ(a, b, f) CAUSAL_SF_4(a, b, __VA_ARGS__)
#define CAUSAL_SF_6(a, b, f, ...) CAUSAL_SF_EQ(a, b, f) CAUSAL_SF_5(a, b, __VA_ARGS__)
#define CAUSAL_SF_7(a, b, f, ...) CAUSAL_SF_EQ(a, b, f) CAUSAL_SF_6(a, b, __VA_ARGS__)
#define CAUSAL_SF_8(a, b, f, ...) CAUSAL_SF_EQ(a, b, f) CAUSAL_SF_7(a, b, __VA_ARGS__)
#define CAUSAL_SF_9(a, b, f, ...) CAUSAL_SF_EQ(a, b, f) CAUSAL_SF_8(a, b, __VA_ARGS__)
#define CAUSAL_SF_10(a, b, f, ...) CAUSAL_SF_EQ(a, b, f) CAUSAL_SF_9(a, b, __VA_ARGS__)
#define CAUSAL_SF_11(a, b, f, ...) CAUSAL_SF_EQ(a, b, f) CAUSAL_SF_10(a, b, __VA_ARGS__)
#define CAUSAL_SF_12(a, b, f, ...) CAUSAL_SF_EQ(a, b, f) CAUSAL_SF_11(a, b, __VA_ARGS__)
#define CAUSAL_SF_13(a, b, f, ...) CAUSAL_SF_EQ(a, b, f) CAUSAL_SF_12(a, b, __VA_ARGS__)
#define CAUSAL_SF_14(a, b, f, ...) CAUSAL_SF_EQ(a, b, f) CAUSAL_SF_13(a, b, __VA_ARGS__)
#define CAUSAL_SF_15(a, b, f, ...) CAUSAL_SF_EQ(a, b, f) CAUSAL_SF_14(a, b, __VA_ARGS__)
#define CAUSAL_SF_16(a, b, f, ...) CAUSAL_SF_EQ(a, b, f) CAUSAL_SF_15(a, b, __VA_ARGS__)
#define CAUSAL_SF_PICK(_1, _2, _3, _4, _5, _6, _7, _8, _9, _10, _11, _12, _13, _14, _15, _16, n, ...) n
#define EXPECT_SAME_FIELDS(a, b, ...)                                                                                 \
  do {                                                                                                                \
    CAUSAL_SF_PICK(__VA_ARGS__, CAUSAL_SF_16, CAUSAL_SF_15, CAUSAL_SF_14, CAUSAL_SF_13, CAUSAL_SF_12, CAUSAL_SF_11,   \
                   CAUSAL_SF_10, CAUSAL_SF_9, CAUSAL_SF_8, CAUSAL_SF_7, CAUSAL_SF_6, CAUSAL_SF_5, CAUSAL_SF_4,        \
                   CAUSAL_SF_3, CAUSAL_SF_2, CAUSAL_SF_1)                                                             \
    (a, b, __VA_ARGS__)                                                                                               \
  } while (false)
