#include "core/error.hpp"

#include <gtest/gtest.h>

namespace tactus {

TEST(SourceLocation, FormatsLineColumnAndByteOffset) {
  EXPECT_EQ((SourceLocation{"a.obj", 12, 3, {}}).str(), "a.obj:12:3");
  EXPECT_EQ((SourceLocation{"a.obj", 12, {}, {}}).str(), "a.obj:12");
  EXPECT_EQ((SourceLocation{"a.stl", {}, {}, 84}).str(), "a.stl: byte 84");
  EXPECT_EQ((SourceLocation{"", {}, {}, {}}).str(), "<input>");
}

TEST(InputError, MessageCarriesLocationAndReason) {
  const InputError e(SourceLocation{"mesh.off", 4, {}, {}}, "expected a number, got 'x'");
  EXPECT_STREQ(e.what(), "mesh.off:4: expected a number, got 'x'");
  EXPECT_EQ(e.reason(), "expected a number, got 'x'");
  EXPECT_EQ(e.where().line, 4u);
}

}  // namespace tactus
