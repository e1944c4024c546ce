// The two-finger grasp (seed 002 §V-D, states VIII and IX): the shared frame (orthonormal,
// right-handed, along the pads' intersection line, parallel pads handled), equal and
// opposite finger forces when a flat patch is squeezed, momentum balance, particles held in
// the shared frame until the tangential load reaches μ_s times the squeeze and sliding at μ_k
// beyond it, and targets that stay continuous when the frame changes rule. The one-point grasp
// of coarse meshes: the squeeze law, the hold at the point's projection moving with the
// fingers, stick below μ_s·F^N and the pull at μ_k·F^N when it slips, the hold carried to
// another point unchanged, and letting go when the pads open.
#include "contact/grasp.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "core/counting_allocator.hpp"
#include "core/error.hpp"

namespace tactus::contact {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRadius = 0.008;

/// Seed 002 eq. 1 with its printed constants (mm, N).
double pawluk_howe_newtons(double depth_mm) { return 0.19 / 2.1 * (std::exp(2.1 * depth_mm) - 1.0); }

CapsuleShape finger_along_x(const Vec3& pad) {
  CapsuleShape s;
  s.base = Vec3(-0.006, 0, 0);
  s.tip = Vec3(0.006, 0, 0);
  s.radius = kRadius;
  s.pad_normal = pad;
  return s;
}

GraspParams pinch_params() {
  GraspParams p;
  p.thumb = finger_along_x(Vec3::UnitZ());   // pad up, toward the index
  p.index = finger_along_x(-Vec3::UnitZ());  // pad down, toward the thumb
  p.fabric_thickness = 0.5e-3;
  p.capture_distance = 1e-3;
  p.static_friction = 1.0;
  p.kinetic_friction = 0.8;
  return p;
}

/// A rigid motion applied to the whole scene.
struct Rigid {
  Quat q = Quat::Identity();
  Vec3 t = Vec3::Zero();
  [[nodiscard]] Vec3 point(const Vec3& x) const { return q * x + t; }
  [[nodiscard]] Pose pose(const Pose& p) const {
    Pose out;
    out.position = point(p.position);
    out.orientation = q * p.orientation;
    return out;
  }
};

/// Thumb below z = 0 and index above, their pads `squeeze` into a fabric of the set thickness
/// lying in z = 0 (particles every mm over ±3 mm).
struct Pinch {
  GraspParams params = pinch_params();
  Grasp grasp{params};
  GraspState state = grasp.make_state();
  std::vector<Vec3> particles;
  std::vector<std::int32_t> candidates;
  Pose thumb, index;

  explicit Pinch(double squeeze = 0.5e-3, const Rigid& motion = {}) {
    const double gap = params.fabric_thickness - squeeze;
    thumb.position = Vec3(0, 0, -(kRadius + 0.5 * gap));
    index.position = Vec3(0, 0, kRadius + 0.5 * gap);
    thumb = motion.pose(thumb);
    index = motion.pose(index);
    for (int j = -3; j <= 3; ++j)
      for (int i = -3; i <= 3; ++i) {
        candidates.push_back(static_cast<std::int32_t>(particles.size()));
        particles.push_back(motion.point(Vec3(1e-3 * i, 1e-3 * j, 0.0)));
      }
  }
  GraspResult step() { return grasp.update(state, thumb, index, particles, candidates); }
};

Vec3 sum_of_particle_forces(const GraspResult& r) {
  Vec3 s = Vec3::Zero();
  for (const HeldParticle& h : r.held) s += h.force;
  return s;
}

TEST(Grasp, SqueezingAFlatPatchGivesEqualAndOppositeFingerForces) {
  std::mt19937 rng(10);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    Rigid m;
    if (trial > 0) {
      m.q = Quat(Eigen::AngleAxisd(kPi * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
      m.t = 0.05 * Vec3(u(rng), u(rng), u(rng));
    }
    const double squeeze_mm = 0.2 + 0.1 * trial;
    Pinch pinch(squeeze_mm * 1e-3, m);
    const GraspResult r = pinch.step();
    ASSERT_TRUE(r.active);
    EXPECT_EQ(r.held.size(), pinch.particles.size());
    EXPECT_EQ(r.friction, FrictionState::stick);
    const double fn = pawluk_howe_newtons(squeeze_mm);
    EXPECT_NEAR(r.squeeze_force, fn, 1e-9 * fn);
    EXPECT_NEAR((r.force_on_thumb + r.force_on_index).norm(), 0.0, 1e-12 * fn) << trial;
    EXPECT_NEAR((r.force_on_index - fn * (m.q * Vec3::UnitZ())).norm(), 0.0, 1e-9 * fn) << trial;
    // The patch lies in the contact plane: nothing pulls it.
    EXPECT_NEAR(r.frame.normal().dot(m.q * Vec3::UnitZ()), 1.0, 1e-12);
    EXPECT_LT(sum_of_particle_forces(r).norm(), 1e-12);
  }
}

TEST(Grasp, FingerAndParticleForcesBalance) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Pinch pinch;
  (void)pinch.step();
  for (int i = 0; i < 50; ++i) {
    // The fabric wrinkles and drifts under the pads.
    for (Vec3& x : pinch.particles) x += Vec3(2e-5 * u(rng), 2e-5 * u(rng), 4e-5 * u(rng));
    const GraspResult r = pinch.step();
    ASSERT_TRUE(r.active);
    const Vec3 total = r.force_on_thumb + r.force_on_index + sum_of_particle_forces(r);
    EXPECT_NEAR(total.norm(), 0.0, 1e-13);
  }
}

TEST(Grasp, EachPadTakesTheReactionOfTheParticlesOnItsSide) {
  // The patch lies 0.1 mm on the thumb's side of the contact plane: the particles are pulled
  // up onto it (by the hold law as a whole), and only the thumb's pad pushes them.
  for (const double offset : {-1e-4, 1e-4}) {
    Pinch pinch;
    for (Vec3& x : pinch.particles) x.z() += offset;
    const GraspResult r = pinch.step();
    ASSERT_TRUE(r.active);
    const double pull = pawluk_howe_newtons(0.1);
    const double n = r.squeeze_force;
    EXPECT_NEAR((sum_of_particle_forces(r) - Vec3(0, 0, -std::copysign(pull, offset))).norm(), 0.0, 1e-12);
    const Vec3 thumb = offset < 0.0 ? Vec3(0, 0, -n - pull) : Vec3(0, 0, -n);
    const Vec3 index = offset < 0.0 ? Vec3(0, 0, n) : Vec3(0, 0, n + pull);
    EXPECT_NEAR((r.force_on_thumb - thumb).norm(), 0.0, 1e-12) << offset;
    EXPECT_NEAR((r.force_on_index - index).norm(), 0.0, 1e-12) << offset;
  }
}

TEST(Grasp, HeldParticlesStayPutUntilMuSTimesTheSqueezeThenSlideAtMuK) {
  Pinch pinch;
  GraspResult r = pinch.step();
  ASSERT_TRUE(r.active);
  std::vector<Vec2> start;
  for (const HeldParticle& h : r.held) start.push_back(h.anchor);
  const std::vector<Vec3> rest = pinch.particles;
  const double n = r.squeeze_force, mu_s = pinch.params.static_friction, mu_k = pinch.params.kinetic_friction;

  // The hanging fabric pulls the patch along x, 2 µm a step.
  double max_stick = 0.0, pulled = 0.0;
  for (int i = 1; i < 2000; ++i) {
    pulled = 2e-6 * i;
    for (std::size_t k = 0; k < rest.size(); ++k) pinch.particles[k] = rest[k] + Vec3(pulled, 0, 0);
    r = pinch.step();
    ASSERT_TRUE(r.active);
    if (r.friction == FrictionState::slip) break;
    for (std::size_t k = 0; k < r.held.size(); ++k) EXPECT_EQ(r.held[k].anchor, start[k]);  // held in place
    // Every particle is pulled back by its share of the hold law: the patch by the whole law.
    EXPECT_NEAR(r.tangential_load, pawluk_howe_newtons(pulled * 1e3), 1e-9);
    EXPECT_LT(sum_of_particle_forces(r).x(), 0.0);
    max_stick = r.tangential_load;
  }
  ASSERT_EQ(r.friction, FrictionState::slip);
  EXPECT_NEAR(max_stick, mu_s * n, 0.02 * mu_s * n);
  EXPECT_NEAR(r.tangential_load, mu_k * n, 1e-6 * mu_k * n);
  EXPECT_GT(r.held[0].anchor.x(), start[0].x());  // re-anchored along the pull

  // Pulled on: it slides, the load stays at μ_k·F^N, the targets trail the fabric.
  for (int i = 1; i <= 200; ++i) {
    for (std::size_t k = 0; k < rest.size(); ++k) pinch.particles[k] = rest[k] + Vec3(pulled + 2e-6 * i, 0, 0);
    r = pinch.step();
    ASSERT_TRUE(r.active);
    EXPECT_EQ(r.friction, FrictionState::slip);
    EXPECT_NEAR(r.tangential_load, mu_k * n, 1e-6 * mu_k * n);
  }
  // The fingers are dragged along the pull.
  EXPECT_GT(r.force_on_thumb.x(), 0.0);
  EXPECT_NEAR(r.force_on_thumb.x(), r.force_on_index.x(), 1e-12);
  // Let go of the pull: the load falls and it sticks.
  for (std::size_t k = 0; k < rest.size(); ++k) pinch.particles[k] -= Vec3(1e-4, 0, 0);
  r = pinch.step();
  EXPECT_EQ(r.friction, FrictionState::stick);
}

TEST(Grasp, HeldParticlesMoveWithTheFingers) {
  Pinch pinch;
  GraspResult r = pinch.step();
  ASSERT_TRUE(r.active);
  std::vector<Vec3> targets;
  for (const HeldParticle& h : r.held) targets.push_back(h.target);
  const Pose thumb0 = pinch.thumb, index0 = pinch.index;
  const std::vector<Vec3> rest = pinch.particles;
  // Hand and fabric turn 40° and move 2 cm together.
  for (int i = 1; i <= 100; ++i) {
    const double s = i / 100.0;
    Rigid m;
    m.q = Quat(Eigen::AngleAxisd(s * 40.0 * kPi / 180.0, Vec3(1, 2, 3).normalized()));
    m.t = s * Vec3(0.02, -0.01, 0.005);
    pinch.thumb = m.pose(thumb0);
    pinch.index = m.pose(index0);
    for (std::size_t k = 0; k < rest.size(); ++k) pinch.particles[k] = m.point(rest[k]);
    r = pinch.step();
    ASSERT_TRUE(r.active);
    EXPECT_EQ(r.friction, FrictionState::stick);
    for (std::size_t k = 0; k < r.held.size(); ++k)
      EXPECT_NEAR((r.held[k].target - m.point(targets[k])).norm(), 0.0, 1e-12);
    EXPECT_LT(sum_of_particle_forces(r).norm(), 1e-9);
  }
}

void expect_right_handed_orthonormal(const SharedFrame& f) {
  EXPECT_NEAR((f.axes.transpose() * f.axes - Mat3::Identity()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(f.axes.determinant(), 1.0, 1e-12);
  EXPECT_NEAR((f.axes.col(0).cross(f.axes.col(1)) - f.axes.col(2)).norm(), 0.0, 1e-12);
}

TEST(SharedFrame, RightHandedOrthonormalAndAlongThePadsIntersection) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const GraspParams p = pinch_params();
  int wedges = 0;
  for (int trial = 0; trial < 500; ++trial) {
    Pose thumb, index;
    thumb.position = 0.01 * Vec3(u(rng), u(rng), u(rng));
    thumb.orientation = Quat(Eigen::AngleAxisd(kPi * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
    // The index roughly facing the thumb's pad, turned by up to ~35°.
    const Vec3 nt = pad_normal(p.thumb, thumb);
    index.position = thumb.position + 0.016 * nt + 0.004 * Vec3(u(rng), u(rng), u(rng));
    index.orientation = Quat(Eigen::AngleAxisd(0.6 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized())) *
                        thumb.orientation * Quat(Eigen::AngleAxisd(kPi * u(rng), Vec3::UnitZ()));
    const SharedFrame f = shared_frame(p.thumb, thumb, p.index, index, std::sin(10.0 * kPi / 180.0));
    expect_right_handed_orthonormal(f);
    const Vec3 ni = pad_normal(p.index, index);
    // e3 bisects the pads: as much along the thumb's pad normal as against the index's.
    EXPECT_NEAR(f.normal().dot(nt), -f.normal().dot(ni), 1e-12);
    EXPECT_GT(f.normal().dot(index.position - thumb.position), 0.0);  // from the thumb toward the index
    if (f.parallel) continue;
    ++wedges;
    EXPECT_NEAR(f.axes.col(0).dot(nt), 0.0, 1e-12);  // along both pad planes
    EXPECT_NEAR(f.axes.col(0).dot(ni), 0.0, 1e-12);
    // A point on both pad planes (their intersection line) lies in the contact plane. Each
    // pad plane touches its capsule on the pad side: n·x = n·(axis point) + r.
    const double ot = nt.dot(thumb.to_world(p.thumb.base)) + kRadius;
    const double oi = ni.dot(index.to_world(p.index.base)) + kRadius;
    Eigen::Matrix<double, 2, 3> a;
    a.row(0) = nt.transpose();
    a.row(1) = ni.transpose();
    const Vec3 on_line = a.transpose() * (a * a.transpose()).inverse() * Eigen::Vector2d(ot, oi);
    EXPECT_NEAR(f.normal().dot(on_line - f.origin), 0.0, 1e-9);
  }
  EXPECT_GT(wedges, 100);
}

TEST(SharedFrame, ParallelFingersUseTheThumbAxis) {
  const GraspParams p = pinch_params();
  const double threshold = std::sin(10.0 * kPi / 180.0);
  Pose thumb, index;
  thumb.position = Vec3(0, 0, -0.008);
  index.position = Vec3(0.001, 0.002, 0.008);
  // Side by side, pointing the same way.
  SharedFrame f = shared_frame(p.thumb, thumb, p.index, index, threshold);
  expect_right_handed_orthonormal(f);
  EXPECT_TRUE(f.parallel);
  EXPECT_EQ(f.pad_sine, 0.0);
  EXPECT_NEAR((f.axes.col(0) - Vec3::UnitX()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((f.normal() - Vec3::UnitZ()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(f.origin.z(), 0.0, 1e-12);  // midway between the pads
  // Pointing opposite ways (index turned 180° about its pad normal), and crossed.
  index.orientation = Quat(Eigen::AngleAxisd(kPi, Vec3::UnitZ()));
  f = shared_frame(p.thumb, thumb, p.index, index, threshold);
  expect_right_handed_orthonormal(f);
  EXPECT_NEAR((f.axes.col(0) - Vec3::UnitX()).norm(), 0.0, 1e-12);
  index.orientation = Quat(Eigen::AngleAxisd(0.5 * kPi, Vec3::UnitZ()));
  f = shared_frame(p.thumb, thumb, p.index, index, threshold);
  EXPECT_TRUE(f.parallel);
  EXPECT_NEAR((f.axes.col(0) - Vec3::UnitX()).norm(), 0.0, 1e-12);
  // Both pads facing the same way (+x: no pinch) and the thumb pointing up at the index
  // above it: e3 falls back on the capsules' normal, +z, which is the thumb's axis, so e1
  // comes from the index's axis (y); with the index upright too, from anything across e3.
  CapsuleShape upright = p.thumb, across = p.index;
  upright.base = Vec3(0, 0, -0.006);
  upright.tip = Vec3(0, 0, 0.006);
  upright.pad_normal = Vec3::UnitX();
  across.base = Vec3(0, -0.006, 0);
  across.tip = Vec3(0, 0.006, 0);
  across.pad_normal = Vec3::UnitX();
  Pose above;
  above.position = Vec3(0, 0, 0.02);
  f = shared_frame(upright, Pose{}, across, above, threshold);
  expect_right_handed_orthonormal(f);
  EXPECT_NEAR((f.normal() - Vec3::UnitZ()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((f.axes.col(0) - Vec3::UnitY()).norm(), 0.0, 1e-12);
  f = shared_frame(upright, Pose{}, upright, above, threshold);
  expect_right_handed_orthonormal(f);
  EXPECT_NEAR((f.normal() - Vec3::UnitZ()).norm(), 0.0, 1e-12);
}

TEST(Grasp, TargetsStayContinuousWhenTheFrameChangesRule) {
  // The index pad starts tilted 14° about y (a wedge: e1 along y), beyond the 10° threshold,
  // and turns flat (parallel rule: e1 along x). Without carrying the targets over, a 90°
  // turn of the frame would move the held particles' targets by millimetres.
  Pinch pinch(0.3e-3);
  // Friction high enough that nothing slips: a slip moves the targets on purpose.
  pinch.params.static_friction = pinch.params.kinetic_friction = 50.0;
  pinch.grasp = Grasp(pinch.params);
  const Pose index0 = pinch.index;
  const auto tilted = [&](double deg) {
    Pose p = index0;
    p.orientation = Quat(Eigen::AngleAxisd(deg * kPi / 180.0, Vec3::UnitY()));
    return p;
  };
  pinch.index = tilted(14.0);
  GraspResult r = pinch.step();
  ASSERT_TRUE(r.active);
  EXPECT_FALSE(r.frame.parallel);
  // The largest step of any particle's target between consecutive updates.
  std::vector<std::pair<std::int32_t, Vec3>> previous;
  double worst = 0.0;
  const auto track = [&](const GraspResult& now) {
    for (const HeldParticle& h : now.held)
      for (const auto& [index, target] : previous)
        if (index == h.index) worst = std::max(worst, (h.target - target).norm());
    previous.clear();
    for (const HeldParticle& h : now.held) previous.emplace_back(h.index, h.target);
  };
  track(r);
  bool switched = false;
  for (int i = 1; i <= 280; ++i) {
    pinch.index = tilted(14.0 - 0.05 * i);
    r = pinch.step();
    ASSERT_TRUE(r.active);
    ASSERT_EQ(r.friction, FrictionState::stick);
    switched = switched || r.frame.parallel;
    track(r);
  }
  EXPECT_TRUE(switched);
  EXPECT_LT(worst, 2e-5);  // the pads' own motion per step, not a turn of the frame
  // Back past 1.5 × the threshold (15°): the rule switches back, still continuously.
  for (int i = 1; i <= 400; ++i) {
    pinch.index = tilted(0.05 * i);
    r = pinch.step();
    ASSERT_TRUE(r.active);
    if (i == 250) {
      EXPECT_TRUE(r.frame.parallel);  // 12.5°: hysteresis keeps the parallel rule
    }
    track(r);
  }
  EXPECT_FALSE(r.frame.parallel);
  EXPECT_LT(worst, 2e-5);
}

TEST(Grasp, LetsGoWhenThePadsOpenOrNothingIsCaught) {
  Pinch pinch;
  ASSERT_TRUE(pinch.step().active);
  pinch.index.position.z() += 1e-3;  // the pads part
  GraspResult r = pinch.step();
  EXPECT_FALSE(r.active);
  EXPECT_TRUE(r.held.empty());
  EXPECT_EQ(r.force_on_thumb, Vec3::Zero());
  EXPECT_FALSE(pinch.state.active);
  // Squeezing with the fabric elsewhere (fingers touching directly): not a grasp.
  Pinch beside;
  for (Vec3& x : beside.particles) x += Vec3(0.05, 0, 0);
  EXPECT_FALSE(beside.step().active);
}

TEST(Grasp, FullHeldListIgnoresTheRestAndUpdatesAllocateNothing) {
  Pinch pinch;
  GraspParams small = pinch.params;
  small.max_particles = 10;
  const Grasp grasp(small);
  GraspState state = grasp.make_state();
  const GraspResult r = grasp.update(state, pinch.thumb, pinch.index, pinch.particles, pinch.candidates);
  EXPECT_EQ(r.held.size(), 10u);
  EXPECT_EQ(r.ignored, static_cast<int>(pinch.particles.size()) - 10);

  (void)pinch.step();
  const std::vector<Vec3> rest = pinch.particles;
  const tactus::testing::AllocationCounter counter;
  double sum = 0.0;
  for (int i = 0; i < 500; ++i) {
    for (std::size_t k = 0; k < rest.size(); ++k) pinch.particles[k] = rest[k] + Vec3(4e-6 * i, 0, 0);
    pinch.index.position.z() = kRadius + 1e-4 * std::sin(0.05 * i);  // the pads part and close again
    sum += pinch.step().tangential_load;
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(sum, 0.0);
}

TEST(Grasp, RejectsBadParametersAndInput) {
  GraspParams p = pinch_params();
  p.kinetic_friction = 1.5;
  EXPECT_THROW(Grasp{p}, InputError);
  p = pinch_params();
  p.max_particles = 0;
  EXPECT_THROW(Grasp{p}, InputError);
  p = pinch_params();
  p.index.pad_normal = Vec3(1, 0, 0);  // along the axis
  EXPECT_THROW(Grasp{p}, InputError);
  p = pinch_params();
  p.fabric_thickness = -1e-3;
  EXPECT_THROW(Grasp{p}, InputError);

  Pinch pinch;
  (void)pinch.step();
  pinch.thumb.orientation.coeffs().setConstant(std::numeric_limits<double>::quiet_NaN());
  const GraspResult r = pinch.step();
  EXPECT_TRUE(r.input_rejected);
  EXPECT_TRUE(pinch.state.active);  // left as it was
}

TEST(PointGrasp, HoldsThePointAtItsProjectionSticksThenSlidesAtMuK) {
  const GraspParams params = pinch_params();
  const double k = 190.0;
  const PointGrasp grasp(params, k);
  PointGraspState state;
  const double squeeze_mm = 0.8, gap = params.fabric_thickness - 0.8e-3;
  Pose thumb, index;
  thumb.position = Vec3(0, 0, -(kRadius + 0.5 * gap));
  index.position = Vec3(0, 0, kRadius + 0.5 * gap);
  const Vec3 point(0.001, 0.0, 0.0002);  // 0.2 mm above the contact plane z = 0

  // Not started without the caller's word that the fabric lies between the pads.
  EXPECT_FALSE(grasp.update(state, thumb, index, point, false).active);
  PointGraspResult r = grasp.update(state, thumb, index, point, true);
  ASSERT_TRUE(r.active);
  const double fn = pawluk_howe_newtons(squeeze_mm);
  EXPECT_NEAR(r.squeeze_force, fn, 1e-9 * fn);
  EXPECT_NEAR((r.target - Vec3(0.001, 0.0, 0.0)).norm(), 0.0, 1e-12);  // its projection
  EXPECT_NEAR((r.hold - Vec3(0, 0, -k * 0.0002)).norm(), 0.0, 1e-12);  // pulled into the plane
  EXPECT_NEAR((r.force_on_thumb + r.force_on_index + r.hold).norm(), 0.0, 1e-12);  // balance
  EXPECT_EQ(r.friction, FrictionState::stick);

  // The fingers move along x while the fabric stays: the target rides with them, the pull
  // grows as k·offset up to μ_s·F^N, then the pinch slips and pulls with μ_k·F^N.
  const double stick_limit = params.static_friction * fn / k;  // [m]
  double moved = 0.0;
  for (; moved < 0.5 * stick_limit; moved += 1e-5) {
    Pose t = thumb, i = index;
    t.position.x() += moved;
    i.position.x() += moved;
    r = grasp.update(state, t, i, point, true);
    ASSERT_EQ(r.friction, FrictionState::stick) << moved;
    EXPECT_NEAR(r.hold.x(), k * moved, 1e-9);
  }
  for (; r.friction == FrictionState::stick && moved < 3.0 * stick_limit; moved += 1e-5) {
    Pose t = thumb, i = index;
    t.position.x() += moved;
    i.position.x() += moved;
    r = grasp.update(state, t, i, point, true);
  }
  ASSERT_EQ(r.friction, FrictionState::slip);
  EXPECT_NEAR(r.hold.x(), params.kinetic_friction * fn, 1e-9);
  EXPECT_GT(moved, stick_limit * (1.0 - 1e-3));

  // Holding another point with the same pull (a slipping pinch moves on to new material).
  const Vec3 other = point + Vec3(0.002, 0.0, 0.0);
  PointGrasp::move_hold(state, point, other);
  Pose t = thumb, i = index;
  t.position.x() += moved;
  i.position.x() += moved;
  const PointGraspResult carried = grasp.update(state, t, i, other, true);
  EXPECT_NEAR((carried.hold - r.hold).norm(), 0.0, 1e-9);

  // Across the plane the hold is bounded by the squeeze: with the pads barely closing and the
  // point 5 mm off the plane (k·5 mm = 0.95 N), the pull into the plane is F^N.
  {
    PointGraspState light;
    Pose lt = thumb, li = index;
    lt.position.z() -= 0.5 * 0.75e-3;  // the gap grows by 0.75 mm: depth 0.05 mm
    li.position.z() += 0.5 * 0.75e-3;
    const PointGraspResult bounded = grasp.update(light, lt, li, Vec3(0.001, 0.0, 0.005), true);
    ASSERT_TRUE(bounded.active);
    const double squeeze = pawluk_howe_newtons(0.05);
    EXPECT_NEAR(bounded.squeeze_force, squeeze, 1e-9 * squeeze);
    EXPECT_NEAR(bounded.hold.z(), -squeeze, 1e-12);
  }

  // The pads open: it lets go.
  t.position.z() -= 1e-3;
  EXPECT_FALSE(grasp.update(state, t, i, other, true).active);
  EXPECT_FALSE(state.active);
  EXPECT_THROW(PointGrasp(params, 0.0), InputError);
}

}  // namespace
}  // namespace tactus::contact
