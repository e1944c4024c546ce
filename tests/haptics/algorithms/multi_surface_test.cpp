// The multiple-surface force algorithm against analytic layers: parallel planes (the force
// is the stiffness times the penetration of the outermost plane), a sphere the proxy slides
// over, the blend between planes at updates, disabled layers, no NaN, no allocation.
#include "haptics/algorithms/multi_surface.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "core/counting_allocator.hpp"

namespace tactus::haptics {
namespace {

constexpr double kFramePeriod = 1e-3;  // [s]
constexpr double kStiffness = 800.0;

MultiSurfaceForce make(std::size_t layers, double blend_time = 0.0, double damping = 0.0) {
  MultiSurfaceConfig c;
  c.stiffness = kStiffness;
  c.damping = damping;
  c.layers = layers;
  c.blend_time = blend_time;
  return MultiSurfaceForce(c);
}

/// Horizontal planes z = heights[i], outward +z: the hits of any downward ray.
SurfaceLayerHits flat_layers(std::initializer_list<double> heights, double x = 0.0, double y = 0.0) {
  SurfaceLayerHits h;
  std::size_t i = 0;
  for (const double z : heights) {
    h.layers[i].found = true;
    h.layers[i].point = Vec3(x, y, z);
    h.layers[i].normal = Vec3::UnitZ();
    h.layers[i].triangle = static_cast<std::int32_t>(i);
    ++i;
  }
  return h;
}

/// Where the ray origin + s · direction (s ≥ −back) first enters the sphere, if it does.
std::optional<SurfaceLayerHit> enter_sphere(const Vec3& origin, const Vec3& direction, const Vec3& centre, double radius) {
  const double back = 0.01;  // [m]: the ray starts behind the proxy, as the runtime's does
  const Vec3 o = origin - back * direction;
  const double b = direction.dot(o - centre), c = (o - centre).squaredNorm() - radius * radius;
  const double disc = b * b - c;
  if (disc < 0.0) return std::nullopt;
  const double s = -b - std::sqrt(disc);
  if (s < 0.0) return std::nullopt;
  SurfaceLayerHit h;
  h.found = true;
  h.point = o + s * direction;
  h.normal = (h.point - centre).normalized();
  return h;
}

TEST(MultiSurface, TwoParallelLayersForceIsStiffnessTimesOutermostPenetration) {
  MultiSurfaceForce ms = make(2);
  ms.set_hits(flat_layers({0.0, -0.005}), 0.0);
  // Above the skin: free. Between the layers and past both: the outer plane alone holds the
  // proxy, so F = k · (0 − z) along +z and the proxy is on the skin.
  EXPECT_FALSE(ms.update(Vec3(0, 0, 0.001), Vec3::Zero(), 0.0).touching);
  for (const double z : {-0.002, -0.0049, -0.008, -0.02}) {
    const MultiSurfaceOutput out = ms.update(Vec3(0.003, -0.001, z), Vec3::Zero(), 0.0);
    ASSERT_TRUE(out.touching) << z;
    EXPECT_EQ(out.layer, 0);
    EXPECT_NEAR(out.force.z(), kStiffness * -z, 1e-9) << z;
    EXPECT_NEAR(out.force.head<2>().norm(), 0.0, 1e-12);
    EXPECT_NEAR(out.proxy.z(), 0.0, 1e-12);
    EXPECT_NEAR(out.depth, -z, 1e-12);
    EXPECT_EQ(out.triangle, 0);
  }
  // The outer layer disabled (torn, or switched off): the inner plane takes over.
  ms.set_layer_enabled(0, false);
  const MultiSurfaceOutput inner = ms.update(Vec3(0, 0, -0.008), Vec3::Zero(), 0.0);
  EXPECT_EQ(inner.layer, 1);
  EXPECT_NEAR(inner.force.z(), kStiffness * 0.003, 1e-9);
  EXPECT_FALSE(ms.update(Vec3(0, 0, -0.002), Vec3::Zero(), 0.0).touching);
  ms.set_layer_enabled(0, true);
  EXPECT_EQ(ms.update(Vec3(0, 0, -0.008), Vec3::Zero(), 0.0).layer, 0);
  // A layer the ray missed holds nothing.
  SurfaceLayerHits missed = flat_layers({0.0, -0.005});
  missed.layers[0].found = false;
  ms.set_hits(missed, 0.0);
  EXPECT_EQ(ms.update(Vec3(0, 0, -0.008), Vec3::Zero(), 0.0).layer, 1);
}

TEST(MultiSurface, ASphereToolRestsOnTheLayerAndFarPlanesHoldNothing) {
  MultiSurfaceConfig c;
  c.stiffness = kStiffness;
  c.radius = 0.005;
  c.max_depth = 0.01;
  MultiSurfaceForce ms(c);
  ms.set_hits(flat_layers({0.0}), 0.0);
  // The sphere's centre 3 mm above the layer: its surface is 2 mm in.
  const MultiSurfaceOutput out = ms.update(Vec3(0, 0, 0.003), Vec3::Zero(), 0.0);
  EXPECT_NEAR(out.force.z(), kStiffness * 0.002, 1e-9);
  EXPECT_NEAR(out.proxy.z(), 0.005, 1e-12);
  // 1 cm behind the held plane and more: not the surface being pressed.
  EXPECT_TRUE(ms.update(Vec3(0, 0, -0.00499), Vec3::Zero(), 0.0).touching);
  EXPECT_FALSE(ms.update(Vec3(0, 0, -0.0051), Vec3::Zero(), 0.0).touching);
}

TEST(MultiSurface, AFaceTheProxyIsBehindHoldsNothing) {
  // A slab between z = −0.02 and 0. The tool is lifted off its top (the ray now points up
  // and, cast from behind the tool, enters the slab's bottom face first): that face's plane
  // has the proxy 2 cm behind it and must not pull the hand down.
  MultiSurfaceForce ms = make(1);
  ms.set_hits(flat_layers({0.0}), 0.0);
  ASSERT_TRUE(ms.update(Vec3(0, 0, -0.001), Vec3::Zero(), 0.0).touching);
  ASSERT_FALSE(ms.update(Vec3(0, 0, 0.002), Vec3(0, 0, 0.05), 0.001).touching);
  SurfaceLayerHits bottom;
  bottom.layers[0].found = true;
  bottom.layers[0].point = Vec3(0, 0, -0.02);
  bottom.layers[0].normal = -Vec3::UnitZ();
  ms.set_hits(bottom, 0.002);
  const MultiSurfaceOutput out = ms.update(Vec3(0, 0, 0.003), Vec3(0, 0, 0.05), 0.002);
  EXPECT_FALSE(out.touching);
  EXPECT_EQ(out.force.norm(), 0.0);
  // A free tool that has moved 1 mm into a layer before its hit arrived is still held.
  ms.set_hits(flat_layers({0.004}), 0.003);
  EXPECT_NEAR(ms.update(Vec3(0, 0, 0.003), Vec3::Zero(), 0.003).force.z(), kStiffness * 0.001, 1e-9);
}

TEST(MultiSurface, FrictionSticksBelowTheStaticLimitAndSlidesAtTheKineticOne) {
  MultiSurfaceConfig c;
  c.stiffness = kStiffness;
  c.layers = 1;
  c.static_friction = 0.5;
  c.kinetic_friction = 0.3;
  MultiSurfaceForce ms(c);
  ms.set_hits(flat_layers({0.0}), 0.0);
  const double depth = 0.005;  // normal force k·depth = 4 N; static limit 2 N, kinetic 1.2 N
  const MultiSurfaceOutput touch = ms.update(Vec3(0, 0, -depth), Vec3::Zero(), 0.0);
  ASSERT_TRUE(touch.touching);
  EXPECT_NEAR(touch.force.x(), 0.0, 1e-12);
  // Sticking: the proxy stays where it touched; the drag is the spring, k·dx, against the move.
  double x = 0.0;
  for (int k = 1; k <= 24; ++k) {
    x = 1e-4 * k;  // up to 2.4 mm: k·dx = 1.92 N < 2 N
    const MultiSurfaceOutput o = ms.update(Vec3(x, 0, -depth), Vec3(0.1, 0, 0), k * kFramePeriod);
    ASSERT_TRUE(o.sticking) << x;
    EXPECT_NEAR(o.proxy.x(), 0.0, 1e-12);
    EXPECT_NEAR(o.force.x(), -kStiffness * x, 1e-9);
    EXPECT_NEAR(o.force.z(), kStiffness * depth, 1e-9);
    // The next ray goes along the plane's inward normal from the held proxy, not towards the
    // device beside it: tilted by the pull, it would find another facet of a coarse skin.
    EXPECT_NEAR(ms.ray_direction().dot(Vec3(0, 0, -1)), 1.0, 1e-12) << x;
  }
  // Past the static limit it slides: the drag drops to μk·Fn and the proxy trails behind.
  const MultiSurfaceOutput slip = ms.update(Vec3(0.0026, 0, -depth), Vec3(0.1, 0, 0), 0.1);
  EXPECT_FALSE(slip.sticking);
  EXPECT_NEAR(slip.force.x(), -0.3 * kStiffness * depth, 1e-9);
  EXPECT_NEAR(slip.proxy.x(), 0.0026 - 0.3 * depth, 1e-12);
  // Stopping there, it sticks again at the slid anchor.
  const MultiSurfaceOutput rest = ms.update(Vec3(0.0026, 0, -depth), Vec3::Zero(), 0.2);
  EXPECT_TRUE(rest.sticking);
  EXPECT_NEAR(rest.force.x(), -0.3 * kStiffness * depth, 1e-9);
  // Lifted off, the anchor is forgotten: touching again starts without drag.
  EXPECT_FALSE(ms.update(Vec3(0.01, 0, 0.01), Vec3::Zero(), 0.3).touching);
  EXPECT_NEAR(ms.update(Vec3(0.01, 0, -depth), Vec3::Zero(), 0.4).force.x(), 0.0, 1e-12);
}

TEST(MultiSurface, DampingActsAlongTheNormalAndNeverPulls) {
  MultiSurfaceForce ms = make(1, 0.0, 2.0);
  ms.set_hits(flat_layers({0.0}), 0.0);
  // Pressing in at 0.1 m/s: k·d + b·v; pulling out fast: the damper may not pull the hand in.
  EXPECT_NEAR(ms.update(Vec3(0, 0, -0.001), Vec3(0, 0, -0.1), 0.0).force.z(), kStiffness * 0.001 + 0.2, 1e-9);
  EXPECT_NEAR(ms.update(Vec3(0, 0, -0.001), Vec3(0, 0, 2.0), 0.0).force.z(), 0.0, 1e-12);
}

TEST(MultiSurface, MovingLaterallyOverACurvedLayerKeepsTheProxyOnIt) {
  // A sphere of radius 5 cm (outward normal), pressed 2 mm deep while the device sweeps 0.6
  // rad of arc in 1 s; new hits every 8 frames (a 125 Hz interaction loop) along the ray the
  // algorithm asks for, with the planes blended over those 8 ms.
  const Vec3 centre(0, 0, -0.05);
  const double radius = 0.05, depth = 0.002;
  MultiSurfaceForce ms = make(1, 8 * kFramePeriod);
  const auto goal_at = [&](double t) {
    const double a = -0.3 + 0.6 * t;
    return Vec3(centre + (radius - depth) * Vec3(std::sin(a), 0, std::cos(a)));
  };
  // Start above the sphere and press in along −z.
  Vec3 previous = goal_at(0.0);
  double worst_off_surface = 0.0, worst_force_error = 0.0;
  for (int k = 0; k <= 1000; ++k) {
    const double t = k * kFramePeriod;
    if (k % 8 == 0) {
      SurfaceLayerHits hits;
      if (const auto h = enter_sphere(ms.ray_origin(), ms.ray_direction(), centre, radius)) hits.layers[0] = *h;
      if (k == 0) hits.layers[0] = *enter_sphere(goal_at(0.0) + Vec3(0, 0, 0.01), Vec3(0, 0, -1), centre, radius);
      ms.set_hits(hits, t);
    }
    const Vec3 goal = goal_at(t);
    const MultiSurfaceOutput out = ms.update(goal, (goal - previous) / kFramePeriod, t);
    previous = goal;
    if (k < 8) continue;  // the first plane is the one above the start point
    ASSERT_TRUE(out.touching) << t;
    worst_off_surface = std::max(worst_off_surface, std::abs((out.proxy - centre).norm() - radius));
    worst_force_error = std::max(worst_force_error, std::abs(out.force.norm() - kStiffness * depth));
  }
  // The proxy rides on tangent planes updated every 8 frames: between updates it drifts from
  // the sphere by (lateral lag)²/(2R), with the lag at most 8 frames of 0.03 mm/frame = 0.24
  // mm, i.e. 0.6 µm; 2 µm leaves room for the blend's turning plane.
  EXPECT_LT(worst_off_surface, 2e-6);
  // The force stays k·depth within the same geometric error times k (2 µm · 800 N/m).
  EXPECT_LT(worst_force_error, kStiffness * 2e-6 + 1e-9);
}

TEST(MultiSurface, PlaneUpdatesAreBlendedWithoutAForceStep) {
  const double blend = 8 * kFramePeriod;
  MultiSurfaceForce ms = make(1, blend);
  ms.set_hits(flat_layers({0.0}), 0.0);
  const Vec3 goal(0, 0, -0.002);
  double last = ms.update(goal, Vec3::Zero(), 0.0).force.z();
  EXPECT_NEAR(last, kStiffness * 0.002, 1e-9);
  // The surface sinks 1 mm at t = 10 ms: the force falls linearly to k · 1 mm over the blend.
  ms.set_hits(flat_layers({-0.001}), 0.010);
  double largest_step = 0.0;
  for (int k = 10; k <= 30; ++k) {
    const double f = ms.update(goal, Vec3::Zero(), k * kFramePeriod).force.z();
    largest_step = std::max(largest_step, std::abs(f - last));
    last = f;
  }
  EXPECT_NEAR(last, kStiffness * 0.001, 1e-9);
  // Δ = 0.8 N spread over 8 frames: 0.1 N a frame (rounding allowed), instead of one 0.8 N step.
  EXPECT_LT(largest_step, kStiffness * 0.001 / 8 + 1e-9);
  // Without blending the same update is a single step.
  MultiSurfaceForce sharp = make(1);
  sharp.set_hits(flat_layers({0.0}), 0.0);
  const double before = sharp.update(goal, Vec3::Zero(), 0.0).force.z();
  sharp.set_hits(flat_layers({-0.001}), 0.010);
  EXPECT_NEAR(before - sharp.update(goal, Vec3::Zero(), 0.010).force.z(), kStiffness * 0.001, 1e-9);
}

TEST(MultiSurface, TheRayPointsAlongThePlanesNormalWhilePressingElseAlongTheMotion) {
  MultiSurfaceForce ms = make(1);
  EXPECT_EQ(ms.ray_direction(), Vec3(0, 0, -1));
  ms.update(Vec3(0, 0, 0.01), Vec3(0.2, 0, 0), 0.0);
  EXPECT_NEAR(ms.ray_direction().dot(Vec3::UnitX()), 1.0, 1e-12);
  ms.update(Vec3(0, 0, 0.01), Vec3::Zero(), 0.0);  // at rest: the last direction stays
  EXPECT_NEAR(ms.ray_direction().dot(Vec3::UnitX()), 1.0, 1e-12);
  SurfaceLayerHits tilted;
  tilted.layers[0].found = true;
  tilted.layers[0].normal = Vec3(1, 0, 1).normalized();
  ms.set_hits(tilted, 0.0);
  const MultiSurfaceOutput out = ms.update(Vec3(-0.001, 0, -0.001), Vec3::Zero(), 0.0);
  ASSERT_TRUE(out.touching);
  EXPECT_NEAR(ms.ray_direction().dot(-Vec3(1, 0, 1).normalized()), 1.0, 1e-12);
  EXPECT_EQ(ms.ray_origin(), out.proxy);
}

TEST(MultiSurface, NeverNaNAndNoAllocation) {
  MultiSurfaceForce ms = make(3, 0.005, 1.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  SurfaceLayerHits bad = flat_layers({0.0, -0.003, -0.006});
  bad.layers[1].normal = Vec3(nan, 0, 0);
  bad.layers[2].normal = Vec3::Zero();
  testing::AllocationCounter counter;
  ms.set_hits(bad, 0.0);
  for (int k = 0; k < 500; ++k) {
    const Vec3 goal = k % 50 == 7 ? Vec3(nan, 0, 0) : Vec3(0, 0, -0.00002 * k);
    const Vec3 velocity = k % 50 == 9 ? Vec3(0, nan, 0) : Vec3(0, 0, -0.02);
    const MultiSurfaceOutput out = ms.update(goal, velocity, k * kFramePeriod);
    EXPECT_TRUE(out.force.allFinite()) << k;
    EXPECT_TRUE(out.proxy.allFinite()) << k;
    if (k % 16 == 0) ms.set_hits(bad, k * kFramePeriod);
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_TRUE(ms.ray_direction().allFinite());
}

TEST(MultiSurface, BadParametersAreRejected) {
  {
    MultiSurfaceConfig c;
    c.static_friction = 0.2;
    c.kinetic_friction = 0.3;
    EXPECT_THROW(MultiSurfaceForce{c}, std::invalid_argument);
  }
  MultiSurfaceConfig c;
  c.layers = 0;
  EXPECT_THROW(MultiSurfaceForce{c}, std::invalid_argument);
  c.layers = kMaxSurfaceLayers + 1;
  EXPECT_THROW(MultiSurfaceForce{c}, std::invalid_argument);
  c = MultiSurfaceConfig{};
  c.stiffness = 0.0;
  EXPECT_THROW(MultiSurfaceForce{c}, std::invalid_argument);
  c = MultiSurfaceConfig{};
  c.damping = -1.0;
  EXPECT_THROW(MultiSurfaceForce{c}, std::invalid_argument);
}

}  // namespace
}  // namespace tactus::haptics
