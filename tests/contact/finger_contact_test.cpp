// Finger on finger without fabric (seed 002 §V-B, states II and III): the normal force is
// the Pawluk–Howe law written from the seed's own numbers (in mm), the forces are equal and
// opposite, and the Coulomb stick–slip transition and the kinetic force fall where eq. 2
// puts them.
#include "contact/finger_contact.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/counting_allocator.hpp"
#include "core/error.hpp"

namespace tactus::contact {
namespace {

/// Seed 002 eq. 1 with its printed constants, m = 2.1 mm⁻¹ and b = 0.19 N/mm: N for d in mm.
double pawluk_howe_newtons(double depth_mm) { return 0.19 / 2.1 * (std::exp(2.1 * depth_mm) - 1.0); }

CapsuleShape along(const Vec3& axis, double radius = 0.008) {
  CapsuleShape s;
  s.base = -0.006 * axis;
  s.tip = 0.006 * axis;
  s.radius = radius;
  s.pad_normal = axis.unitOrthogonal();
  return s;
}

// Thumb along x at the origin, index along y above it: crossed fingertips.
struct Crossed {
  FingerContactParams params = make_params();
  FingerContact contact{along(Vec3::UnitX()), along(Vec3::UnitY()), params};
  static FingerContactParams make_params() {
    FingerContactParams p;
    p.tangential_stiffness = 2000.0;
    p.static_friction = 1.0;
    p.kinetic_friction = 0.7;
    return p;
  }
  static Pose index_at(double depth, const Vec3& slide = Vec3::Zero()) {
    Pose p;
    p.position = Vec3(0, 0, 0.016 - depth) + slide;
    return p;
  }
};

TEST(FingerContact, NormalForceIsTheFingerpadLawAtTheDepth) {
  const Crossed c;
  for (const double depth_mm : {0.1, 0.5, 1.0, 1.5, 2.5}) {
    FingerContactState state;
    const FingerContactResult r = c.contact.update(state, Pose{}, Crossed::index_at(depth_mm * 1e-3));
    ASSERT_TRUE(r.in_contact);
    EXPECT_NEAR(r.depth, depth_mm * 1e-3, 1e-15);
    EXPECT_NEAR(r.normal_force, pawluk_howe_newtons(depth_mm), 1e-12 * pawluk_howe_newtons(depth_mm));
    EXPECT_NEAR((r.normal - Vec3::UnitZ()).norm(), 0.0, 1e-12);
    EXPECT_NEAR((r.force_on_index - r.normal_force * Vec3::UnitZ()).norm(), 0.0, 1e-12);  // no slide yet
    EXPECT_EQ(r.friction, FrictionState::stick);
  }
  FingerContactState state;
  const FingerContactResult apart = c.contact.update(state, Pose{}, Crossed::index_at(-1e-4));
  EXPECT_FALSE(apart.in_contact);
  EXPECT_EQ(apart.force_on_index, Vec3::Zero());
  EXPECT_FALSE(state.in_contact);
}

TEST(FingerContact, ForcesAreEqualAndOppositeForArbitraryPoses) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const FingerContact contact(along(Vec3::UnitX()), along(Vec3(0.3, 0.2, 1.0).normalized(), 0.006));
  int touching = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Pose thumb, index;
    thumb.position = 0.005 * Vec3(u(rng), u(rng), u(rng));
    thumb.orientation = Quat(Eigen::AngleAxisd(3.0 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
    index.position = 0.012 * Vec3(u(rng), u(rng), u(rng));
    index.orientation = Quat(Eigen::AngleAxisd(3.0 * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
    FingerContactState state;
    (void)contact.update(state, thumb, index);
    index.position += 0.002 * Vec3(u(rng), u(rng), u(rng));  // a slide, so that friction acts
    const FingerContactResult r = contact.update(state, thumb, index);
    EXPECT_EQ(r.force_on_thumb, (-r.force_on_index).eval());
    if (!r.in_contact) continue;
    ++touching;
    EXPECT_NEAR(r.force_on_index.dot(r.normal), r.normal_force, 1e-9 * (1.0 + r.normal_force));
    EXPECT_LE(r.tangential_force, contact.params().static_friction * r.normal_force * (1.0 + 1e-9) + 1e-12);
  }
  EXPECT_GT(touching, 50);
}

TEST(FingerContact, SticksUntilMuSTimesTheNormalForceThenSlidesAtMuK) {
  const Crossed c;
  const double depth = 1e-3;
  const double fn = pawluk_howe_newtons(1.0);
  const double mu_s = c.params.static_friction, mu_k = c.params.kinetic_friction;
  FingerContactState state;
  (void)c.contact.update(state, Pose{}, Crossed::index_at(depth));

  // Slide the index along the thumb's axis 1 µm a step (2 mN of spring a step).
  double max_stick = 0.0, slide = 0.0;
  FingerContactResult r;
  for (int i = 1; i < 2000; ++i) {
    slide = 1e-6 * i;
    r = c.contact.update(state, Pose{}, Crossed::index_at(depth, Vec3(slide, 0, 0)));
    ASSERT_TRUE(r.in_contact);
    if (r.friction == FrictionState::slip) break;
    max_stick = r.tangential_force;
    // The spring pulls the index back, along −x.
    EXPECT_NEAR(r.force_on_index.x(), -c.params.tangential_stiffness * slide, 1e-9);
  }
  ASSERT_EQ(r.friction, FrictionState::slip);
  EXPECT_NEAR(max_stick, mu_s * fn, 0.02 * mu_s * fn);  // the 2 %
  EXPECT_NEAR(slide, mu_s * fn / c.params.tangential_stiffness, 2e-6);
  EXPECT_NEAR(r.tangential_force, mu_k * fn, 1e-9);

  // Sliding on: the kinetic force, against the motion.
  for (int i = 1; i <= 2000; ++i) {
    r = c.contact.update(state, Pose{}, Crossed::index_at(depth, Vec3(slide + 1e-6 * i, 0, 0)));
    ASSERT_EQ(r.friction, FrictionState::slip);
    EXPECT_NEAR(r.tangential_force, mu_k * fn, 0.02 * mu_k * fn);
    EXPECT_LT(r.force_on_index.x(), 0.0);
  }
  slide += 2e-3;

  // Stopping holds the kinetic force; turning back sticks, through zero, until μ_s·F^N the
  // other way: a reversal of (μ_k + μ_s)·F^N / k.
  r = c.contact.update(state, Pose{}, Crossed::index_at(depth, Vec3(slide, 0, 0)));
  EXPECT_EQ(r.friction, FrictionState::stick);
  double back = 0.0;
  for (int i = 1; i < 4000; ++i) {
    back = 1e-6 * i;
    r = c.contact.update(state, Pose{}, Crossed::index_at(depth, Vec3(slide - back, 0, 0)));
    if (r.friction == FrictionState::slip) break;
  }
  EXPECT_NEAR(back, (mu_k + mu_s) * fn / c.params.tangential_stiffness, 2e-6);
  EXPECT_GT(r.force_on_index.x(), 0.0);
}

TEST(FingerContact, SlidingAlongTheIndexAxisDragsToo) {
  // The anchor ties material points: sliding the index along its own axis (the contact point
  // on it moves, the one on the thumb does not) still stretches the spring.
  const Crossed c;
  FingerContactState state;
  (void)c.contact.update(state, Pose{}, Crossed::index_at(1e-3));
  const FingerContactResult r = c.contact.update(state, Pose{}, Crossed::index_at(1e-3, Vec3(0, 1e-4, 0)));
  EXPECT_EQ(r.friction, FrictionState::stick);
  EXPECT_NEAR(r.force_on_index.y(), -c.params.tangential_stiffness * 1e-4, 1e-9);
}

TEST(FingerContact, ThumbMovingUnderAStillIndexIsTheSameAsTheReverse) {
  // Only relative motion matters: the thumb sliding −x gives the index the same force as
  // the index sliding +x.
  const Crossed c;
  FingerContactState a, b;
  (void)c.contact.update(a, Pose{}, Crossed::index_at(1e-3));
  (void)c.contact.update(b, Pose{}, Crossed::index_at(1e-3));
  Pose thumb;
  thumb.position = Vec3(-1e-4, 0, 0);
  const FingerContactResult ra = c.contact.update(a, thumb, Crossed::index_at(1e-3));
  const FingerContactResult rb = c.contact.update(b, Pose{}, Crossed::index_at(1e-3, Vec3(1e-4, 0, 0)));
  EXPECT_NEAR((ra.force_on_index - rb.force_on_index).norm(), 0.0, 1e-12);
}

TEST(FingerContact, UpdateAllocatesNothingAndRejectsBadInput) {
  const Crossed c;
  FingerContactState state;
  const tactus::testing::AllocationCounter counter;
  double sum = 0.0;
  for (int i = 0; i < 1000; ++i)
    sum += c.contact.update(state, Pose{}, Crossed::index_at(1e-3, Vec3(1e-6 * i, 0, 0))).tangential_force;
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(sum, 0.0);

  Pose bad;
  bad.position.x() = std::numeric_limits<double>::quiet_NaN();
  const FingerContactResult r = c.contact.update(state, bad, Crossed::index_at(1e-3));
  EXPECT_FALSE(r.in_contact);
  EXPECT_TRUE(state.in_contact);  // left as it was

  FingerContactParams p;
  p.kinetic_friction = 2.0;  // above μ_s
  EXPECT_THROW(FingerContact(along(Vec3::UnitX()), along(Vec3::UnitY()), p), InputError);
  p = FingerContactParams{};
  p.tangential_stiffness = 0.0;
  EXPECT_THROW(FingerContact(along(Vec3::UnitX()), along(Vec3::UnitY()), p), InputError);
  p = FingerContactParams{};
  p.normal_law.m = -1.0;
  EXPECT_THROW(FingerContact(along(Vec3::UnitX()), along(Vec3::UnitY()), p), InputError);
}

}  // namespace
}  // namespace tactus::contact
