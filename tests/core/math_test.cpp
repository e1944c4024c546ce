#include "core/math.hpp"

#include <gtest/gtest.h>

namespace tactus {

TEST(Aabb, GrowsWithPointsAndStartsEmpty) {
  Aabb box;
  EXPECT_TRUE(box.empty());
  EXPECT_EQ(box.size(), Vec3::Zero());
  box.add(Vec3(1, 2, 3));
  box.add(Vec3(-1, 0, 5));
  EXPECT_FALSE(box.empty());
  EXPECT_EQ(box.size(), Vec3(2, 2, 2));
  EXPECT_EQ(box.center(), Vec3(0, 1, 4));
  EXPECT_TRUE(box.contains(Vec3(0, 1, 4)));
  EXPECT_FALSE(box.contains(Vec3(0, 3, 4)));
}

}  // namespace tactus
