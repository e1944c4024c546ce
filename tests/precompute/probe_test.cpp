// Probe spaces: the lean's geometry, levels built as point spaces with the patch turned, and
// the force between leans against direct solves of the leaning probe.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <random>
#include <unistd.h>
#include <vector>

#include "core/error.hpp"
#include "precompute/builder.hpp"
#include "precompute/probe.hpp"
#include "precompute/space_file.hpp"
#include "test_body.hpp"

namespace tactus::precompute {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

/// The block's settings with a patch of the contact node and its four neighbours (10 mm
/// away) as the end of a probe pointing down, leaning up to 12 degrees either way.
SpaceSettings probe_settings(const physics::Body& body, int levels = 3) {
  SpaceSettings s = testing::block_settings(body);
  const VecX& rest = body.model->rest_positions();
  const Vec3 contact = rest.segment<3>(3 * s.contact_node);
  s.patch_radius = 0.011;
  s.patch_nodes.clear();
  for (Eigen::Index n = 0; n < rest.size() / 3; ++n)
    if ((rest.segment<3>(3 * n) - contact).norm() <= s.patch_radius) s.patch_nodes.push_back(static_cast<int>(n));
  s.probe.axis = Vec3(0.0, 0.0, -1.0);
  s.probe.max_tilt = 12.0 * kDegree;
  s.probe.tilt_levels = levels;
  return s;
}

Space build(const physics::Body& body, const SpaceSettings& s) {
  Space space = make_space(body, s, "");
  const auto stats = build_local(space, [&] { return std::make_unique<ConfigurationSolver>(body, s); }, {});
  // Every point solved once, and once more for each failed transition tried again from
  // another neighbour.
  EXPECT_EQ(stats.computed, space.grid.size() + stats.retried);
  return space;
}

std::vector<Space> build_levels(const physics::Body& body, const SpaceSettings& s) {
  std::vector<Space> levels;
  for (std::size_t k = 0; k < s.probe.level_count(); ++k) levels.push_back(build(body, level_settings(s, k)));
  return levels;
}

std::vector<std::shared_ptr<const Space>> shared(std::vector<Space> levels) {
  std::vector<std::shared_ptr<const Space>> out;
  for (auto& l : levels) out.push_back(std::make_shared<const Space>(std::move(l)));
  return out;
}

TEST(ProbeFrame, ALeanAndItsDirectionMapBothWays) {
  for (const Vec3& axis : {Vec3(0, 0, -1), Vec3(1, 2, -3), Vec3(0.3, -1, 0.1)}) {
    const ProbeFrame f(axis);
    EXPECT_NEAR(f.e1.dot(f.axis), 0.0, 1e-15);
    EXPECT_NEAR(f.e2.dot(f.axis), 0.0, 1e-15);
    EXPECT_NEAR(f.e1.cross(f.e2).dot(f.axis), 1.0, 1e-15);
    EXPECT_TRUE(f.tilt(f.axis).isZero(1e-15));
    for (const Vec2& t : {Vec2(0.3, 0.0), Vec2(-0.2, 0.5), Vec2(0.0, -1.2), Vec2(1.0, 1.0)}) {
      const Vec3 d = f.direction(t);
      EXPECT_NEAR(d.norm(), 1.0, 1e-15);
      EXPECT_NEAR(std::acos(std::clamp(d.dot(f.axis), -1.0, 1.0)), t.norm(), 1e-12);
      EXPECT_LT((f.tilt(3.0 * d) - t).norm(), 1e-12) << t.transpose();
      // The rotation vector turns the axis to the direction.
      const Vec3 w = f.rotation(t);
      EXPECT_LT((Eigen::AngleAxisd(w.norm(), w.normalized()) * f.axis - d).norm(), 1e-12);
    }
  }
  EXPECT_THROW((void)ProbeFrame(Vec3::Zero()), InputError);
}

TEST(ProbeSpace, LevelsLieOnALatticeOfLeansAroundTheUprightOne) {
  ProbeSettings p;
  p.axis = Vec3(0, 0, -1);
  p.max_tilt = 0.3;
  p.tilt_levels = 5;
  ASSERT_EQ(p.level_count(), 25u);
  EXPECT_LT((level_tilt(p, 0) - Vec2(-0.3, -0.3)).norm(), 1e-15);
  EXPECT_LT((level_tilt(p, 12) - Vec2(0.0, 0.0)).norm(), 1e-15);
  EXPECT_LT((level_tilt(p, 13) - Vec2(0.15, 0.0)).norm(), 1e-15);
  EXPECT_LT((level_tilt(p, 24) - Vec2(0.3, 0.3)).norm(), 1e-15);
}

TEST(ProbeSpace, TheUprightLevelIsThePointSpaceOfTheSamePatch) {
  const physics::Body body = testing::block_body();
  SpaceSettings probe = probe_settings(body);
  SpaceSettings point = probe;
  point.probe = {};
  const Space upright = build(body, level_settings(probe, 4));
  const Space plain = build(body, point);
  ASSERT_TRUE(level_settings(probe, 4).tilt.isZero(0.0));
  for (std::size_t p = 0; p < plain.grid.size(); ++p) EXPECT_EQ(upright.force[p], plain.force[p]) << p;
  EXPECT_TRUE(upright.displacement == plain.displacement);
  // The levels are different models: a point space's file does not pass for a level's.
  EXPECT_NE(upright.identity.model_hash, plain.identity.model_hash);
}

TEST(ProbeSpace, ALeaningLevelHoldsItsPatchTurnedAboutTheContactNode) {
  const physics::Body body = testing::block_body();
  const SpaceSettings s = level_settings(probe_settings(body), 5);  // leaning (+12°, 0)
  const Space space = build(body, s);
  EXPECT_EQ(space.count(PointStatus::solved), space.grid.size());
  for (std::size_t p = 0; p < space.grid.size(); ++p)
    if (!space.solved(p)) ADD_FAILURE() << p << ": " << space.reason[p] << " at " << space.grid.point(p).transpose();
  const ProbeFrame frame(s.probe.axis);
  const Vec3 w = frame.rotation(s.tilt);
  const Mat3 turn = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  const VecX& rest = body.model->rest_positions();
  const Vec3 contact = rest.segment<3>(3 * s.contact_node);
  for (std::size_t p = 0; p < space.grid.size(); ++p)
    for (auto n : s.patch_nodes) {
      const Vec3 x = rest.segment<3>(3 * n) + space.displacement.col(static_cast<Eigen::Index>(p)).segment<3>(3 * n);
      EXPECT_LT((x - (space.grid.point(p) + turn * (rest.segment<3>(3 * n) - contact))).norm(), 1e-12)
          << "point " << p << " node " << n << " status " << int(space.status[p]);
    }
  // Leaning in place bends the block: at the start point the patch is turned but not moved,
  // and the block resists with a force (not zero, as it is upright).
  EXPECT_GT(space.force[space.start].norm(), 1e-3);
}

/// Mean and largest relative error of `predict` against direct solves at random positions
/// in the grid's box and random leans within the space's, relative to the largest force
/// of the sample (the accuracy study's measure, validation.md); of the torque with `torque`.
template <class Predict>
std::pair<double, double> errors_against_direct(const physics::Body& body, const SpaceSettings& s, Predict predict,
                                                int samples, bool torque = false) {
  ConfigurationSolver solver(body, level_settings(s, 0));
  const ProbeFrame frame(s.probe.axis);
  const Space layout = make_space(body, s, "");
  const Vec3 lo = layout.grid.origin;
  const Vec3 hi = lo + layout.grid.spacing * Vec3(layout.grid.counts[0] - 1, layout.grid.counts[1] - 1,
                                                  layout.grid.counts[2] - 1);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> truth, guess;
  for (int i = 0; i < samples; ++i) {
    const Vec3 p = lo + (hi - lo).cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    const Vec2 t = s.probe.max_tilt * Vec2(2.0 * u(rng) - 1.0, 2.0 * u(rng) - 1.0);
    const PointResult r = solver.solve_direct(p, frame.rotation(t), 4);
    EXPECT_EQ(r.status, PointStatus::solved) << r.reason;
    truth.push_back(torque ? r.torque : r.force);
    guess.push_back(predict(p, frame.direction(t)));
  }
  return testing::relative_errors(truth, guess);
}

TEST(ProbeSpace, BetweenLeansTheForceFollowsDirectSolvesOfTheLeaningProbe) {
  const physics::Body body = testing::block_body();
  const SpaceSettings s = probe_settings(body);
  const ProbeInterpolator probe(shared(build_levels(body, s)), Interpolation::tricubic_hermite);
  ASSERT_EQ(probe.level_count(), 9u);

  // At a level's lean and a grid point, the level's own configuration.
  const Space& level5 = probe.level(5).space();
  for (std::size_t p = 0; p < level5.grid.size(); ++p) {
    const Query q = probe.force(level5.grid.point(p), probe.frame().direction(level5.settings.tilt));
    ASSERT_TRUE(q.valid);
    EXPECT_LT((q.force - level5.force[p]).norm(), 1e-12 * (1.0 + level5.force[p].norm()));
  }

  const auto [mean, worst] = errors_against_direct(
      body, s, [&](const Vec3& p, const Vec3& d) { return probe.force(p, d).force; }, 40);
  // The same positions with the lean ignored (the upright level alone): what the levels buy.
  const auto [mean_upright, worst_upright] = errors_against_direct(
      body, s, [&](const Vec3& p, const Vec3&) { return probe.level(4).force(p).force; }, 40);
  std::printf("probe space: mean %.3f %%, max %.3f %%; upright level alone: mean %.3f %%, max %.3f %%\n",
              100 * mean, 100 * worst, 100 * mean_upright, 100 * worst_upright);
  EXPECT_LT(mean, 0.005);
  EXPECT_LT(worst, 0.05);
  EXPECT_LT(mean, 0.1 * mean_upright);

  // The torque about the probe's end: exact at a level's grid points, and between them and
  // between the leans against the same direct solves' torques.
  for (std::size_t p = 0; p < level5.grid.size(); ++p) {
    const Query q = probe.force_and_torque(level5.grid.point(p), probe.frame().direction(level5.settings.tilt));
    ASSERT_TRUE(q.valid);
    EXPECT_LT((q.force - level5.force[p]).norm(), 1e-12 * (1.0 + level5.force[p].norm()));
    EXPECT_LT((q.torque - level5.torque[p]).norm(), 1e-12 * (1.0 + level5.torque[p].norm()));
  }
  const auto [torque_mean, torque_worst] = errors_against_direct(
      body, s, [&](const Vec3& p, const Vec3& d) { return probe.force_and_torque(p, d).torque; }, 40, true);
  const auto [torque_mean_upright, torque_worst_upright] = errors_against_direct(
      body, s, [&](const Vec3& p, const Vec3&) { return probe.level(4).force_and_torque(p).torque; }, 40, true);
  std::printf("torque: mean %.3f %%, max %.3f %%; upright level alone: mean %.3f %%, max %.3f %%\n",
              100 * torque_mean, 100 * torque_worst, 100 * torque_mean_upright, 100 * torque_worst_upright);
  EXPECT_LT(torque_mean, 0.005);
  EXPECT_LT(torque_worst, 0.05);
  EXPECT_LT(torque_mean, 0.1 * torque_mean_upright);
}

TEST(ProbeSpace, TheTorqueOnTheProbeBalancesTheMomentOfTheSupports) {
  // A static body is in moment balance: the probe's torque about its end and the moments of
  // the held base's reactions about the same point cancel, as the forces do. The reactions
  // are summed here from the model's nodal forces on the solved shape, a path the solver's
  // torque does not take; what is left is the free nodes' out-of-balance, below 1e-9.
  const physics::Body body = testing::block_body();
  const SpaceSettings s = level_settings(probe_settings(body), 5);  // leaning (+12°, 0)
  ConfigurationSolver solver(body, s);
  const PointResult r = solver.solve_direct(solver.contact_rest() + Vec3(0.002, -0.001, -0.004), 6);
  ASSERT_EQ(r.status, PointStatus::solved) << r.reason;
  const VecX x = body.model->rest_positions() + r.displacement;
  physics::BodyState state = physics::make_state(body);
  VecX f = VecX::Zero(x.size());
  body.model->forces(x, state.v, state.q, f, *state.model_scratch);
  const Vec3 end = x.segment<3>(3 * s.contact_node);
  Vec3 support_force = Vec3::Zero(), support_moment = Vec3::Zero();
  for (Eigen::Index n = 0; n < x.size() / 3; ++n)
    if (body.fixed_dofs[static_cast<std::size_t>(3 * n)]) {
      support_force += f.segment<3>(3 * n);
      support_moment += (x.segment<3>(3 * n) - end).cross(Vec3(f.segment<3>(3 * n)));
    }
  EXPECT_GT(r.torque.norm(), 1e-4);  // the leaning probe bends the block: N·m, not round-off
  EXPECT_LT((r.force + support_force).norm(), 1e-9 * (1.0 + r.force.norm()));
  EXPECT_LT((r.torque + support_moment).norm(), 1e-9 * (1.0 + r.torque.norm())) << r.torque.transpose() << " / "
                                                                                  << support_moment.transpose();
}

TEST(ProbeSpace, TheTorquesDerivativeMatchesCentralDifferences) {
  // As Build.DerivativesMatchCentralDifferencesOfSolvedConfigurations does for the force:
  // configurations solved 20 µm either side along each axis, to 1e-5 of the slope.
  const physics::Body body = testing::block_body();
  SpaceSettings s = level_settings(probe_settings(body), 5);
  s.tolerance = 1e-12;
  ConfigurationSolver solver(body, s);
  const Vec3 at = solver.contact_rest() + Vec3(0.002, -0.001, -0.004);
  const PointResult centre = solver.solve_direct(at, 8);
  ASSERT_EQ(centre.status, PointStatus::solved) << centre.reason;
  constexpr double kStep = 2e-5;
  Mat3 slope;
  const auto either_side = testing::solved_either_side(solver, centre, at, kStep);
  for (int k = 0; k < 3; ++k) {
    const auto& [plus, minus] = either_side[static_cast<std::size_t>(k)];
    ASSERT_EQ(plus.status, PointStatus::solved) << plus.reason;
    ASSERT_EQ(minus.status, PointStatus::solved) << minus.reason;
    slope.col(k) = (plus.torque - minus.torque) / (2 * kStep);
  }
  EXPECT_GT(slope.norm(), 1e-3);
  EXPECT_LT((centre.torque_gradient - slope).norm(), 1e-5 * slope.norm()) << centre.torque_gradient << "\n" << slope;
}

TEST(ProbeSpace, AFileHoldsEveryLevel) {
  const physics::Body body = testing::block_body();
  const SpaceSettings s = probe_settings(body);
  const std::vector<Space> levels = build_levels(body, s);
  const auto path = std::filesystem::temp_directory_path() / ("tactus_probe_" + std::to_string(::getpid()) + ".h5");
  write_space_levels(path, levels);
  const std::vector<Space> read = read_space_levels(path);
  std::filesystem::remove(path);
  ASSERT_EQ(read.size(), levels.size());
  for (std::size_t k = 0; k < levels.size(); ++k) {
    EXPECT_EQ(read[k].identity.model_hash, levels[k].identity.model_hash);
    EXPECT_EQ(read[k].settings.tilt, levels[k].settings.tilt);
    EXPECT_EQ(read[k].settings.probe.axis, s.probe.axis);
    EXPECT_EQ(read[k].settings.probe.max_tilt, s.probe.max_tilt);
    EXPECT_TRUE(read[k].displacement == levels[k].displacement);
    EXPECT_EQ(read[k].force, levels[k].force);
    EXPECT_EQ(read[k].torque, levels[k].torque);
    EXPECT_EQ(read[k].torque_gradient, levels[k].torque_gradient);
  }
  // Levels out of order, or missing, do not make a probe space.
  std::vector<Space> swapped = read;
  std::swap(swapped[1], swapped[2]);
  EXPECT_THROW((void)ProbeInterpolator(shared(std::move(swapped)), Interpolation::trilinear), InputError);
  std::vector<Space> missing = read;
  missing.pop_back();
  EXPECT_THROW((void)ProbeInterpolator(shared(std::move(missing)), Interpolation::trilinear), InputError);
}

}  // namespace
}  // namespace tactus::precompute
