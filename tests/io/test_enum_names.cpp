// io::enum_names: the one name table behind every enum's to_string and parse. The compile-time checks (a missing,
// doubled or stray name does not build) are the ctest cases io_enum_names_refuses_* (enum_names_refused.cpp).
#include "causal/io/enum_names.hpp"

#include <gtest/gtest.h>

#include <cstdint>

namespace {

enum class Colour { red, green, blue };
enum class Small : std::uint8_t { a, b };

constexpr auto kColourNames =
    causal::io::enum_names<Colour>({{Colour::red, "red"}, {Colour::green, "green"}, {Colour::blue, "blue"}});

TEST(EnumNames, NamesEveryEnumerator) {
  EXPECT_STREQ(kColourNames.name(Colour::red, "?"), "red");
  EXPECT_STREQ(kColourNames.name(Colour::green, "?"), "green");
  EXPECT_STREQ(kColourNames.name(Colour::blue, "?"), "blue");
}

TEST(EnumNames, AValueThatIsNoEnumeratorGetsTheOtherText) {
  EXPECT_STREQ(kColourNames.name(static_cast<Colour>(7), "unknown"), "unknown");
  EXPECT_STREQ(kColourNames.name(static_cast<Colour>(-1), "?"), "?");
}

TEST(EnumNames, ParseIsTheInverseAndExact) {
  EXPECT_EQ(kColourNames.parse("green"), Colour::green);
  EXPECT_EQ(kColourNames.parse("blue"), Colour::blue);
  EXPECT_FALSE(kColourNames.parse("Green").has_value());
  EXPECT_FALSE(kColourNames.parse("gree").has_value());
  EXPECT_FALSE(kColourNames.parse("").has_value());
}

TEST(EnumNames, TheListMayBeInAnyOrderAndTheEnumOfAnyWidth) {
  constexpr auto names = causal::io::enum_names<Small>({{Small::b, "b"}, {Small::a, "a"}});
  EXPECT_STREQ(names.name(Small::a, "?"), "a");
  EXPECT_STREQ(names.name(Small::b, "?"), "b");
  EXPECT_EQ(names.parse("a"), Small::a);
}

}  // namespace
