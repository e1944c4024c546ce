// Seed 002 Table I: every input combination against the table as printed, all nine states
// reachable, the impossible "-" cells handled as documented.
#include "contact/grasp_state.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace tactus::contact {
namespace {

/// Table I, read off the seed: rows by fabric contacts (0, 1, 2), columns by fingers
/// touching and friction (no/static, no/dynamic, yes/static, yes/dynamic). "-" is empty.
const char* const kTable[3][4] = {
    {"I", "I", "II", "III"},
    {"IV", "V", "-", "-"},
    {"VI", "VII", "VIII", "IX"},
};

TEST(ContactStates, ClassifyFollowsTableI) {
  std::set<ContactState> seen;
  for (int bits = 0; bits < 16; ++bits) {
    ContactInputs in;
    in.thumb_on_fabric = (bits & 1) != 0;
    in.index_on_fabric = (bits & 2) != 0;
    in.fingers_touch = (bits & 4) != 0;
    in.dynamic_friction = (bits & 8) != 0;
    const int row = (in.thumb_on_fabric ? 1 : 0) + (in.index_on_fabric ? 1 : 0);
    const int column = (in.fingers_touch ? 2 : 0) + (in.dynamic_friction ? 1 : 0);
    const std::string expected = kTable[row][column];
    const ContactState s = classify(in);
    seen.insert(s);
    if (expected == "-") {
      // One contact point while the fingers touch: the fabric must be squeezed between
      // them, so the grasp's state, with the friction given.
      EXPECT_FALSE(is_possible(in));
      EXPECT_EQ(s, in.dynamic_friction ? ContactState::IX : ContactState::VIII);
    } else {
      EXPECT_TRUE(is_possible(in));
      EXPECT_EQ(std::string(name(s)), expected) << bits;
    }
  }
  EXPECT_EQ(seen.size(), 9u);
}

TEST(ContactStates, NamesAreTheSeedsNumerals) {
  const char* numerals[] = {"I", "II", "III", "IV", "V", "VI", "VII", "VIII", "IX"};
  for (int i = 1; i <= 9; ++i) {
    const auto s = static_cast<ContactState>(i);
    EXPECT_EQ(std::string(name(s)), numerals[i - 1]);
    EXPECT_FALSE(describe(s).empty());
  }
  EXPECT_EQ(std::string(name(static_cast<ContactState>(0))), "?");
}

}  // namespace
}  // namespace tactus::contact
