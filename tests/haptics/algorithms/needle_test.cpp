// Needle insertion through flat stacked layers: stages, rupture thresholds and order, shaft
// friction, retraction through the holes, the lateral spring, no allocation per frame.
#include "haptics/algorithms/needle.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/counting_allocator.hpp"

namespace tactus::haptics {
namespace {

constexpr double kFrame = 1e-3;  // [s]
const Vec3 kDown(0, 0, -1);

/// A horizontal slab between two heights, crossed by a vertical needle at x = y = 0.
struct Slab {
  double top = 0.0, bottom = 0.0;
};

NeedleLayer layer(std::size_t body, double rupture_force, double stiffness, double viscous = 0.0, double coulomb = 0.0) {
  NeedleLayer l;
  l.body = body;
  l.rupture_force = rupture_force;
  l.stiffness = stiffness;
  l.viscous_friction = viscous;
  l.coulomb_friction = coulomb;
  return l;
}

/// What the interaction loop would find for a vertical line through (x, y).
NeedleSurfaces crossings(const std::vector<Slab>& slabs, double x = 0.0, double y = 0.0) {
  NeedleSurfaces s;
  for (std::size_t i = 0; i < slabs.size(); ++i) {
    s.layers[i].entry_found = true;
    s.layers[i].entry = Vec3(x, y, slabs[i].top);
    s.layers[i].entry_triangle = static_cast<std::int32_t>(10 + i);
    s.layers[i].entry_barycentric = Vec3(0.2, 0.3, 0.5);
    s.layers[i].exit_found = true;
    s.layers[i].exit = Vec3(x, y, slabs[i].bottom);
  }
  return s;
}

/// Drives the tip straight down at `speed` from z0 for `frames` frames; returns every output.
struct Trace {
  std::vector<NeedleOutput> out;
  std::vector<double> z;
};
Trace drive(NeedleInsertion& needle, const NeedleSurfaces& s, double z0, double speed, int frames, double x = 0.0) {
  Trace r;
  for (int k = 0; k < frames; ++k) {
    const double z = z0 - speed * kFrame * k;
    r.z.push_back(z);
    r.out.push_back(needle.update(Vec3(x, 0, z), kDown, speed * kDown, s, k * kFrame));
  }
  return r;
}

TEST(NeedleInsertion, FreeAboveTheTissueThenASpringAtTheTouchPoint) {
  NeedleConfig c;
  c.layers = {layer(0, 2.0, 1000.0)};
  NeedleInsertion needle(c);
  const NeedleSurfaces s = crossings({{0.0, -0.01}});
  const NeedleOutput above = needle.update(Vec3(0, 0, 0.001), kDown, Vec3::Zero(), s, 0.0);
  EXPECT_FALSE(above.touching);
  EXPECT_EQ(above.force, Vec3::Zero());
  EXPECT_EQ(above.load_layer, -1);
  EXPECT_EQ(needle.stage(0), NeedleStage::untouched);

  const NeedleOutput in = needle.update(Vec3(0, 0, -0.0012), kDown, Vec3::Zero(), s, kFrame);
  EXPECT_TRUE(in.touching);
  EXPECT_EQ(needle.stage(0), NeedleStage::deforming);
  // Met 1.2 mm late: the spring starts engage_slack above the tip.
  EXPECT_NEAR(in.force.z(), 1000.0 * c.engage_slack, 1e-9);
  const NeedleOutput deeper = needle.update(Vec3(0, 0, -0.0017), kDown, Vec3::Zero(), s, 2 * kFrame);
  EXPECT_NEAR(deeper.force.z(), 1000.0 * (c.engage_slack + 0.0005), 1e-9);
  EXPECT_NEAR(deeper.force.head<2>().norm(), 0.0, 1e-12);
  // The tissue takes the reaction at the touch point of the layer.
  EXPECT_EQ(deeper.load_layer, 0);
  EXPECT_EQ(deeper.load_triangle, 10);
  EXPECT_EQ(deeper.load_barycentric, Vec3(0.2, 0.3, 0.5));
}

TEST(NeedleInsertion, RupturesAtTheThresholdAndTheForceDrops) {
  NeedleConfig c;
  c.layers = {layer(0, 2.0, 800.0, 100.0, 50.0)};
  NeedleInsertion needle(c);
  const double speed = 0.01;
  const Trace r = drive(needle, crossings({{0.0, -0.02}}), 0.001, speed, 600);
  int at = -1;
  for (std::size_t k = 0; k < r.out.size(); ++k)
    if (r.out[k].rupture) {
      EXPECT_EQ(at, -1) << "one rupture only";
      at = static_cast<int>(k);
    }
  ASSERT_GE(at, 1);
  const NeedleRupture& rupture = *r.out[static_cast<std::size_t>(at)].rupture;
  EXPECT_EQ(rupture.layer, 0u);
  // Within one frame's spring increment of the threshold.
  EXPECT_GE(rupture.force, 2.0);
  EXPECT_LE(rupture.force, 2.0 + 800.0 * speed * kFrame);
  EXPECT_NEAR(rupture.t, at * kFrame, 1e-12);
  EXPECT_NEAR(rupture.point.z(), 0.0, 1e-12);
  ASSERT_EQ(needle.ruptures().size(), 1u);
  // Loss of resistance: the force just before is the spring's, just after only friction.
  const double before = r.out[static_cast<std::size_t>(at) - 1].force.norm();
  const double after = r.out[static_cast<std::size_t>(at)].force.norm();
  EXPECT_GT(before, 1.9);
  EXPECT_LT(after, 0.5 * before);
  EXPECT_EQ(needle.stage(0), NeedleStage::ruptured);
}

TEST(NeedleInsertion, ShaftFrictionIsViscousPlusCoulombPerLengthInside) {
  NeedleConfig c;
  c.layers = {layer(0, 0.5, 1000.0, 120.0, 40.0)};
  c.stick_speed = 1e-4;
  NeedleInsertion needle(c);
  const NeedleSurfaces s = crossings({{0.0, -0.004}});
  const double speed = 0.005;
  drive(needle, s, 0.0005, speed, 300);  // through the spring stage
  ASSERT_EQ(needle.stage(0), NeedleStage::ruptured);
  const double puncture_z = needle.ruptures()[0].point.z();
  for (const double tip_z : {-0.002, -0.003, -0.006}) {
    const NeedleOutput o = needle.update(Vec3(0, 0, tip_z), kDown, speed * kDown, s, 1.0);
    const double inside = std::min(puncture_z - tip_z, puncture_z - (-0.004));
    const double expected = inside * (120.0 * speed + 40.0);
    EXPECT_NEAR(o.force.z(), expected, 1e-9) << "tip at " << tip_z;  // resists the insertion: up
    EXPECT_TRUE(o.touching);
    EXPECT_EQ(o.load_layer, 0);
  }
  // Pulling out: the friction turns to resist the withdrawal.
  const NeedleOutput out = needle.update(Vec3(0, 0, -0.003), kDown, -speed * kDown, s, 1.1);
  EXPECT_LT(out.force.z(), 0.0);
}

TEST(NeedleInsertion, LayersRuptureInTheOrderTheNeedleMeetsThem) {
  // Listed deepest first: the order comes from the geometry, not the list.
  NeedleConfig c;
  c.layers = {layer(2, 4.0, 1500.0, 50.0, 20.0), layer(1, 1.5, 1200.0, 80.0, 30.0), layer(0, 2.5, 1000.0, 100.0, 40.0)};
  NeedleInsertion needle(c);
  const NeedleSurfaces s = crossings({{-0.005, -0.03}, {-0.003, -0.005}, {0.0, -0.003}});
  const Trace r = drive(needle, s, 0.001, 0.005, 8000);
  ASSERT_EQ(needle.ruptures().size(), 3u);
  const std::size_t expected_order[] = {2, 1, 0};
  for (std::size_t k = 0; k < 3; ++k) {
    const NeedleRupture& rupture = needle.ruptures()[k];
    EXPECT_EQ(rupture.layer, expected_order[k]);
    const NeedleLayer& l = c.layers[rupture.layer];
    EXPECT_GE(rupture.force, l.rupture_force);
    EXPECT_LE(rupture.force, l.rupture_force + l.stiffness * 0.005 * kFrame);
    if (k > 0) {
      EXPECT_GT(rupture.t, needle.ruptures()[k - 1].t);
    }
  }
  for (const NeedleOutput& o : r.out) {
    EXPECT_TRUE(o.force.allFinite());
    EXPECT_LT(o.force.norm(), 6.0);
  }
}

TEST(NeedleInsertion, RetractionThroughTheHoleMeetsNoResistance) {
  NeedleConfig c;
  c.layers = {layer(0, 1.0, 1000.0, 100.0, 50.0)};
  NeedleInsertion needle(c);
  const NeedleSurfaces s = crossings({{0.0, -0.01}});
  drive(needle, s, 0.0005, 0.005, 1000);
  ASSERT_EQ(needle.stage(0), NeedleStage::ruptured);
  // Out of the tissue: nothing; back in: only friction, no spring (the hole remains).
  const NeedleOutput outside = needle.update(Vec3(0, 0, 0.0005), kDown, Vec3::Zero(), s, 2.0);
  EXPECT_FALSE(outside.touching);
  EXPECT_EQ(outside.force, Vec3::Zero());
  const NeedleOutput back_in = needle.update(Vec3(0, 0, -0.002), kDown, Vec3::Zero(), s, 2.1);
  EXPECT_EQ(needle.stage(0), NeedleStage::ruptured);
  EXPECT_EQ(back_in.spring_force, 0.0);
  EXPECT_NEAR(back_in.force.z(), 0.0, 1e-12);  // at rest: no viscous part, Coulomb smoothed to zero
  EXPECT_EQ(needle.ruptures().size(), 1u);
}

TEST(NeedleInsertion, PullingBackBeforeRuptureReleasesTheLayer) {
  NeedleConfig c;
  c.layers = {layer(0, 5.0, 1000.0)};
  NeedleInsertion needle(c);
  const NeedleSurfaces s = crossings({{0.0, -0.01}});
  needle.update(Vec3(0, 0, -0.0001), kDown, Vec3::Zero(), s, 0.0);
  EXPECT_EQ(needle.stage(0), NeedleStage::deforming);
  const NeedleOutput o = needle.update(Vec3(0, 0, 0.001), kDown, Vec3::Zero(), s, kFrame);
  EXPECT_EQ(needle.stage(0), NeedleStage::untouched);
  EXPECT_FALSE(o.touching);
  EXPECT_TRUE(needle.ruptures().empty());
}

TEST(NeedleInsertion, LateralSpringPullsTowardsThePuncturePathAndStiffensWithDepth) {
  NeedleConfig c;
  c.length = 0.05;
  c.lateral_stiffness = 400.0;
  c.layers = {layer(0, 0.5, 1000.0)};
  NeedleInsertion needle(c);
  const NeedleSurfaces s = crossings({{0.0, -0.04}});
  drive(needle, s, 0.0002, 0.005, 200);
  ASSERT_EQ(needle.stage(0), NeedleStage::ruptured);
  const double z0 = needle.ruptures()[0].point.z();
  const double offset = 0.002;
  const NeedleOutput shallow = needle.update(Vec3(offset, 0, z0 - 0.01), kDown, Vec3::Zero(), s, 1.0);
  const NeedleOutput deep = needle.update(Vec3(offset, 0, z0 - 0.03), kDown, Vec3::Zero(), s, 1.1);
  EXPECT_NEAR(shallow.force.x(), -400.0 * (0.01 / 0.05) * offset, 1e-12);
  EXPECT_NEAR(deep.force.x(), -400.0 * (0.03 / 0.05) * offset, 1e-12);
  EXPECT_NEAR(deep.lateral_deviation, offset, 1e-12);
  EXPECT_NEAR(needle.max_deviation(), offset, 1e-12);
  // The lateral part is reported apart (its reaction goes along the shaft into the tissue),
  // from the first puncture to the tip.
  EXPECT_NEAR(deep.lateral_force.x(), -400.0 * (0.03 / 0.05) * offset, 1e-12);
  EXPECT_NEAR(deep.lateral_force.z(), 0.0, 1e-12);
  EXPECT_TRUE(deep.shaft);
  EXPECT_NEAR((deep.shaft_from - needle.ruptures()[0].point).norm(), 0.0, 1e-12);
}

TEST(NeedleInsertion, DeviationIsMeasuredFromThePlannedPath) {
  NeedleConfig c;
  c.layers = {layer(0, 0.5, 1000.0)};
  c.planned = std::array<Vec3, 2>{Vec3(0.001, 0, 0.01), Vec3(0.001, 0, -0.05)};
  NeedleInsertion needle(c);
  drive(needle, crossings({{0.0, -0.04}}), 0.0002, 0.005, 400);
  ASSERT_EQ(needle.stage(0), NeedleStage::ruptured);
  EXPECT_NEAR(needle.max_deviation(), 0.001, 1e-12);
  EXPECT_NEAR(needle.last_deviation(), 0.001, 1e-12);
}

TEST(NeedleInsertion, NonFiniteInputGivesNoForce) {
  NeedleConfig c;
  c.layers = {layer(0, 1.0, 1000.0)};
  NeedleInsertion needle(c);
  const double nan = std::nan("");
  const NeedleOutput o = needle.update(Vec3(0, 0, nan), kDown, Vec3::Zero(), crossings({{0.0, -0.01}}), 0.0);
  EXPECT_EQ(o.force, Vec3::Zero());
  EXPECT_FALSE(o.touching);
}

TEST(NeedleInsertion, RejectsBadConfigurations) {
  NeedleConfig too_many;
  too_many.layers.assign(kMaxNeedleLayers + 1, layer(0, 1.0, 1000.0));
  EXPECT_THROW(NeedleInsertion{too_many}, std::invalid_argument);
  NeedleConfig soft;
  soft.layers = {layer(0, 1.0, 0.0)};
  EXPECT_THROW(NeedleInsertion{soft}, std::invalid_argument);
  NeedleConfig no_threshold;
  no_threshold.layers = {layer(0, -1.0, 1000.0)};
  EXPECT_THROW(NeedleInsertion{no_threshold}, std::invalid_argument);
  NeedleConfig point_path;
  point_path.planned = std::array<Vec3, 2>{Vec3::Zero(), Vec3::Zero()};
  EXPECT_THROW(NeedleInsertion{point_path}, std::invalid_argument);
}

TEST(NeedleInsertion, UpdateAllocatesNothing) {
  NeedleConfig c;
  c.layers = {layer(0, 1.0, 1000.0, 100.0, 50.0), layer(1, 2.0, 1000.0, 100.0, 50.0)};
  NeedleInsertion needle(c);
  const NeedleSurfaces s = crossings({{0.0, -0.003}, {-0.003, -0.02}});
  testing::AllocationCounter counter;
  for (int k = 0; k < 3000; ++k)
    (void)needle.update(Vec3(0, 0, 0.001 - 5e-6 * k), kDown, 0.005 * kDown, s, k * kFrame);
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_EQ(needle.ruptures().size(), 2u);
}

TEST(NeedleInsertion, ANewSiteTearsTheLayersAgainAndTheOldHoleDoesNot) {
  NeedleConfig c;
  c.layers = {layer(0, 1.0, 1000.0, 100.0, 50.0)};
  NeedleInsertion needle(c);
  const NeedleSurfaces s = crossings({{0.0, -0.01}});
  drive(needle, s, 0.0005, 0.005, 1000);
  ASSERT_EQ(needle.ruptures().size(), 1u);
  // Out of the hole and 2 mm aside (within new_site_distance): still the old site.
  needle.update(Vec3(0.002, 0, 0.0005), kDown, Vec3::Zero(), s, 2.0);
  EXPECT_EQ(needle.stage(0), NeedleStage::ruptured);
  // 5 mm aside, out of the tissue: a new site; pressing in again tears the layer again.
  needle.update(Vec3(0.005, 0, 0.0005), kDown, Vec3::Zero(), s, 2.1);
  EXPECT_EQ(needle.stage(0), NeedleStage::untouched);
  const NeedleSurfaces beside = crossings({{0.0, -0.01}}, 0.005);
  double t = 2.2;
  for (double z = 0.0005; z > -0.003 && needle.ruptures().size() < 2; z -= 1e-5, t += 1e-3)
    needle.update(Vec3(0.005, 0, z), kDown, Vec3(0, 0, -0.01), beside, t);
  ASSERT_EQ(needle.ruptures().size(), 2u);
  EXPECT_NEAR(needle.ruptures()[1].force, 1.0, 0.02);
}

}  // namespace
}  // namespace tactus::haptics
