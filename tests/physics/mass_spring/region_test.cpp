// Restriction of the dynamics to a region around a contact (seed 000 §3.3).
#include <gtest/gtest.h>

#include <set>

#include "ms_test_util.hpp"
#include "physics/mass_spring/region.hpp"
#include "physics/mass_spring/tet_builder.hpp"

namespace tactus::physics {
namespace {

using test::nodes_at;

TEST(Region, NodesOutsideRadiusAreExactlyTheFarOnes) {
  // Nodes on a line at x = 0, 1, ..., 9 (metres); centre 4.2, radius 2: nodes 3..6 are inside
  // (distances 1.2, 0.2, 0.8, 1.8); the boundary case (distance exactly 2) stays inside.
  VecX x = VecX::Zero(30);
  for (int i = 0; i < 10; ++i) x[3 * i] = i;
  EXPECT_EQ(nodes_outside_radius(x, Vec3(4.2, 0, 0), 2.0), (std::vector<std::int32_t>{0, 1, 2, 7, 8, 9}));
  EXPECT_EQ(nodes_outside_radius(x, Vec3(4, 0, 0), 2.0), (std::vector<std::int32_t>{0, 1, 7, 8, 9}));
  EXPECT_TRUE(nodes_outside_radius(x, Vec3(4, 0, 0), 100.0).empty());
  EXPECT_THROW(nodes_outside_radius(x, Vec3::Zero(), -1.0), InputError);
}

struct Scenario {
  Body full;
  std::shared_ptr<const SpringNetwork> net;
  Vec3 contact{0.0, 0.0, 0.025};
};

Scenario scenario() {
  TetSpringParams p;
  p.youngs_modulus = 5e3;
  p.damping_per_mass = 20.0;
  p.viscoelastic = ViscoelasticParams::standard_linear_solid(1.0, 1.0, 0.2);
  Scenario s;
  auto net = tet_mass_spring(mesh::box_volume(Vec3(0.05, 0.05, 0.05), 5, 5, 5), p);
  s.net = net;
  s.full.model = net;
  s.full.fix_nodes(nodes_at(net->rest_positions(), 2, -0.025));
  return s;
}

TEST(Region, RestrictedBodyFixesFarNodesAndKeepsMovingSprings) {
  Scenario su = scenario();
  const VecX& x = su.net->rest_positions();
  const double radius = 0.02;
  const Body r = restrict_to_region(su.full, *su.net, x, su.contact, radius);
  const auto far = nodes_outside_radius(x, su.contact, radius);
  std::set<std::int32_t> fixed(far.begin(), far.end());
  for (auto n : nodes_at(x, 2, -0.025)) fixed.insert(n);
  ASSERT_EQ(r.fixed_node_count(), fixed.size());
  for (std::int32_t n = 0; n < static_cast<std::int32_t>(su.net->node_count()); ++n)
    EXPECT_EQ(r.fixed_dofs[3 * static_cast<std::size_t>(n)] != 0, fixed.count(n) == 1) << n;
  const auto& springs = static_cast<const SpringNetwork&>(*r.model).springs();
  std::size_t moving = 0;
  for (const auto& s : su.net->springs()) moving += !(fixed.count(s.i) && fixed.count(s.j));
  EXPECT_EQ(springs.size(), moving);
  EXPECT_LT(springs.size(), su.net->springs().size() / 2);
  EXPECT_EQ(r.model->internal_size(), su.net->internal_size());
}

TEST(Region, RestrictedModelStepsLikeTheFullOneWithTheSameNodesFixed) {
  // Springs between two fixed nodes exert no force on a free node, so dropping them changes
  // nothing the integrator sees: the two runs agree to round-off (1e-12 of the motion).
  Scenario su = scenario();
  const VecX& x0 = su.net->rest_positions();
  su.full.settings.cg_tolerance = 1e-13;
  const Body restricted = restrict_to_region(su.full, *su.net, x0, su.contact, 0.02);
  Body same_fixed = su.full;
  same_fixed.fixed_dofs = restricted.fixed_dofs;
  BodyState a = make_state(restricted), b = make_state(same_fixed);
  VecX f = VecX::Zero(x0.size());
  const auto top = nodes_at(x0, 2, 0.025);
  for (auto n : top)
    if ((x0.segment<3>(3 * n) - su.contact).norm() < 0.012) f[3 * n + 2] = -0.01;
  for (int i = 0; i < 50; ++i) {
    step(restricted, a, 1e-3, f);
    step(same_fixed, b, 1e-3, f);
  }
  const double motion = (b.x - x0).cwiseAbs().maxCoeff();
  ASSERT_GT(motion, 1e-5);
  EXPECT_LT((a.x - b.x).cwiseAbs().maxCoeff(), 1e-9 * motion);
}

TEST(Region, RegionFollowsAMovingContact) {
  Scenario su = scenario();
  const VecX& x0 = su.net->rest_positions();
  Body r = restrict_to_region(su.full, *su.net, x0, Vec3(-0.015, 0.005, 0.025), 0.015);
  BodyState s = make_state(r);
  VecX f = VecX::Zero(x0.size());
  for (int i = 0; i < 10; ++i) step(r, s, 1e-3, f);
  // Move the contact to the other side: nodes there must become free and move under a push.
  const Vec3 there(0.015, 0.005, 0.025);
  r = restrict_to_region(su.full, *su.net, s.x, there, 0.015);
  rebind_state(r, s);
  std::int32_t pushed = -1;
  for (auto n : nodes_at(x0, 2, 0.025))
    if ((x0.segment<3>(3 * n) - there).norm() < 1e-9) pushed = n;
  ASSERT_GE(pushed, 0);
  f[3 * pushed + 2] = -0.01;
  for (int i = 0; i < 10; ++i) step(r, s, 1e-3, f);
  EXPECT_LT(s.x[3 * pushed + 2], x0[3 * pushed + 2]);
  EXPECT_TRUE(s.x.allFinite());
}

}  // namespace
}  // namespace tactus::physics
