#include <gtest/gtest.h>

#include "core/error.hpp"
#include "precompute/builder.hpp"
#include "precompute/model_identity.hpp"
#include "test_body.hpp"

namespace tactus::precompute {
namespace {

Space build(const physics::Body& body, const SpaceSettings& s, unsigned threads) {
  Space space = make_space(body, s, "");
  BuildOptions o;
  o.threads = threads;
  const auto stats = build_local(space, [&] { return std::make_unique<ConfigurationSolver>(body, s); }, o);
  EXPECT_EQ(stats.computed + stats.unreachable, space.grid.size());
  return space;
}

TEST(Build, SolvesEveryPointOfASmallSpace) {
  const physics::Body body = testing::block_body();
  const SpaceSettings s = testing::block_settings(body);
  const Space space = build(body, s, 1);
  ASSERT_EQ(space.grid.size(), 36u);
  EXPECT_EQ(space.count(PointStatus::solved), space.grid.size());
  // The undeformed contact point: no force, no displacement.
  EXPECT_LT(space.force[space.start].norm(), 1e-12);
  EXPECT_LT(space.displacement.col(static_cast<Eigen::Index>(space.start)).norm(), 1e-15);
  // Pressed straight down, the block pushes back up; pulled up, it pulls down.
  const auto c = space.grid.cell(space.start);
  const Vec3 pressed = space.force[space.grid.index(c[0], c[1], c[2] - 2)];
  const Vec3 pressed_less = space.force[space.grid.index(c[0], c[1], c[2] - 1)];
  const Vec3 pulled = space.force[space.grid.index(c[0], c[1], c[2] + 1)];
  EXPECT_GT(pressed.z(), pressed_less.z());
  EXPECT_GT(pressed_less.z(), 0.0);
  EXPECT_LT(pulled.z(), 0.0);
  // The contact node sits at its grid point in every configuration.
  const VecX& rest = body.model->rest_positions();
  for (std::size_t p = 0; p < space.grid.size(); ++p) {
    const Vec3 x = rest.segment<3>(3 * s.contact_node) +
                   space.displacement.col(static_cast<Eigen::Index>(p)).segment<3>(3 * s.contact_node);
    EXPECT_LT((x - space.grid.point(p)).norm(), 1e-12);
    EXPECT_LE(space.residual[p], s.tolerance * 100);
  }
}

TEST(Build, ThreadCountDoesNotChangeTheSpace) {
  const physics::Body body = testing::block_body();
  const SpaceSettings s = testing::block_settings(body);
  const Space one = build(body, s, 1);
  const Space three = build(body, s, 3);
  EXPECT_EQ(one.status, three.status);
  EXPECT_EQ(one.source, three.source);
  for (std::size_t p = 0; p < one.grid.size(); ++p) EXPECT_EQ(one.force[p], three.force[p]) << "point " << p;
  EXPECT_TRUE(one.displacement == three.displacement);
}

TEST(Build, ASecondPointHeldStillStaysWhereItIsHeldInEveryConfiguration) {
  // A second finger: the top node 10 mm along +x held 2 mm down while the contact node
  // visits its grid. The held node keeps its place, its pull changes the contact's force, and
  // the equilibria are those of a direct solve with both held.
  const physics::Body body = testing::block_body();
  SpaceSettings s = testing::block_settings(body);
  const Space alone = build(body, s, 1);
  const VecX& rest = body.model->rest_positions();
  for (Eigen::Index n = 0; n < rest.size() / 3; ++n)
    if (rest.segment<3>(3 * n).isApprox(Vec3(0.01, 0, 0.01), 1e-9)) s.held_node = static_cast<std::int32_t>(n);
  ASSERT_GE(s.held_node, 0);
  s.held_at = Vec3(0.01, 0.0, 0.008);
  const Space held = build(body, s, 2);
  ASSERT_EQ(held.count(PointStatus::solved), held.grid.size());
  EXPECT_NE(held.identity.model_hash, alone.identity.model_hash);
  for (std::size_t p = 0; p < held.grid.size(); ++p) {
    const Vec3 x = rest.segment<3>(3 * s.held_node) +
                   held.displacement.col(static_cast<Eigen::Index>(p)).segment<3>(3 * s.held_node);
    EXPECT_LT((x - s.held_at).norm(), 1e-12) << p;
  }
  // At the start point the contact node is where it rests, and the other finger's press
  // pulls it down: the tool is pulled into the body.
  EXPECT_LT(held.force[held.start].z(), -1e-3);
  EXPECT_LT(alone.force[alone.start].norm(), 1e-12);
  ConfigurationSolver solver(body, s);
  const std::size_t p = held.grid.index(0, 2, 0);
  const PointResult direct = solver.solve_direct(held.grid.point(p), 6);
  ASSERT_EQ(direct.status, PointStatus::solved) << direct.reason;
  EXPECT_LT((direct.force - held.force[p]).norm(), 1e-5 * direct.force.norm());
  // A held node in the contact patch or outside the mesh is refused.
  SpaceSettings bad = s;
  bad.held_node = s.contact_node;
  EXPECT_THROW((void)ConfigurationSolver(body, bad), InputError);
  bad.held_node = 100000;
  EXPECT_THROW((void)ConfigurationSolver(body, bad), InputError);
}

TEST(Build, EquilibriumMatchesADirectSolve) {
  // A transition path and a straight path from rest reach the same equilibrium (an elastic,
  // path-independent law), up to the solver tolerance.
  const physics::Body body = testing::block_body();
  const SpaceSettings s = testing::block_settings(body);
  const Space space = build(body, s, 1);
  ConfigurationSolver solver(body, s);
  const std::size_t p = space.grid.index(0, 2, 0);  // a far corner: several transitions away
  const PointResult direct = solver.solve_direct(space.grid.point(p), 6);
  ASSERT_EQ(direct.status, PointStatus::solved) << direct.reason;
  EXPECT_LT((direct.force - space.force[p]).norm(), 1e-5 * direct.force.norm());
}

TEST(Build, DerivativesMatchCentralDifferencesOfSolvedConfigurations) {
  // The stored ∂force/∂x and ∂displacement/∂x against configurations solved 20 µm either side
  // of a pressed, sheared point along each axis. The difference's own error is O(δ²) (about
  // 1e-7 relative here) and the solves' balance 1e-10 relative: 1e-5 leaves room for both and
  // would still catch a wrong sign, a missing patch node or the projected tangent.
  const physics::Body body = testing::block_body();
  SpaceSettings s = testing::block_settings(body);
  s.tolerance = 1e-12;
  ConfigurationSolver solver(body, s);
  const Vec3 at = solver.contact_rest() + Vec3(0.002, -0.001, -0.004);
  const PointResult centre = solver.solve_direct(at, 8);
  ASSERT_EQ(centre.status, PointStatus::solved) << centre.reason;
  ASSERT_EQ(centre.displacement_gradient.cols(), 3);
  constexpr double kStep = 2e-5;
  Mat3 force_slope;
  MatX shape_slope(centre.displacement.size(), 3);
  const auto either_side = testing::solved_either_side(solver, centre, at, kStep);
  for (int k = 0; k < 3; ++k) {
    const auto& [plus, minus] = either_side[static_cast<std::size_t>(k)];
    ASSERT_EQ(plus.status, PointStatus::solved) << plus.reason;
    ASSERT_EQ(minus.status, PointStatus::solved) << minus.reason;
    force_slope.col(k) = (plus.force - minus.force) / (2 * kStep);
    shape_slope.col(k) = (plus.displacement - minus.displacement) / (2 * kStep);
  }
  EXPECT_LT((centre.force_gradient - force_slope).norm(), 1e-5 * force_slope.norm())
      << centre.force_gradient << "\n" << force_slope;
  EXPECT_LT((centre.displacement_gradient - shape_slope).norm(), 1e-5 * shape_slope.norm());
  // Pressing down (−z) the block pushes back harder: ∂F_z/∂z < 0, and the tangent is
  // symmetric (the reaction derives from the stored energy).
  EXPECT_LT(centre.force_gradient(2, 2), 0.0);
  EXPECT_LT((centre.force_gradient - centre.force_gradient.transpose()).norm(), 1e-8 * centre.force_gradient.norm());
}

TEST(Build, FailedSolvesAreRecordedWithTheirReason) {
  const physics::Body body = testing::block_body();
  SpaceSettings s = testing::block_settings(body);
  s.max_iterations = 1;  // no load step converges in one Newton iteration
  s.tolerance = 1e-14;
  const Space space = build(body, s, 1);
  // The start point needs no iteration; its neighbours fail, the rest is unreachable.
  EXPECT_EQ(space.status[space.start], PointStatus::solved);
  EXPECT_GT(space.count(PointStatus::failed), 0u);
  EXPECT_GT(space.count(PointStatus::unreachable), 0u);
  for (std::size_t p = 0; p < space.grid.size(); ++p)
    if (space.status[p] == PointStatus::failed) {
      EXPECT_NE(space.reason[p].find("load step"), std::string::npos);
    }
}

TEST(Build, AFailedLoadStepIsRefinedByHalving) {
  // Pressing 9 mm into the 20 mm block in one load step needs more Newton iterations than
  // allowed (5, against 3); halving the step gets there, to the equilibrium of a finely
  // stepped solve. (Deeper than its 10 mm elements, StVK's equilibrium turns the elements
  // under the node inside out, which every solve refuses.)
  const physics::Body body = testing::block_body(5.0e3, 0.45);
  SpaceSettings s = testing::block_settings(body);
  s.load_steps = 1;
  s.max_iterations = 3;
  s.max_step_halvings = 0;
  const Vec3 rest = ConfigurationSolver(body, s).contact_rest();
  const Vec3 target = rest - Vec3(0, 0, 0.009);
  const VecX zero = VecX::Zero(3 * static_cast<Eigen::Index>(body.model->node_count()));

  ConfigurationSolver unrefined(body, s);
  const PointResult failed = unrefined.transition(1, 0, zero, rest, target);
  EXPECT_EQ(failed.status, PointStatus::failed);
  EXPECT_EQ(failed.refinements, 0);
  EXPECT_NE(failed.reason.find("load step 1/1: no convergence"), std::string::npos) << failed.reason;

  s.max_step_halvings = 4;
  ConfigurationSolver refined(body, s);
  const PointResult solved = refined.transition(1, 0, zero, rest, target);
  ASSERT_EQ(solved.status, PointStatus::solved) << solved.reason;
  EXPECT_GT(solved.refinements, 0);

  SpaceSettings fine = s;
  fine.max_iterations = 100;
  const PointResult reference = ConfigurationSolver(body, fine).solve_direct(target, 16);
  ASSERT_EQ(reference.status, PointStatus::solved) << reference.reason;
  EXPECT_GT(reference.force.z(), 0.0);
  EXPECT_LT((solved.force - reference.force).norm(), 1e-5 * reference.force.norm());
  EXPECT_LT((solved.displacement - reference.displacement).norm(), 1e-5 * reference.displacement.norm());
}

TEST(Build, RefinementIsBoundedByTheHalvingLimit) {
  // One Newton iteration per step never converges: the point fails after exactly the allowed
  // number of halvings, and says so.
  const physics::Body body = testing::block_body();
  SpaceSettings s = testing::block_settings(body);
  s.load_steps = 2;
  s.max_iterations = 1;
  s.tolerance = 1e-14;
  s.max_step_halvings = 3;
  ConfigurationSolver solver(body, s);
  const Vec3 rest = solver.contact_rest();
  const PointResult r = solver.solve_direct(rest - Vec3(0, 0, 0.003), 2);
  EXPECT_EQ(r.status, PointStatus::failed);
  EXPECT_EQ(r.refinements, 3);
  EXPECT_NE(r.reason.find("after 3 halvings"), std::string::npos) << r.reason;
}

TEST(Build, PatchNodeInAFixedRegionIsAnInputError) {
  const physics::Body body = testing::block_body();
  SpaceSettings s = testing::block_settings(body);
  s.patch_nodes = {0};  // a base node
  s.contact_node = 0;
  EXPECT_THROW(ConfigurationSolver(body, s), InputError);
}

}  // namespace
}  // namespace tactus::precompute
