#include <gtest/gtest.h>

#include "core/error.hpp"
#include "precompute/grid.hpp"

namespace tactus::precompute {
namespace {

TEST(Grid, LatticeThroughTheAnchorCoversTheBox) {
  const Grid g = Grid::through(Vec3(0.01, 0.0, 0.0), Vec3(-0.02, -0.005, -0.001), Vec3(0.025, 0.005, 0.0), 0.01);
  EXPECT_EQ(g.counts[0], 5);  // -0.02 ... 0.02
  EXPECT_EQ(g.counts[1], 1);  // 0 only
  EXPECT_EQ(g.counts[2], 1);
  EXPECT_NEAR(g.origin.x(), -0.02, 1e-15);
  const std::size_t anchor = g.nearest(Vec3(0.0101, 0.0, 0.0));
  EXPECT_TRUE(g.point(anchor).isApprox(Vec3(0.01, 0.0, 0.0)));
  for (std::size_t p = 0; p < g.size(); ++p) {
    const auto c = g.cell(p);
    EXPECT_EQ(g.index(c[0], c[1], c[2]), p);
  }
}

TEST(Grid, RejectsBadInput) {
  EXPECT_THROW(Grid::through(Vec3::Zero(), Vec3::Constant(-1), Vec3::Constant(1), 0.0), InputError);
  EXPECT_THROW(Grid::through(Vec3::Constant(2), Vec3::Constant(-1), Vec3::Constant(1), 0.1), InputError);
  EXPECT_THROW(Grid::through(Vec3::Zero(), Vec3::Constant(-1), Vec3::Constant(1), 1e-3, 1000), InputError);
}

TEST(Grid, NearestClampsOutside) {
  const Grid g = Grid::through(Vec3::Zero(), Vec3::Constant(-0.01), Vec3::Constant(0.01), 0.01);
  EXPECT_EQ(g.nearest(Vec3(5, 5, 5)), g.size() - 1);
  EXPECT_EQ(g.nearest(Vec3(-5, -5, -5)), 0u);
}

}  // namespace
}  // namespace tactus::precompute
