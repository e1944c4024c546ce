// Two-point spaces: the levels each point's space is built as, the force of each point
// against direct solves with both points held, and the file that holds them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>
#include <unistd.h>
#include <vector>

#include "core/error.hpp"
#include "precompute/builder.hpp"
#include "precompute/pair.hpp"
#include "precompute/space_file.hpp"
#include "test_body.hpp"

namespace tactus::precompute {
namespace {

std::int32_t node_at(const physics::Body& body, const Vec3& at) {
  const VecX& rest = body.model->rest_positions();
  for (Eigen::Index n = 0; n < rest.size() / 3; ++n)
    if (rest.segment<3>(3 * n).isApprox(at, 1e-9)) return static_cast<std::int32_t>(n);
  return -1;
}

/// Two points on the block's top 20 mm apart, each with a 3 mm grid over 3 mm either way and
/// 6 mm down: 27 points each.
SpaceSettings pair_settings(const physics::Body& body) {
  SpaceSettings s = testing::block_settings(body);
  s.contact_node = node_at(body, Vec3(-0.01, 0.0, 0.01));
  s.patch_nodes = {s.contact_node};
  s.bounds_min = Vec3(-0.013, -0.003, 0.004);
  s.bounds_max = Vec3(-0.007, 0.003, 0.0101);
  s.pair.node = node_at(body, Vec3(0.01, 0.0, 0.01));
  s.pair.patch_nodes = {s.pair.node};
  s.pair.bounds_min = Vec3(0.007, -0.003, 0.004);
  s.pair.bounds_max = Vec3(0.013, 0.003, 0.0101);
  return s;
}

Space build_pair_level(const physics::Body& body, const SpaceSettings& s) {
  Space space = make_space(body, s, "");
  BuildOptions o;
  o.threads = 2;
  (void)build_local(space, [&] { return std::make_unique<ConfigurationSolver>(body, s); }, o);
  return space;
}

std::vector<Space> build_pair_levels(const physics::Body& body, const SpaceSettings& s) {
  std::vector<Space> levels;
  for (const SpaceSettings& level : space_levels(s, body.model->rest_positions()))
    levels.push_back(build_pair_level(body, level));
  return levels;
}

std::vector<std::shared_ptr<const Space>> shared_pair_levels(const std::vector<Space>& levels) {
  std::vector<std::shared_ptr<const Space>> out;
  for (const auto& l : levels) out.push_back(std::make_shared<const Space>(l));
  return out;
}

TEST(PairSpace, LevelsHoldEachPointFreeThenTheOtherAtEachOfItsGridPoints) {
  const physics::Body body = testing::block_body();
  const SpaceSettings s = pair_settings(body);
  ASSERT_GE(s.contact_node, 0);
  ASSERT_GE(s.pair.node, 0);
  const VecX& rest = body.model->rest_positions();
  const std::vector<SpaceSettings> levels = space_levels(s, rest);
  const Grid a = pair_grid(s, 0, rest), b = pair_grid(s, 1, rest);
  ASSERT_EQ(a.size(), 27u);
  ASSERT_EQ(b.size(), 27u);
  ASSERT_EQ(levels.size(), 2 + a.size() + b.size());
  // The two points' own spaces, the other free.
  EXPECT_EQ(levels[0].contact_node, s.contact_node);
  EXPECT_EQ(levels[0].finger, 0);
  EXPECT_EQ(levels[1].contact_node, s.pair.node);
  EXPECT_EQ(levels[1].pair.node, s.contact_node);
  EXPECT_EQ(levels[1].bounds_min, s.pair.bounds_min);
  EXPECT_EQ(levels[1].finger, 1);
  EXPECT_LT(levels[0].held_node, 0);
  EXPECT_LT(levels[1].held_node, 0);
  // Then the first point's with the second held at each of its grid points, and the reverse.
  for (std::size_t j = 0; j < b.size(); ++j) {
    const SpaceSettings& l = levels[2 + j];
    EXPECT_EQ(l.finger, 0);
    EXPECT_EQ(l.held_node, s.pair.node);
    EXPECT_EQ(l.held_at, b.point(j));
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    const SpaceSettings& l = levels[2 + b.size() + i];
    EXPECT_EQ(l.finger, 1);
    EXPECT_EQ(l.contact_node, s.pair.node);
    EXPECT_EQ(l.held_node, s.contact_node);
    EXPECT_EQ(l.held_at, a.point(i));
  }
}

/// Mean and largest error of `predict` (the force on point `finger`) against direct solves
/// with both points held, walked straight from rest, at random places of the two boxes,
/// relative to the largest force of the sample (the accuracy study's measure).
template <class Predict>
std::pair<double, double> pair_errors_against_direct(const physics::Body& body, const SpaceSettings& s,
                                                     Predict predict, int samples) {
  const VecX& rest = body.model->rest_positions();
  const std::array<Grid, 2> grids{pair_grid(s, 0, rest), pair_grid(s, 1, rest)};
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto draw = [&](const Grid& g) {
    return Vec3(g.lower() + (g.upper() - g.lower()).cwiseProduct(Vec3(u(rng), u(rng), u(rng))));
  };
  std::vector<Vec3> truth, guess;
  for (int i = 0; i < samples; ++i) {
    const std::array<Vec3, 2> at{draw(grids[0]), draw(grids[1])};
    for (int finger = 0; finger < 2; ++finger) {
      SpaceSettings held = pair_point(s, finger);
      held.held_node = held.pair.node;
      held.held_patch = held.pair.patch_nodes;
      held.held_at = at[static_cast<std::size_t>(1 - finger)];
      ConfigurationSolver solver(body, held);
      const PointResult r = solver.solve_direct(at[static_cast<std::size_t>(finger)], 4);
      EXPECT_EQ(r.status, PointStatus::solved) << r.reason;
      truth.push_back(r.force);
      guess.push_back(predict(finger, at[static_cast<std::size_t>(finger)], at[static_cast<std::size_t>(1 - finger)]));
    }
  }
  return testing::relative_errors(truth, guess);
}

TEST(PairSpace, EachPointsForceFollowsDirectSolvesWithBothPointsHeld) {
  const physics::Body body = testing::block_body();
  const SpaceSettings s = pair_settings(body);
  const std::vector<Space> levels = build_pair_levels(body, s);
  for (std::size_t k = 0; k < levels.size(); ++k)
    ASSERT_EQ(levels[k].count(PointStatus::solved), levels[k].grid.size()) << "level " << k;
  const PairInterpolator pair(shared_pair_levels(levels), Interpolation::tricubic_hermite);

  // With both points at grid points, each point's force is its own level's configuration.
  const Grid& a = pair.grid(0);
  const Grid& b = pair.grid(1);
  for (std::size_t j : {std::size_t{0}, std::size_t{13}, std::size_t{26}})
    for (std::size_t i = 0; i < a.size(); ++i) {
      const Vec3 pa = a.point(i), pb = b.point(j);
      const Query q = pair.force(0, pa, &pb);
      ASSERT_TRUE(q.valid);
      EXPECT_LT((q.force - levels[2 + j].force[i]).norm(), 1e-12 * (1.0 + q.force.norm()));
      const Query r = pair.force(1, pb, &pa);
      EXPECT_LT((r.force - levels[2 + b.size() + i].force[j]).norm(), 1e-12 * (1.0 + r.force.norm()));
    }
  // The other point out of its box, or unknown: it is free, and the point's own space answers.
  const Vec3 away(0.0, 0.0, 0.05), pa = a.point(5);
  EXPECT_EQ(pair.force(0, pa, &away).force, pair.level(0).force(pa).force);
  EXPECT_EQ(pair.force(0, pa, nullptr).force, pair.level(0).force(pa).force);

  const auto [mean, worst] = pair_errors_against_direct(
      body, s, [&](int f, const Vec3& p, const Vec3& other) { return pair.force(f, p, &other).force; }, 20);
  // The same positions with the other point ignored (each point's space alone).
  const auto [mean_alone, worst_alone] = pair_errors_against_direct(
      body, s,
      [&](int f, const Vec3& p, const Vec3&) { return pair.level(static_cast<std::size_t>(f)).force(p).force; }, 20);
  std::printf("two-point space: mean %.3f %%, max %.3f %%; each point alone: mean %.3f %%, max %.3f %%\n", 100 * mean,
              100 * worst, 100 * mean_alone, 100 * worst_alone);
  EXPECT_LT(mean, 0.005);
  EXPECT_LT(worst, 0.05);
  EXPECT_LT(mean, 0.1 * mean_alone);
}

TEST(PairSpace, ALevelWithoutAValueHandsItsWeightToTheLevelsAroundIt) {
  const physics::Body body = testing::block_body();
  const SpaceSettings s = pair_settings(body);
  std::vector<Space> levels = build_pair_levels(body, s);
  const PairInterpolator whole(shared_pair_levels(levels), Interpolation::trilinear);
  // The first point's level with the second at B's grid point (1, 1, 1) (the centre) fails
  // everywhere: around it the force is trilinear over the seven corners left, renormalized.
  const Grid& b = whole.grid(1);
  const std::size_t centre = b.index(1, 1, 1);
  for (auto& status : levels[2 + centre].status) status = PointStatus::failed;
  const PairInterpolator holed(shared_pair_levels(levels), Interpolation::trilinear);
  const Vec3 pa = whole.grid(0).point(4), pb = b.point(1, 1, 1) + Vec3(0.0004, 0.0011, 0.0007);
  const Query q = holed.force(0, pa, &pb);
  ASSERT_TRUE(q.valid);
  EXPECT_TRUE(q.across_levels);
  EXPECT_FALSE(q.fallback);  // no level fell back within itself (trilinear levels cannot)
  EXPECT_FALSE(whole.force(0, pa, &pb).across_levels);
  Vec3 expected = Vec3::Zero();
  double kept = 0.0;
  const Vec3 t = (pb - b.point(1, 1, 1)) / b.spacing;
  for (int corner = 1; corner < 8; ++corner) {  // corner 0 is the failed centre
    const int i = corner & 1, j = (corner >> 1) & 1, k = corner >> 2;
    const double w = (i ? t.x() : 1 - t.x()) * (j ? t.y() : 1 - t.y()) * (k ? t.z() : 1 - t.z());
    expected += w * levels[2 + b.index(1 + i, 1 + j, 1 + k)].force[4];
    kept += w;
  }
  EXPECT_LT((q.force - expected / kept).norm(), 1e-12 * expected.norm());
}

TEST(PairSpace, ALevelWithoutAValueAtAnEndIsLeftOutByAStencilLinearAlongItsAxis) {
  const physics::Body body = testing::block_body();
  const SpaceSettings s = pair_settings(body);
  std::vector<Space> levels = build_pair_levels(body, s);
  // The first point's level with the second at B's grid point (0, 1, 1) fails everywhere.
  // The second sits in B's cell between x-levels 1 and 2, so a stencil linear along x
  // (levels 1 and 2) and quadratic along y and z (levels 0, 1, 2) leaves the failed one out.
  const Grid b = PairInterpolator(shared_pair_levels(levels), Interpolation::trilinear).grid(1);
  for (auto& status : levels[2 + b.index(0, 1, 1)].status) status = PointStatus::failed;
  const PairInterpolator holed(shared_pair_levels(levels), Interpolation::trilinear);
  const Vec3 pa = holed.grid(0).point(4), pb = b.point(1, 1, 1) + Vec3(0.0004, 0.0011, -0.0007);
  const Query q = holed.force(0, pa, &pb);
  ASSERT_TRUE(q.valid);
  EXPECT_TRUE(q.levels_lowered);
  EXPECT_FALSE(q.across_levels);
  const Vec3 t = (pb - b.point(1, 1, 1)) / b.spacing;
  auto quadratic = [](double x, int m) {
    return m == 0 ? 0.5 * x * (x - 1.0) : m == 1 ? 1.0 - x * x : 0.5 * x * (x + 1.0);
  };
  Vec3 expected = Vec3::Zero();
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) {
        const double w = (i ? t.x() : 1.0 - t.x()) * quadratic(t.y(), j) * quadratic(t.z(), k);
        expected += w * levels[2 + b.index(1 + i, j, k)].force[4];
      }
  EXPECT_LT((q.force - expected).norm(), 1e-12 * expected.norm());
  // With the centre failed instead, every lowered stencil holds it: trilinear across levels.
  for (auto& status : levels[2 + b.index(1, 1, 1)].status) status = PointStatus::failed;
  const Query centre = PairInterpolator(shared_pair_levels(levels), Interpolation::trilinear).force(0, pa, &pb);
  EXPECT_TRUE(centre.across_levels);
  EXPECT_FALSE(centre.levels_lowered);
}

TEST(PairSpace, AFileHoldsEveryLevelAndRefusesOnesThatDoNotBelong) {
  const physics::Body body = testing::block_body();
  const SpaceSettings s = pair_settings(body);
  const std::vector<Space> levels = build_pair_levels(body, s);
  const auto path = std::filesystem::temp_directory_path() / ("tactus_pair_" + std::to_string(::getpid()) + ".h5");
  write_space_levels(path, levels);
  const std::vector<Space> read = read_space_levels(path);
  ASSERT_EQ(read.size(), levels.size());
  for (std::size_t k = 0; k < levels.size(); ++k) {
    EXPECT_EQ(read[k].identity.model_hash, levels[k].identity.model_hash) << k;
    EXPECT_EQ(read[k].settings.finger, levels[k].settings.finger) << k;
    EXPECT_EQ(read[k].settings.pair.node, levels[k].settings.pair.node) << k;
    EXPECT_EQ(read[k].settings.pair.patch_nodes, levels[k].settings.pair.patch_nodes) << k;
    EXPECT_EQ(read[k].settings.pair.bounds_max, levels[k].settings.pair.bounds_max) << k;
    EXPECT_EQ(read[k].settings.held_node, levels[k].settings.held_node) << k;
    EXPECT_EQ(read[k].settings.held_at, levels[k].settings.held_at) << k;
    EXPECT_EQ(read[k].force, levels[k].force) << k;
  }
  // The levels' model hashes differ: no level passes for another.
  EXPECT_NE(levels[2].identity.model_hash, levels[3].identity.model_hash);
  EXPECT_NE(levels[0].identity.model_hash, levels[1].identity.model_hash);
  const PairInterpolator pair(shared_pair_levels(read), Interpolation::tricubic_hermite);
  const Vec3 pa(-0.0098, 0.0012, 0.0061), pb(0.0111, -0.0007, 0.0083);
  EXPECT_EQ(pair.force(0, pa, &pb).force,
            PairInterpolator(shared_pair_levels(levels), Interpolation::tricubic_hermite).force(0, pa, &pb).force);

  // A file without its last level is refused by name; so are levels out of order.
  std::vector<Space> short_of_one(levels.begin(), levels.end() - 1);
  write_space_levels(path, short_of_one);
  try {
    (void)read_space_levels(path);
    ADD_FAILURE() << "a file without its last level was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("level 55 of 56 is missing"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
  std::vector<std::shared_ptr<const Space>> swapped = shared_pair_levels(levels);
  std::swap(swapped[3], swapped[4]);
  try {
    (void)PairInterpolator(swapped, Interpolation::trilinear);
    ADD_FAILURE() << "levels out of order were taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("level 3 of the two-point space does not belong to it (its held point"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW((void)PairInterpolator(shared_pair_levels(short_of_one), Interpolation::trilinear), InputError);
}

TEST(PairSpace, AHeldPatchMovesRigidlyWithItsNode) {
  // The second point with its four neighbours on the top (10 mm away) as its patch, held
  // 3 mm down and 2 mm aside: every node of the patch keeps its place relative to the node.
  const physics::Body body = testing::block_body();
  SpaceSettings s = pair_point(pair_settings(body), 0);
  const VecX& rest = body.model->rest_positions();
  s.held_node = s.pair.node;
  const Vec3 centre = rest.segment<3>(3 * s.held_node);
  for (Eigen::Index n = 0; n < rest.size() / 3; ++n)
    if ((rest.segment<3>(3 * n) - centre).norm() < 0.0101 && rest(3 * n + 2) > 0.0099)
      s.held_patch.push_back(static_cast<std::int32_t>(n));
  ASSERT_EQ(s.held_patch.size(), 5u);  // the node and its four neighbours
  s.held_at = centre + Vec3(0.002, 0.0, -0.003);
  const Space space = build_pair_level(body, s);
  ASSERT_EQ(space.count(PointStatus::solved), space.grid.size());
  for (std::size_t p = 0; p < space.grid.size(); ++p)
    for (auto n : s.held_patch) {
      const Vec3 moved = space.displacement.col(static_cast<Eigen::Index>(p)).segment<3>(3 * n);
      EXPECT_LT((moved - Vec3(0.002, 0.0, -0.003)).norm(), 1e-12) << p << " " << n;
    }
  // A patch that does not hold its node is refused.
  SpaceSettings bad = s;
  bad.held_patch.erase(std::find(bad.held_patch.begin(), bad.held_patch.end(), s.held_node));
  EXPECT_THROW((void)ConfigurationSolver(body, bad), InputError);
}

}  // namespace
}  // namespace tactus::precompute
