// The accuracy study of docs/validation.md in small: spaces of the test block built by
// transitions, against configurations solved directly from rest at the same solver.
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "precompute/builder.hpp"
#include "precompute/configuration_solver.hpp"
#include "precompute/interpolator.hpp"
#include "test_body.hpp"

namespace tactus::precompute {
namespace {

/// A built space of the block over 4 mm in +x, +y and down from the contact node.
std::shared_ptr<Space> block_space(const physics::Body& body, double spacing) {
  SpaceSettings s = testing::block_settings(body);
  s.spacing = spacing;
  s.bounds_min = Vec3(-1e-7, -1e-7, 0.006 - 1e-7);
  s.bounds_max = Vec3(0.004 + 1e-7, 0.004 + 1e-7, 0.01 + 1e-7);
  auto space = std::make_shared<Space>(make_space(body, s, ""));
  BuildOptions options;
  options.threads = 1;
  build_local(*space, [&] { return std::make_unique<ConfigurationSolver>(body, s); }, options);
  return space;
}

TEST(Accuracy, GridPointsMatchDirectSolvesAndFinerGridsInterpolateBetter) {
  const physics::Body body = testing::block_body();
  const auto coarse = block_space(body, 0.004);  // 2 x 2 x 2 points
  const auto fine = block_space(body, 0.002);    // 3 x 3 x 3 points
  ASSERT_EQ(coarse->grid.size(), 8u);
  ASSERT_EQ(fine->grid.size(), 27u);
  ASSERT_EQ(coarse->count(PointStatus::solved), coarse->grid.size());
  ASSERT_EQ(fine->count(PointStatus::solved), fine->grid.size());
  ConfigurationSolver solver(body, fine->settings);

  // At grid points: the interpolation returns the stored configuration, and that equals
  // the configuration reached straight from rest. A hyperelastic body with a prescribed
  // patch has one equilibrium near rest whatever the path; both are converged to 1e-8 of
  // their load steps' forces, so they agree far inside 1e-5.
  const Interpolator exact(fine, Interpolation::trilinear);
  VecX shape;
  for (std::size_t p = 0; p < fine->grid.size(); ++p) {
    const Query q = exact.shape(fine->grid.point(p), shape);
    ASSERT_TRUE(q.valid);
    EXPECT_LT((q.force - fine->force[p]).norm(), 1e-12 * (1.0 + fine->force[p].norm())) << "point " << p;
    if (p == fine->start) continue;
    const PointResult direct = solver.solve_direct(fine->grid.point(p), 4);
    ASSERT_EQ(direct.status, PointStatus::solved) << direct.reason;
    EXPECT_LT((direct.force - fine->force[p]).norm(), 1e-5 * direct.force.norm()) << "point " << p;
    EXPECT_LT((direct.displacement - shape).norm(), 1e-5 * direct.displacement.norm()) << "point " << p;
  }

  // Between grid points: trilinear interpolation's error falls as the square of the
  // spacing, so halving it must lower the mean error (by about 4 x; asserting only
  // "lower" keeps the test about the trend, not the constant).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double coarse_error = 0.0, fine_error = 0.0;
  const Interpolator coarse_in(coarse, Interpolation::trilinear), fine_in(fine, Interpolation::trilinear);
  for (int i = 0; i < 12; ++i) {
    const Vec3 p = coarse->grid.lower() + 0.004 * Vec3(u(rng), u(rng), u(rng));
    const PointResult direct = solver.solve_direct(p, 4);
    ASSERT_EQ(direct.status, PointStatus::solved) << direct.reason;
    coarse_error += (coarse_in.force(p).force - direct.force).norm() / direct.force.norm();
    fine_error += (fine_in.force(p).force - direct.force).norm() / direct.force.norm();
  }
  EXPECT_GT(coarse_error, 0.0);
  EXPECT_LT(fine_error, coarse_error);
}

}  // namespace
}  // namespace tactus::precompute
