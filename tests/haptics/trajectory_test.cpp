#include "haptics/trajectory.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace tactus::haptics {
namespace {

constexpr double kTol = 1e-12;

#define EXPECT_VEC_NEAR(a, b, tol)                                                   \
  do {                                                                               \
    const Vec3 va_ = (a), vb_ = (b);                                                 \
    EXPECT_LE((va_ - vb_).norm(), (tol)) << "got " << va_.transpose() << ", expected " \
                                         << vb_.transpose();                         \
  } while (0)

WaypointsPath three_points(bool loop) {
  WaypointsPath p;
  p.points = {{0.0, Vec3(0, 0, 0)}, {1.0, Vec3(1, 0, 0)}, {3.0, Vec3(1, 2, 0)}};
  p.loop = loop;
  return p;
}

TEST(Waypoints, InterpolatesLinearlyInTimeAndHoldsTheEnds) {
  const Trajectory t = three_points(false);
  EXPECT_VEC_NEAR(position_at(t, 0.0), Vec3(0, 0, 0), kTol);
  EXPECT_VEC_NEAR(position_at(t, 0.25), Vec3(0.25, 0, 0), kTol);
  EXPECT_VEC_NEAR(position_at(t, 1.0), Vec3(1, 0, 0), kTol);
  EXPECT_VEC_NEAR(position_at(t, 2.0), Vec3(1, 1, 0), kTol);
  EXPECT_VEC_NEAR(position_at(t, 3.0), Vec3(1, 2, 0), kTol);
  EXPECT_VEC_NEAR(position_at(t, 50.0), Vec3(1, 2, 0), kTol);
  EXPECT_VEC_NEAR(velocity_at(t, 0.5), Vec3(1, 0, 0), kTol);
  EXPECT_VEC_NEAR(velocity_at(t, 2.0), Vec3(0, 1, 0), kTol);
  EXPECT_VEC_NEAR(velocity_at(t, 1.0), Vec3(0, 1, 0), kTol);  // one-sided: the segment ahead
  EXPECT_VEC_NEAR(velocity_at(t, 3.5), Vec3::Zero(), kTol);
  EXPECT_DOUBLE_EQ(duration(t), 3.0);
}

TEST(Waypoints, HoldsTheFirstPointBeforeItsTime) {
  WaypointsPath p;
  p.points = {{0.5, Vec3(1, 2, 3)}, {1.5, Vec3(2, 2, 3)}};
  const Trajectory t = p;
  EXPECT_VEC_NEAR(position_at(t, 0.0), Vec3(1, 2, 3), kTol);
  EXPECT_VEC_NEAR(position_at(t, 0.3), Vec3(1, 2, 3), kTol);
  EXPECT_VEC_NEAR(velocity_at(t, 0.3), Vec3::Zero(), kTol);
  EXPECT_VEC_NEAR(position_at(t, 1.0), Vec3(1.5, 2, 3), kTol);
}

TEST(Waypoints, LoopRepeatsWithThePeriodOfTheLastTime) {
  const Trajectory t = three_points(true);
  EXPECT_EQ(duration(t), std::numeric_limits<double>::infinity());
  for (double s : {0.1, 0.9, 1.7, 2.95})
    for (int k : {1, 2, 7}) {
      EXPECT_VEC_NEAR(position_at(t, s + 3.0 * k), position_at(t, s), 1e-12);
      EXPECT_VEC_NEAR(velocity_at(t, s + 3.0 * k), velocity_at(t, s), 1e-12);
    }
}

RasterPath square_raster() {
  RasterPath p;
  p.min = Vec2(-0.04, -0.04);
  p.max = Vec2(0.04, 0.04);
  p.z = 0.025;
  p.spacing = 0.01;
  p.speed = 0.02;
  return p;
}

TEST(Raster, ScansLinesAlongXAndVisitsAllFourCorners) {
  // 9 lines 0.08 long and 0.08 of connecting moves: 0.8 m at 0.02 m/s = 40 s.
  const Trajectory t = square_raster();
  EXPECT_NEAR(duration(t), 40.0, 1e-9);
  EXPECT_VEC_NEAR(position_at(t, 0.0), Vec3(-0.04, -0.04, 0.025), kTol);
  EXPECT_VEC_NEAR(position_at(t, 2.0), Vec3(0.0, -0.04, 0.025), kTol);
  EXPECT_VEC_NEAR(position_at(t, 4.0), Vec3(0.04, -0.04, 0.025), kTol);    // corner
  EXPECT_VEC_NEAR(position_at(t, 4.25), Vec3(0.04, -0.035, 0.025), kTol);  // moving up in y
  EXPECT_VEC_NEAR(position_at(t, 4.5), Vec3(0.04, -0.03, 0.025), kTol);
  EXPECT_VEC_NEAR(position_at(t, 6.5), Vec3(0.0, -0.03, 0.025), kTol);     // second line runs −x
  EXPECT_VEC_NEAR(position_at(t, 36.0), Vec3(-0.04, 0.04, 0.025), kTol);   // corner
  EXPECT_VEC_NEAR(position_at(t, 40.0), Vec3(0.04, 0.04, 0.025), kTol);    // corner
  EXPECT_VEC_NEAR(position_at(t, 100.0), Vec3(0.04, 0.04, 0.025), kTol);
  EXPECT_VEC_NEAR(velocity_at(t, 1.0), Vec3(0.02, 0, 0), kTol);
  EXPECT_VEC_NEAR(velocity_at(t, 4.25), Vec3(0, 0.02, 0), kTol);
  EXPECT_VEC_NEAR(velocity_at(t, 6.0), Vec3(-0.02, 0, 0), kTol);
  EXPECT_VEC_NEAR(velocity_at(t, 41.0), Vec3::Zero(), kTol);
}

TEST(Raster, AddsALastLineOnMaxYWhenTheHeightIsNotAMultipleOfTheSpacing) {
  RasterPath p = square_raster();
  p.max.y() = -0.015;  // height 0.025: lines at −0.04, −0.03, −0.02, −0.015
  const Trajectory t = p;
  const double length = 4 * 0.08 + 0.025;
  EXPECT_NEAR(duration(t), length / 0.02, 1e-9);
  EXPECT_VEC_NEAR(position_at(t, duration(t)), Vec3(-0.04, -0.015, 0.025), kTol);  // 4th line runs −x
  EXPECT_VEC_NEAR(position_at(t, (3 * 0.08 + 0.025) / 0.02), Vec3(0.04, -0.015, 0.025), 1e-12);
}

TEST(Raster, StaysInTheRectangleAtConstantSpeed) {
  const RasterPath p = square_raster();
  const Trajectory t = p;
  const double dt = 1e-3;
  Vec3 previous = position_at(t, 0.0);
  for (double s = dt; s <= duration(t); s += dt) {
    const Vec3 x = position_at(t, s);
    ASSERT_GE(x.x(), p.min.x() - kTol);
    ASSERT_LE(x.x(), p.max.x() + kTol);
    ASSERT_GE(x.y(), p.min.y() - kTol);
    ASSERT_LE(x.y(), p.max.y() + kTol);
    ASSERT_EQ(x.z(), p.z);
    // Path length per step is speed·dt; the chord is shorter only across a corner.
    const double step = (x - previous).norm();
    ASSERT_LE(step, p.speed * dt + 1e-12) << s;
    ASSERT_GE(step, p.speed * dt / std::sqrt(2.0) - 1e-12) << s;
    previous = x;
  }
}

TEST(Raster, AnApproachComesStraightDownOntoTheFirstCornerAndDelaysTheScan) {
  RasterPath p = square_raster();
  p.approach = 0.01;  // 0.5 s at 0.02 m/s
  const Trajectory t = p, plain = square_raster();
  EXPECT_NEAR(duration(t), 40.5, 1e-9);
  EXPECT_VEC_NEAR(position_at(t, 0.0), Vec3(-0.04, -0.04, 0.035), kTol);
  EXPECT_VEC_NEAR(position_at(t, 0.25), Vec3(-0.04, -0.04, 0.030), kTol);
  EXPECT_VEC_NEAR(velocity_at(t, 0.25), Vec3(0, 0, -0.02), kTol);
  // Then the scan, half a second late.
  for (double s : {0.5, 1.0, 4.75, 20.0, 40.5})
    EXPECT_VEC_NEAR(position_at(t, s), position_at(plain, s - 0.5), 1e-12);
  EXPECT_VEC_NEAR(velocity_at(t, 1.0), Vec3(0.02, 0, 0), kTol);
  EXPECT_VEC_NEAR(velocity_at(t, 41.0), Vec3::Zero(), kTol);
}

PressPath two_presses() {
  PressPath p;
  p.position = Vec3(0, 0, 0.01);
  p.direction = Vec3(0, 0, -1);
  p.depth = 0.005;
  p.speed = 0.01;
  p.hold = 1.0;
  p.repeat = 2;
  return p;
}

TEST(Press, ReachesDepthAtDepthOverSpeedHoldsAndReturns) {
  // Stroke 0.5 s, cycle 0.5 + 1 + 0.5 = 2 s, two cycles.
  const Trajectory t = two_presses();
  EXPECT_DOUBLE_EQ(duration(t), 4.0);
  EXPECT_VEC_NEAR(position_at(t, 0.0), Vec3(0, 0, 0.01), kTol);
  EXPECT_VEC_NEAR(position_at(t, 0.25), Vec3(0, 0, 0.0075), kTol);
  EXPECT_VEC_NEAR(position_at(t, 0.5), Vec3(0, 0, 0.005), kTol);
  EXPECT_VEC_NEAR(position_at(t, 1.2), Vec3(0, 0, 0.005), kTol);
  EXPECT_VEC_NEAR(position_at(t, 1.75), Vec3(0, 0, 0.0075), kTol);
  EXPECT_VEC_NEAR(position_at(t, 2.0), Vec3(0, 0, 0.01), kTol);
  EXPECT_VEC_NEAR(position_at(t, 2.5), Vec3(0, 0, 0.005), kTol);
  EXPECT_VEC_NEAR(position_at(t, 3.9), Vec3(0, 0, 0.009), kTol);
  EXPECT_VEC_NEAR(position_at(t, 9.0), Vec3(0, 0, 0.01), kTol);
  EXPECT_VEC_NEAR(velocity_at(t, 0.25), Vec3(0, 0, -0.01), kTol);
  EXPECT_VEC_NEAR(velocity_at(t, 1.0), Vec3::Zero(), kTol);
  EXPECT_VEC_NEAR(velocity_at(t, 1.75), Vec3(0, 0, 0.01), kTol);
  EXPECT_VEC_NEAR(velocity_at(t, 5.0), Vec3::Zero(), kTol);
}

TEST(Press, FollowsAnObliqueDirection) {
  PressPath p = two_presses();
  p.direction = Vec3(1, 0, -1).normalized();
  p.repeat = 1;
  const Trajectory t = p;
  EXPECT_VEC_NEAR(position_at(t, 0.5), p.position + 0.005 * p.direction, kTol);
  EXPECT_DOUBLE_EQ(duration(t), 2.0);
}

TEST(Circle, StartsOnTheProjectedXAxisTurnsCounterclockwiseWithConstantRadius) {
  CirclePath p;
  p.center = Vec3(1, 2, 3);
  p.normal = Vec3(0, 0, 1);
  p.radius = 0.02;
  p.period = 2.0;
  const Trajectory t = p;
  EXPECT_EQ(duration(t), std::numeric_limits<double>::infinity());
  EXPECT_VEC_NEAR(position_at(t, 0.0), Vec3(1.02, 2, 3), kTol);
  EXPECT_VEC_NEAR(position_at(t, 0.5), Vec3(1, 2.02, 3), kTol);
  EXPECT_VEC_NEAR(position_at(t, 1.0), Vec3(0.98, 2, 3), kTol);
  EXPECT_VEC_NEAR(velocity_at(t, 0.0), Vec3(0, 0.02 * std::numbers::pi, 0), kTol);
}

TEST(Circle, RadiusIsConstantAndThePeriodExactForATiltedPlane) {
  CirclePath p;
  p.center = Vec3(0.1, -0.2, 0.3);
  p.normal = Vec3(1, 1, 1).normalized();
  p.radius = 0.015;
  p.period = 0.7;
  const Trajectory t = p;
  for (double s = 0.0; s < 5.0; s += 0.0137) {
    const Vec3 r = position_at(t, s) - p.center;
    ASSERT_NEAR(r.norm(), p.radius, 1e-15);
    ASSERT_NEAR(r.dot(p.normal), 0.0, 1e-15);
    ASSERT_LE((position_at(t, s + p.period) - position_at(t, s)).norm(), 1e-15);
    ASSERT_LE((position_at(t, s + 100 * p.period) - position_at(t, s)).norm(), 1e-13);
    ASSERT_NEAR(velocity_at(t, s).norm(), 2 * std::numbers::pi * p.radius / p.period, 1e-14);
  }
  // Half a period later the point is diametrically opposite.
  EXPECT_VEC_NEAR(position_at(t, 0.2) + position_at(t, 0.2 + 0.35), 2 * p.center, 1e-15);
}

TEST(Circle, NormalAlongXStartsOnTheProjectedYAxis) {
  CirclePath p;
  p.normal = Vec3(1, 0, 0);
  p.radius = 1.0;
  const Trajectory t = p;
  EXPECT_VEC_NEAR(position_at(t, 0.0), Vec3(0, 1, 0), kTol);
  EXPECT_VEC_NEAR(position_at(t, p.period / 4), Vec3(0, 0, 1), kTol);  // x × y = z: right-handed about x
}

TEST(NeedleLine, MovesFromEntryAtSpeedAndStopsExactlyAtTarget) {
  NeedleLinePath p;
  p.entry = Vec3(0, 0, 0.05);
  p.target = Vec3(0.03, 0, 0.01);  // 0.05 m away
  p.speed = 0.005;
  const Trajectory t = p;
  EXPECT_NEAR(duration(t), 10.0, 1e-12);
  EXPECT_VEC_NEAR(position_at(t, 0.0), p.entry, kTol);
  EXPECT_VEC_NEAR(position_at(t, 5.0), Vec3(0.015, 0, 0.03), kTol);
  EXPECT_VEC_NEAR(velocity_at(t, 5.0), Vec3(0.003, 0, -0.004), kTol);
  EXPECT_EQ(position_at(t, 10.0), p.target);
  EXPECT_EQ(position_at(t, 25.0), p.target);
  EXPECT_EQ(velocity_at(t, 10.5), Vec3::Zero());
}

TEST(Trajectory, VelocityMatchesFiniteDifferencesWhereThePathIsSmooth) {
  CirclePath circle;
  circle.center = Vec3(0, 0, 0.1);
  circle.normal = Vec3(0, 1, 1).normalized();
  circle.radius = 0.02;
  circle.period = 1.3;
  NeedleLinePath needle;
  needle.entry = Vec3(0, 0, 0.05);
  needle.target = Vec3(0, 0.01, 0);
  const std::vector<Trajectory> all = {three_points(true), square_raster(), two_presses(), circle, needle};
  const double h = 1e-6;
  for (const Trajectory& t : all) {
    int smooth = 0, samples = 0;
    const double end = std::isfinite(duration(t)) ? duration(t) : 5.0;
    for (double s = 0.0123; s < end; s += end / 997.0, ++samples) {
      const Vec3 forward = (position_at(t, s + h) - position_at(t, s)) / h;
      const Vec3 backward = (position_at(t, s) - position_at(t, s - h)) / h;
      if ((forward - backward).norm() > 1e-3 * (1.0 + forward.norm())) continue;  // a corner
      ++smooth;
      const Vec3 central = 0.5 * (forward + backward);
      ASSERT_LE((velocity_at(t, s) - central).norm(), 1e-6 * (1.0 + central.norm()))
          << "type " << t.index() << " at t = " << s;
    }
    EXPECT_GE(smooth, samples * 9 / 10) << "type " << t.index();
  }
}

TEST(Tremor, IsBoundedByTheAmplitudeYetNotSmall) {
  const Tremor tremor{0.001, 8.0};
  for (unsigned seed : {0u, 1u, 42u, 4000000000u}) {
    double max_norm = 0.0, sum_sq = 0.0;
    int n = 0, sign_changes = 0;
    double previous_x = tremor_at(tremor, 0.0, seed).x();
    for (double t = 0.0; t <= 10.0; t += 1e-4, ++n) {
      const Vec3 w = tremor_at(tremor, t, seed);
      max_norm = std::max(max_norm, w.norm());
      sum_sq += w.squaredNorm();
      if ((w.x() > 0) != (previous_x > 0)) ++sign_changes;
      previous_x = w.x();
    }
    const double rms = std::sqrt(sum_sq / n);
    EXPECT_LE(max_norm, tremor.amplitude) << seed;
    EXPECT_GT(rms, 0.2 * tremor.amplitude) << seed;
    // Two zero crossings per cycle near 8 Hz: about 160 in 10 s.
    EXPECT_GT(sign_changes, 100) << seed;
    EXPECT_LT(sign_changes, 240) << seed;
  }
}

TEST(Tremor, IsDeterministicPerSeedAndZeroWithoutAmplitude) {
  const Tremor tremor{0.002, 6.0};
  EXPECT_EQ(tremor_at(tremor, 1.234, 7), tremor_at(tremor, 1.234, 7));
  EXPECT_NE(tremor_at(tremor, 1.234, 7), tremor_at(tremor, 1.234, 8));
  EXPECT_EQ(tremor_at(Tremor{0.0, 8.0}, 1.234, 7), Vec3::Zero());
}

}  // namespace
}  // namespace tactus::haptics
