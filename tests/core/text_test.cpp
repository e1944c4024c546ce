#include "core/text.hpp"

#include <gtest/gtest.h>

namespace tactus::text {

TEST(Text, ParsesWholeTokensOnly) {
  EXPECT_EQ(to_double("1.5e-3"), 1.5e-3);
  EXPECT_EQ(to_double("+2"), 2.0);
  EXPECT_EQ(to_double("-0.25"), -0.25);
  EXPECT_FALSE(to_double("1.5x"));
  EXPECT_FALSE(to_double(""));
  EXPECT_FALSE(to_double("abc"));
  EXPECT_EQ(to_int("42"), 42);
  EXPECT_EQ(to_int("-7"), -7);
  EXPECT_FALSE(to_int("4.2"));
  EXPECT_FALSE(to_int("99999999999999999999999"));  // overflow is not a number
}

TEST(Text, SplitsOnBlanksAndDropsCarriageReturn) {
  const auto t = split("  v 1\t2  3\r");
  ASSERT_EQ(t.size(), 4u);
  EXPECT_EQ(t[0], "v");
  EXPECT_EQ(t[3], "3");
  EXPECT_TRUE(split("   ").empty());
  EXPECT_EQ(trim("  a b \r\n"), "a b");
}

TEST(Text, JsonQuotedEscapesQuotesBackslashesAndControlCharacters) {
  EXPECT_EQ(json_quoted("plain"), "\"plain\"");
  EXPECT_EQ(json_quoted("a\"b\\c"), "\"a\\\"b\\\\c\"");
  EXPECT_EQ(json_quoted(std::string("x\ny\x01", 4)), "\"x\\u000ay\\u0001\"");
}

}  // namespace tactus::text
