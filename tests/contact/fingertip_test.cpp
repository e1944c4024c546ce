// Capsule fingertips: closest points and signed distances against brute-force sampling of
// the surfaces and axes, and continuous collision against a moving capsule, checked against
// a reference that samples time densely with an independent distance.
#include "contact/fingertip.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "contact/closest_point.hpp"
#include "core/error.hpp"

namespace tactus::contact {
namespace {

constexpr double kPi = std::numbers::pi;

// Trial counts, smaller under sanitizers (ten to fifty times slower).
#ifdef TACTUS_SANITIZED
constexpr int kSweepTrials = 60;
#else
constexpr int kSweepTrials = 300;
#endif

/// Points on the surface of the capsule: the cylinder and the two hemispherical caps.
std::vector<Vec3> surface_samples(const Capsule& c, int rings, int around) {
  const Vec3 axis = c.tip - c.base;
  const Vec3 u = axis.norm() > 0.0 ? Vec3(axis.normalized()) : Vec3::UnitZ();
  const Vec3 v = u.unitOrthogonal(), w = u.cross(v);
  std::vector<Vec3> out;
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < around; ++j) {
      const double phi = 2.0 * kPi * j / around;
      const Vec3 radial = std::cos(phi) * v + std::sin(phi) * w;
      out.push_back(c.base + (static_cast<double>(i) / rings) * axis + c.radius * radial);
    }
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < around; ++j) {
      const double theta = 0.5 * kPi * i / rings, phi = 2.0 * kPi * j / around;
      const Vec3 radial = std::cos(phi) * v + std::sin(phi) * w;
      out.push_back(c.base + c.radius * (-std::cos(theta) * u + std::sin(theta) * radial));
      out.push_back(c.tip + c.radius * (std::cos(theta) * u + std::sin(theta) * radial));
    }
  return out;
}

/// The distance from p to the segment, by sampling it.
double sampled_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b, int samples) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= samples; ++i)
    best = std::min(best, (p - (a + (static_cast<double>(i) / samples) * (b - a))).norm());
  return best;
}

Capsule random_capsule(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.02, 0.02), r(0.002, 0.01);
  Capsule c;
  c.base = Vec3(u(rng), u(rng), u(rng));
  c.tip = c.base + Vec3(u(rng), u(rng), u(rng));
  c.radius = r(rng);
  return c;
}

TEST(PointCapsule, SignedDistanceMatchesSampledSurface) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-0.04, 0.04);
  int inside = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const Capsule c = random_capsule(rng);
    const std::vector<Vec3> samples = surface_samples(c, 160, 160);
    const double spacing = std::max((c.tip - c.base).norm() / 160.0, 2.0 * kPi * c.radius / 160.0);
    for (int k = 0; k < 20; ++k) {
      // Some points near the axis, so that inside points are tried too.
      const Vec3 p = k % 3 == 0 ? Vec3(c.base + 0.5 * (c.tip - c.base) + 0.3 * c.radius * Vec3::Random())
                                : Vec3(u(rng), u(rng), u(rng));
      double reference = std::numeric_limits<double>::infinity();
      for (const Vec3& s : samples) reference = std::min(reference, (p - s).norm());
      const bool is_inside = sampled_segment_distance(p, c.base, c.tip, 4000) < c.radius;
      if (is_inside) {
        reference = -reference;
        ++inside;
      }
      const CapsulePoint q = point_capsule(p, c);
      // Samples lie on the surface, so they overestimate the gap by at most about one spacing.
      EXPECT_NEAR(q.signed_distance, reference, spacing) << trial << " " << k;
      if (!is_inside) {
        EXPECT_LE(q.signed_distance, reference + 1e-12);
      }
      // The returned point is on the surface, |p − point| is the distance, the normal unit.
      EXPECT_NEAR(sampled_segment_distance(q.surface_point, c.base, c.tip, 20000), c.radius, 1e-6);
      EXPECT_NEAR((p - q.surface_point).norm(), std::abs(q.signed_distance), 1e-12);
      EXPECT_NEAR(q.normal.norm(), 1.0, 1e-12);
    }
  }
  EXPECT_GT(inside, 20);
}

TEST(PointCapsule, PointOnTheAxisGetsANormalAcrossIt) {
  const Capsule c{Vec3(0, 0, 0), Vec3(0.02, 0, 0), 0.005};
  const CapsulePoint q = point_capsule(Vec3(0.01, 0, 0), c);
  EXPECT_DOUBLE_EQ(q.signed_distance, -0.005);
  EXPECT_NEAR(q.normal.dot(Vec3::UnitX()), 0.0, 1e-15);
  EXPECT_NEAR(q.normal.norm(), 1.0, 1e-15);
}

TEST(CapsuleCapsule, MatchesSampledAxesIncludingParallelCases) {
  std::mt19937 rng(2);
  std::vector<std::pair<Capsule, Capsule>> cases;
  for (int i = 0; i < 30; ++i) cases.emplace_back(random_capsule(rng), random_capsule(rng));
  // Parallel, antiparallel, collinear and overlapping, crossing, point-like.
  const Capsule x{Vec3(0, 0, 0), Vec3(0.02, 0, 0), 0.005};
  cases.push_back({x, {Vec3(0.005, 0.012, 0), Vec3(0.03, 0.012, 0), 0.004}});
  cases.push_back({x, {Vec3(0.03, 0.0, 0.011), Vec3(0.01, 0.0, 0.011), 0.004}});
  cases.push_back({x, {Vec3(0.025, 0.0, 0.0), Vec3(0.05, 0.0, 0.0), 0.004}});
  cases.push_back({x, {Vec3(-0.01, 0.001, 0.0), Vec3(0.04, 0.001, 0.0), 0.004}});
  cases.push_back({x, {Vec3(0.01, -0.01, 0.002), Vec3(0.01, 0.01, 0.002), 0.004}});
  cases.push_back({x, {Vec3(0.03, 0.01, 0.0), Vec3(0.03, 0.01, 0.0), 0.004}});
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const auto& [a, b] = cases[k];
    double axes = std::numeric_limits<double>::infinity();
    const int n = 1500;
    for (int i = 0; i <= n; ++i) {
      const Vec3 pa = a.base + (static_cast<double>(i) / n) * (a.tip - a.base);
      axes = std::min(axes, sampled_segment_distance(pa, b.base, b.tip, n));
    }
    const double spacing = std::max((a.tip - a.base).norm(), (b.tip - b.base).norm()) / n;
    const CapsulePair q = capsule_capsule(a, b);
    // A capsule is its axis grown by its radius, so the gap is the axes' distance minus both radii.
    EXPECT_NEAR(q.signed_distance, axes - a.radius - b.radius, spacing) << k;
    EXPECT_LE(q.signed_distance, axes - a.radius - b.radius + 1e-12) << k;
    EXPECT_NEAR(sampled_segment_distance(q.on_first, a.base, a.tip, 20000), a.radius, 1e-6) << k;
    EXPECT_NEAR(sampled_segment_distance(q.on_second, b.base, b.tip, 20000), b.radius, 1e-6) << k;
    EXPECT_NEAR(q.normal.norm(), 1.0, 1e-12);
    if (q.signed_distance > 0.0) {
      EXPECT_NEAR((q.on_second - q.on_first).norm(), q.signed_distance, 1e-12);
      EXPECT_NEAR((q.on_second - q.on_first).normalized().dot(q.normal), 1.0, 1e-9);
    }
  }
}

TEST(CapsuleCapsule, SeparatedPairsMatchSampledSurfaces) {
  std::mt19937 rng(3);
  int tried = 0;
  while (tried < 6) {
    const Capsule a = random_capsule(rng), b = random_capsule(rng);
    if (capsule_capsule(a, b).signed_distance < 0.002) continue;
    ++tried;
    const std::vector<Vec3> sa = surface_samples(a, 50, 60), sb = surface_samples(b, 50, 60);
    double reference = std::numeric_limits<double>::infinity();
    for (const Vec3& p : sa)
      for (const Vec3& q : sb) reference = std::min(reference, (p - q).squaredNorm());
    reference = std::sqrt(reference);
    const double spacing = 2.0 * kPi * std::max(a.radius, b.radius) / 60.0 +
                           std::max((a.tip - a.base).norm(), (b.tip - b.base).norm()) / 50.0;
    const double d = capsule_capsule(a, b).signed_distance;
    EXPECT_LE(d, reference + 1e-12);
    EXPECT_NEAR(d, reference, spacing);
  }
}

TEST(ClosestPointsSegments, ParallelOverlapGivesTheMiddleAndAPerpendicularPair) {
  const SegmentPair p = closest_points_segments(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.4, 1, 0), Vec3(2, 1, 0));
  EXPECT_DOUBLE_EQ(p.distance, 1.0);
  EXPECT_NEAR(p.s, 0.7, 1e-12);  // overlap [0.4, 1] on the first
  EXPECT_NEAR((p.on_second - p.on_first).dot(Vec3::UnitX()), 0.0, 1e-12);
  // Antiparallel and disjoint: the nearest ends.
  const SegmentPair q = closest_points_segments(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(3, 1, 0), Vec3(2, 1, 0));
  EXPECT_NEAR(q.distance, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR((q.on_first - Vec3(1, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((q.on_second - Vec3(2, 1, 0)).norm(), 0.0, 1e-12);
}

TEST(SegmentTriangle, MatchesSampledSegmentAgainstTriangle) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int pierced = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    const Vec3 p0 = 1.5 * Vec3(u(rng), u(rng), u(rng)), p1 = 1.5 * Vec3(u(rng), u(rng), u(rng));
    const int n = 20000;
    double reference = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= n; ++i) {
      const Vec3 x = p0 + (static_cast<double>(i) / n) * (p1 - p0);
      reference = std::min(reference, (x - closest_point_on_triangle(x, a, b, c).point).norm());
    }
    const SegmentTrianglePair q = closest_points_segment_triangle(p0, p1, a, b, c);
    const double spacing = (p1 - p0).norm() / n;
    EXPECT_LE(q.distance, reference + 1e-12) << trial;
    EXPECT_NEAR(q.distance, reference, spacing) << trial;
    EXPECT_NEAR((q.on_segment - q.on_triangle).norm(), q.distance, 1e-12);
    EXPECT_NEAR((q.barycentric[0] * a + q.barycentric[1] * b + q.barycentric[2] * c - q.on_triangle).norm(), 0.0,
                1e-12);
    EXPECT_NEAR(q.barycentric.sum(), 1.0, 1e-12);
    EXPECT_GE(q.barycentric.minCoeff(), -1e-12);
    if (q.distance < 1e-12) ++pierced;
  }
  EXPECT_GT(pierced, 10);
}

// --- continuous collision --------------------------------------------------------------------

CapsuleShape finger_shape() {
  CapsuleShape s;
  s.base = Vec3(0, 0, 0);
  s.tip = Vec3(0.02, 0, 0);
  s.radius = 0.005;
  return s;
}

/// Gap between p and the capsule at the pose, from the sampled axis (not the code's query).
double reference_gap(const Vec3& p, const CapsuleShape& s, const Pose& pose) {
  return sampled_segment_distance(p, pose.to_world(s.base), pose.to_world(s.tip), 400) - s.radius;
}

Pose interpolate(const Pose& a, const Pose& b, double t) {
  Pose p;
  p.position = (1.0 - t) * a.position + t * b.position;
  p.orientation = a.orientation.slerp(t, b.orientation);
  return p;
}

TEST(SweepParticleCapsule, CatchesAFastFingerThatDiscreteChecksMiss) {
  const CapsuleShape s = finger_shape();
  const Vec3 particle(0.01, 0.0, 0.0);
  // Straight through in one step: 10 cm, far more than the 1 cm thick finger.
  Pose from, to;
  from.position = Vec3(0, 0, 0.05);
  to.position = Vec3(0, 0, -0.05);
  EXPECT_GT(point_capsule(particle, posed(s, from)).signed_distance, 0.0);
  EXPECT_GT(point_capsule(particle, posed(s, to)).signed_distance, 0.0);
  ParticleSweep hit = sweep_particle_capsule(particle, particle, s, from, to);
  ASSERT_TRUE(hit.hit);
  EXPECT_TRUE(hit.converged);
  EXPECT_NEAR(hit.time, (0.05 - 0.005) / 0.1, 1e-5);  // touches when its surface reaches the particle
  EXPECT_LE(hit.time, 0.45 + 1e-12);                  // never after

  // A fingertip swinging 170° about its base past a particle 15 mm out.
  Pose swing0, swing1;
  swing1.orientation = Quat(Eigen::AngleAxisd(170.0 * kPi / 180.0, Vec3::UnitZ()));
  const Vec3 on_arc(0.0, 0.015, 0.0);
  EXPECT_GT(point_capsule(on_arc, posed(s, swing0)).signed_distance, 0.0);
  EXPECT_GT(point_capsule(on_arc, posed(s, swing1)).signed_distance, 0.0);
  hit = sweep_particle_capsule(on_arc, on_arc, s, swing0, swing1);
  ASSERT_TRUE(hit.hit);
  // The axis at angle φ is 15 mm·sin(90° − φ) from the particle: touching when that is r.
  const double phi = kPi / 2.0 - std::asin(0.005 / 0.015);
  EXPECT_NEAR(hit.time, phi / (170.0 * kPi / 180.0), 1e-4);
  EXPECT_LE(hit.time, phi / (170.0 * kPi / 180.0) + 1e-12);

  // A particle moving against a still finger, and one that passes beside it.
  hit = sweep_particle_capsule(Vec3(0.01, 0.0, 0.1), Vec3(0.01, 0.0, -0.1), s, Pose{}, Pose{});
  ASSERT_TRUE(hit.hit);
  EXPECT_NEAR(hit.time, (0.1 - 0.005) / 0.2, 1e-5);
  EXPECT_FALSE(sweep_particle_capsule(Vec3(0.01, 0.02, 0.1), Vec3(0.01, 0.02, -0.1), s, Pose{}, Pose{}).hit);
  // Starting inside is a hit at once.
  hit = sweep_particle_capsule(Vec3(0.01, 0.0, 0.001), Vec3(0.01, 0.0, 0.1), s, Pose{}, Pose{});
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.time, 0.0);
}

TEST(SweepParticleCapsule, NeverLateAgainstDenseTimeSampling) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const CapsuleShape s = finger_shape();
  int hits = 0, misses = 0;
  for (int trial = 0; trial < kSweepTrials; ++trial) {
    Pose a, b;
    a.position = 0.03 * Vec3(u(rng), u(rng), u(rng));
    b.position = 0.03 * Vec3(u(rng), u(rng), u(rng));
    a.orientation = Quat(Eigen::AngleAxisd(kPi * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
    b.orientation = a.orientation * Quat(Eigen::AngleAxisd(2.0 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
    // Half the particles start near where the finger passes halfway, so that many are hit.
    const Vec3 near_path = interpolate(a, b, 0.5).to_world(s.base + 0.5 * (1.0 + u(rng)) * (s.tip - s.base));
    const Vec3 p0 = trial % 2 == 0 ? Vec3(near_path + 0.01 * Vec3(u(rng), u(rng), u(rng)))
                                   : Vec3(0.03 * Vec3(u(rng), u(rng), u(rng)));
    const Vec3 p1 = p0 + 0.01 * Vec3(u(rng), u(rng), u(rng));
    if (reference_gap(p0, s, a) <= 1e-4) continue;  // starts (nearly) in contact

    const int n = 2000;
    double first = 2.0, closest = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= n && first > 1.0; ++i) {
      const double t = static_cast<double>(i) / n;
      const double g = reference_gap((1.0 - t) * p0 + t * p1, s, interpolate(a, b, t));
      closest = std::min(closest, g);
      if (g <= 0.0) first = t;
    }
    SweepOptions options;
    options.max_iterations = 100000;
    const ParticleSweep hit = sweep_particle_capsule(p0, p1, s, a, b, options);
    if (first <= 1.0) {
      ASSERT_TRUE(hit.hit) << trial;
      ++hits;
      EXPECT_LE(hit.time, first + 1e-12) << trial;  // never later than the sampled first contact
      EXPECT_LE(hit.signed_distance, options.tolerance);
      // Nothing touched before the reported time: the reference is clear there.
      for (int i = 0; i <= 200; ++i) {
        const double t = hit.time * i / 200.0;
        EXPECT_GT(reference_gap((1.0 - t) * p0 + t * p1, s, interpolate(a, b, t)), -1e-6) << trial;
      }
    } else if (closest > 1e-4) {
      EXPECT_FALSE(hit.hit) << trial;
      ++misses;
    }
  }
  EXPECT_GT(hits, kSweepTrials / 10);
  EXPECT_GT(misses, kSweepTrials / 10);
}

TEST(CapsuleShape, ValidationNamesTheProblem) {
  CapsuleShape s = finger_shape();
  EXPECT_NO_THROW(validate(s, "thumb"));
  s.radius = 0.0;
  EXPECT_THROW(validate(s, "thumb"), InputError);
  s = finger_shape();
  s.pad_normal = Vec3(1, 0, 0);  // along the axis
  try {
    validate(s, "thumb");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("thumb"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("pad normal"), std::string::npos);
  }
  s = finger_shape();
  s.tip.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(validate(s, "index"), InputError);
}

}  // namespace
}  // namespace tactus::contact
