// The V-proxy (seed 002 §V-C) of a capsule finger on a thin fabric patch: the spring force
// at a set depth, stick below μ_s·F^N and the kinetic force above it, the proxy never
// crossing to the other side however far or fast the finger goes, loads on the fabric that
// balance the finger's force, fabric that carries a resting proxy, and passivity: over
// closed loops the contact force does no net work on the finger.
#include "contact/fabric_proxy.hpp"

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
constexpr double kDt = 1e-3;

/// A square patch in z = 0, `cells` × `cells` squares over [−half, half]², each split in
/// two triangles counter-clockwise seen from +z (front normals +z).
struct Patch {
  std::vector<Vec3> positions;
  std::vector<mesh::Triangle> triangles;
  std::vector<std::int32_t> all;
};

Patch flat_patch(double half = 0.03, int cells = 12) {
  Patch p;
  const int n = cells + 1;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      p.positions.emplace_back(-half + 2.0 * half * i / cells, -half + 2.0 * half * j / cells, 0.0);
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      const std::int32_t a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
      p.triangles.push_back({a, b, c});
      p.triangles.push_back({a, c, d});
    }
  for (std::size_t t = 0; t < p.triangles.size(); ++t) p.all.push_back(static_cast<std::int32_t>(t));
  return p;
}

CapsuleShape lying_finger() {
  CapsuleShape s;
  s.base = Vec3(-0.006, 0, 0);
  s.tip = Vec3(0.006, 0, 0);
  s.radius = 0.008;
  return s;
}

FabricProxyParams params_for(int side = +1, double mu_s = 0.5, double mu_k = 0.4) {
  FabricProxyParams p;
  p.finger = lying_finger();
  p.side = side;
  p.stiffness = 1000.0;
  p.static_friction = mu_s;
  p.kinetic_friction = mu_k;
  return p;
}

Pose at(const Vec3& position, const Quat& orientation = Quat::Identity()) {
  Pose p;
  p.position = position;
  p.orientation = orientation;
  return p;
}

/// Lowest point of the capsule at `pose` along z: how far it reaches below z = 0 is the depth.
double lowest_z(const CapsuleShape& s, const Pose& pose) {
  return std::min(pose.to_world(s.base).z(), pose.to_world(s.tip).z()) - s.radius;
}

struct Touch {
  FabricProxy proxy;
  FabricProxyState state;
  Patch patch;
  explicit Touch(const FabricProxyParams& p, const Vec3& start = Vec3(0, 0, 0.02), Patch fabric = flat_patch())
      : proxy(p), state(make_fabric_proxy_state(start)), patch(std::move(fabric)) {}
  FabricProxyResult step(const Pose& finger) {
    return proxy.update(state, finger, patch.positions, patch.triangles, patch.all, kDt);
  }
  /// Moves the finger in a straight line to `to` over `steps` updates.
  FabricProxyResult move(const Vec3& from, const Vec3& to, int steps, const Quat& q = Quat::Identity()) {
    FabricProxyResult r;
    for (int i = 1; i <= steps; ++i) r = step(at(from + (static_cast<double>(i) / steps) * (to - from), q));
    return r;
  }
};

TEST(FabricProxy, PressingByOneMillimetreGivesStiffnessTimesDepthAlongTheNormal) {
  const double r = lying_finger().radius;
  Touch run(params_for());
  const FabricProxyResult free = run.move(Vec3(0, 0, 0.02), Vec3(0, 0, r + 1e-3), 20);
  EXPECT_FALSE(free.in_contact);
  EXPECT_EQ(free.force, Vec3::Zero());
  const FabricProxyResult pressed = run.move(Vec3(0, 0, r + 1e-3), Vec3(0, 0, r - 1e-3), 20);
  ASSERT_TRUE(pressed.in_contact);
  EXPECT_NEAR(pressed.depth, 1e-3, 1e-12);
  EXPECT_NEAR((pressed.force - Vec3(0, 0, 1000.0 * 1e-3)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((pressed.contact_normal - Vec3::UnitZ()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(pressed.contact_point.z(), 0.0, 1e-15);
  EXPECT_NEAR(pressed.proxy.z(), r, 1e-12);  // resting on the fabric

  // A finger tilted 30° about y pressing with its tip: the depth is how far its lowest point
  // is below the fabric.
  const Quat tilt(Eigen::AngleAxisd(30.0 * kPi / 180.0, Vec3::UnitY()));
  Touch tilted(params_for());
  Pose touch = at(Vec3(0.002, 0.001, 0.02), tilt);
  touch.position.z() -= lowest_z(lying_finger(), touch);  // just touching
  (void)tilted.move(Vec3(0.002, 0.001, 0.03), touch.position + Vec3(0, 0, 1e-3), 10, tilt);
  const Vec3 pressed_at = touch.position - Vec3(0, 0, 1e-3);
  const FabricProxyResult t = tilted.move(touch.position + Vec3(0, 0, 1e-3), pressed_at, 20, tilt);
  ASSERT_TRUE(t.in_contact);
  EXPECT_NEAR(-lowest_z(lying_finger(), at(pressed_at, tilt)), 1e-3, 1e-12);
  EXPECT_NEAR((t.force - Vec3(0, 0, 1.0)).norm(), 0.0, 1e-9);
}

TEST(FabricProxy, SticksBelowMuSThenSlidesWithTheKineticForce) {
  const double r = lying_finger().radius, depth = 1e-3;
  const FabricProxyParams p = params_for();
  Touch run(p);
  (void)run.move(Vec3(0, 0, 0.02), Vec3(0, 0, r - depth), 20);
  const Vec3 rest = run.state.position;
  const double fn = p.stiffness * depth;

  // Pull along x at 5 mm/s: 5 µm, 5 mN a step.
  const double speed = 5e-3;
  double max_stick = 0.0, pulled = 0.0;
  FabricProxyResult res;
  for (int i = 1; i < 1000; ++i) {
    pulled = speed * kDt * i;
    res = run.step(at(Vec3(pulled, 0, r - depth)));
    ASSERT_TRUE(res.in_contact);
    if (res.friction == FrictionState::slip) break;
    EXPECT_EQ(run.state.position, rest);  // the proxy does not move
    EXPECT_NEAR(res.force.x(), -p.stiffness * pulled, 1e-9);
    max_stick = res.tangential_force;
  }
  ASSERT_EQ(res.friction, FrictionState::slip);
  EXPECT_NEAR(max_stick, p.static_friction * fn, 0.02 * p.static_friction * fn);

  // Sliding on for a second: after the start-up, the tangential force is μ_k·F^N (plus b·v,
  // 0.5 % here), and the proxy keeps pace with the finger.
  for (int i = 1; i <= 1000; ++i) {
    res = run.step(at(Vec3(pulled + speed * kDt * i, 0, r - depth)));
    ASSERT_TRUE(res.in_contact);
    if (i < 100) continue;
    EXPECT_EQ(res.friction, FrictionState::slip) << i;
    EXPECT_NEAR(res.tangential_force, p.kinetic_friction * fn, 0.02 * p.kinetic_friction * fn) << i;
    EXPECT_LT(res.force.x(), 0.0);
    EXPECT_NEAR(res.normal_force, fn, 1e-9);
    EXPECT_NEAR(run.state.velocity.x(), speed, 0.02 * speed) << i;
  }
  // Stopping: the proxy comes to rest and sticks.
  for (int i = 0; i < 200; ++i) res = run.step(at(Vec3(pulled + speed, 0, r - depth)));
  EXPECT_EQ(res.friction, FrictionState::stick);
  EXPECT_LE(res.tangential_force, p.kinetic_friction * fn * (1.0 + 1e-9));
}

TEST(FabricProxy, NeverCrossesToTheOtherSide) {
  const double r = lying_finger().radius;
  for (const int side : {+1, -1}) {
    const double s = side;
    // The thumb comes from the front (+z), the index from the back (−z).
    Touch run(params_for(side), Vec3(0, 0, s * 0.02));
    // One step from just in front to 5 cm behind: far more than the finger's thickness.
    (void)run.move(Vec3(0, 0, s * 0.02), Vec3(0, 0, s * (r + 1e-3)), 10);
    FabricProxyResult res = run.step(at(Vec3(0.001, 0, -s * 0.05)));
    ASSERT_TRUE(res.in_contact) << side;
    EXPECT_NEAR(res.proxy.z(), s * r, 1e-12);
    EXPECT_NEAR(res.force.z(), s * 1000.0 * (0.05 + r), 1e-6);
    // Deeper and wandering about behind the fabric: the proxy stays on its side.
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < 500; ++i) {
      res = run.step(at(Vec3(0.01 * u(rng), 0.01 * u(rng), -s * (0.03 + 0.02 * u(rng)))));
      ASSERT_TRUE(res.in_contact);
      EXPECT_GE(s * res.proxy.z(), r - 1e-12) << side << " " << i;
      EXPECT_GT(s * res.force.z(), 0.0);
      EXPECT_NEAR(res.normal_force, 1000.0 * res.depth, 1e-9);
    }
    // Back out: free again, and the proxy follows the finger.
    res = run.move(run.state.position, Vec3(0, 0, s * 0.02), 10);
    EXPECT_FALSE(res.in_contact);
    EXPECT_EQ(res.proxy, Vec3(0, 0, s * 0.02));
  }
  // A finger on the wrong side (the index in front) is not held: it passes through.
  Touch wrong(params_for(-1), Vec3(0, 0, 0.02));
  const FabricProxyResult res = wrong.move(Vec3(0, 0, 0.02), Vec3(0, 0, -0.02), 20);
  EXPECT_FALSE(res.in_contact);
}

TEST(FabricProxy, LoadsOnTheTouchedTriangleBalanceTheFingerForce) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double r = lying_finger().radius;
  Touch run(params_for());
  (void)run.move(Vec3(0, 0, 0.02), Vec3(0, 0, r - 5e-4), 20);
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 xd(0.01 * std::sin(0.003 * i), 0.008 * std::sin(0.005 * i), r - 1e-3 - 5e-4 * u(rng));
    const Quat q(Eigen::AngleAxisd(0.3 * std::sin(0.002 * i), Vec3::UnitZ()));
    const FabricProxyResult res = run.step(at(xd, q));
    ASSERT_TRUE(res.in_contact);
    Vec3 sum = Vec3::Zero();
    for (const Vec3& f : res.vertex_loads) sum += f;
    EXPECT_NEAR((sum + res.force).norm(), 0.0, 1e-14 * (1.0 + res.force.norm()));
    // The loads are on the triangle's own vertices, at the contact point's weights.
    const mesh::Triangle& tri = run.patch.triangles[static_cast<std::size_t>(res.triangle)];
    EXPECT_EQ(res.vertices, tri);
    EXPECT_NEAR(res.barycentric.sum(), 1.0, 1e-12);
    EXPECT_GE(res.barycentric.minCoeff(), -1e-12);
    const Vec3 point = res.barycentric[0] * run.patch.positions[static_cast<std::size_t>(tri[0])] +
                       res.barycentric[1] * run.patch.positions[static_cast<std::size_t>(tri[1])] +
                       res.barycentric[2] * run.patch.positions[static_cast<std::size_t>(tri[2])];
    EXPECT_NEAR((point - res.contact_point).norm(), 0.0, 1e-15);
    // Right under the proxy's capsule, at its radius.
    const Capsule placed = posed(lying_finger(), at(res.proxy, q));
    EXPECT_NEAR(point_capsule(res.contact_point, placed).signed_distance, 0.0, 1e-9);
    ++checked;
  }
  EXPECT_EQ(checked, 2000);
}

TEST(FabricProxy, MovingFabricCarriesAStuckProxyAndPushesIt) {
  const double r = lying_finger().radius;
  Touch run(params_for());
  (void)run.move(Vec3(0, 0, 0.02), Vec3(0, 0, r - 1e-3), 20);
  const Vec3 rest = run.state.position;
  // The fabric drifts 0.2 mm along x (below the 0.5 N the friction holds) and rises 0.3 mm.
  for (Vec3& v : run.patch.positions) v += Vec3(2e-4, 0, 3e-4);
  const FabricProxyResult res = run.step(at(Vec3(0, 0, r - 1e-3)));
  ASSERT_TRUE(res.in_contact);
  EXPECT_EQ(res.friction, FrictionState::stick);
  EXPECT_NEAR((run.state.position - (rest + Vec3(2e-4, 0, 3e-4))).norm(), 0.0, 1e-12);
  EXPECT_NEAR((res.force - Vec3(0.2, 0, 1.3)).norm(), 0.0, 1e-9);
}

TEST(FabricProxy, FabricSlidingPastTheConeUnderAStillFingerPullsItWithTheKineticForce) {
  // A stretched sheet let go springs back under the finger at about a metre a second: 1 mm a
  // frame along x. The proxy slips on it at once and is pulled with μ_k·F^N, every frame in
  // contact; carried with the sheet, it ended millimetres off the finger and lost the sheet.
  const double r = lying_finger().radius, depth = 1e-3;
  const FabricProxyParams p = params_for();
  Touch run(p);
  (void)run.move(Vec3(0, 0, 0.02), Vec3(0, 0, r - depth), 20);
  const double fn = p.stiffness * depth;
  for (int k = 0; k < 10; ++k) {
    for (Vec3& v : run.patch.positions) v.x() += 1e-3;
    const FabricProxyResult res = run.step(at(Vec3(0, 0, r - depth)));
    ASSERT_TRUE(res.in_contact) << "frame " << k;
    EXPECT_EQ(res.friction, FrictionState::slip);
    EXPECT_NEAR(res.normal_force, fn, 1e-9);
    EXPECT_NEAR(res.tangential_force, p.kinetic_friction * fn, 1e-9);
    EXPECT_GT(res.force.x(), 0.0);  // dragged along with the sheet
  }
}

TEST(FabricProxy, LetsGoPastTheEdgeOfTheCandidatesAndIgnoresOthers) {
  const double r = lying_finger().radius;
  Touch run(params_for(+1, 0.0, 0.0));  // frictionless: the proxy follows the finger sideways
  (void)run.move(Vec3(0, 0, 0.02), Vec3(0, 0, r - 1e-3), 20);
  const FabricProxyResult res = run.move(Vec3(0, 0, r - 1e-3), Vec3(0.06, 0, r - 1e-3), 300);
  EXPECT_FALSE(res.in_contact);  // the patch ends at 3 cm (the capsule reaches 1.4 cm)

  // Only the listed candidates count.
  Touch none(params_for());
  none.patch.all.clear();
  EXPECT_FALSE(none.move(Vec3(0, 0, 0.02), Vec3(0, 0, r - 1e-3), 20).in_contact);
  none.patch.all = {-1, 100000};  // out of range: skipped
  EXPECT_FALSE(none.move(Vec3(0, 0, r - 1e-3), Vec3(0, 0, r - 2e-3), 5).in_contact);
}

/// Drives the finger around a closed loop (in, a figure of eight while pressing harder and
/// softer, out, back to the start) and returns the passivity observer's work on the finger,
/// Σ F_{n+1}·(x_{n+1} − x_n) (Hannaford & Ryu 2002), after checking per step that the work
/// plus the change of the energy stored in the coupling (½k|x^p − x^d|² + ½m|ẋ^p|²) is not
/// positive. Also returns the trapezoid-rule work.
struct LoopWork {
  double observer = 0.0;
  double trapezoid = 0.0;
  int contact_steps = 0;
  int slip_steps = 0;
};

LoopWork closed_loop(const FabricProxyParams& p, const Quat& q, int steps) {
  const double top = -lowest_z(p.finger, at(Vec3::Zero(), q)) + 1e-3;  // 1 mm clear of the fabric
  Touch run(p, Vec3(0, 0, top));
  const auto path = [&](int i) {
    const double th = 2.0 * kPi * i / steps;
    return Vec3(0.01 * std::sin(th), 0.006 * std::sin(2.0 * th),
                top - 0.004 * std::pow(std::sin(0.5 * th), 2) * (1.0 + 0.3 * std::sin(3.0 * th)));
  };
  const auto energy = [&](const FabricProxyResult& r, const Vec3& xd) {
    return 0.5 * p.stiffness * (r.proxy - xd).squaredNorm() + 0.5 * p.mass * run.state.velocity.squaredNorm();
  };
  LoopWork w;
  Vec3 x_prev = path(0);
  FabricProxyResult prev = run.step(at(x_prev, q));
  double e_prev = energy(prev, x_prev);
  EXPECT_FALSE(prev.in_contact);
  for (int i = 1; i <= steps; ++i) {
    const Vec3 x = path(i);
    const FabricProxyResult r = run.step(at(x, q));
    const double work = r.force.dot(x - x_prev);
    const double e = energy(r, x);
    EXPECT_LE(work + e - e_prev, 1e-15) << "step " << i;
    w.observer += work;
    w.trapezoid += 0.5 * (prev.force + r.force).dot(x - x_prev);
    w.contact_steps += r.in_contact ? 1 : 0;
    w.slip_steps += r.friction == FrictionState::slip ? 1 : 0;
    x_prev = x;
    prev = r;
    e_prev = e;
  }
  EXPECT_FALSE(prev.in_contact);  // out of contact again, nothing stored
  return w;
}

TEST(FabricProxy, ClosedLoopsDoNoNetWorkOnTheFinger) {
  const Quat tilt(Eigen::AngleAxisd(20.0 * kPi / 180.0, Vec3(0.3, 1.0, 0.0).normalized()));
  for (const bool friction : {true, false})
    for (const int steps : {500, 2000, 8000}) {
      const FabricProxyParams p = friction ? params_for() : params_for(+1, 0.0, 0.0);
      const LoopWork w = closed_loop(p, tilt, steps);
      EXPECT_GT(w.contact_steps, steps / 2);
      EXPECT_GT(w.slip_steps, steps / 10);
      EXPECT_LE(w.observer, 1e-12) << friction << " " << steps;
      // With friction the contact dissipates far more than the trapezoid rule's error.
      if (friction) {
        EXPECT_LT(w.trapezoid, 0.0) << steps;
      }
    }
}

TEST(FabricProxy, UpdateAllocatesNothingAndRejectsBadInput) {
  const double r = lying_finger().radius;
  Touch run(params_for());
  (void)run.move(Vec3(0, 0, 0.02), Vec3(0, 0, r - 1e-3), 20);
  const tactus::testing::AllocationCounter counter;
  double sum = 0.0;
  for (int i = 0; i < 1000; ++i) sum += run.step(at(Vec3(1e-5 * i, 0, r - 1e-3))).tangential_force;
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(sum, 0.0);

  const FabricProxyState before = run.state;
  FabricProxyResult res = run.step(at(Vec3(0, std::numeric_limits<double>::quiet_NaN(), 0)));
  EXPECT_TRUE(res.input_rejected);
  EXPECT_EQ(res.force, Vec3::Zero());
  EXPECT_EQ(run.state.position, before.position);
  res = run.proxy.update(run.state, at(Vec3(0, 0, r - 1e-3)), run.patch.positions, run.patch.triangles,
                         run.patch.all, 0.0);
  EXPECT_TRUE(res.input_rejected);

  FabricProxyParams bad = params_for();
  bad.side = 0;
  EXPECT_THROW(FabricProxy{bad}, InputError);
  bad = params_for(+1, 0.3, 0.4);
  EXPECT_THROW(FabricProxy{bad}, InputError);
  bad = params_for();
  bad.stiffness = -1.0;
  EXPECT_THROW(FabricProxy{bad}, InputError);
  bad = params_for();
  bad.finger.radius = 0.0;
  EXPECT_THROW(FabricProxy{bad}, InputError);
}

}  // namespace
}  // namespace tactus::contact

namespace tactus::contact {
namespace {

TEST(FabricProxy, ASheetThatMovedIntoAFreeFingerIsTouchedAtOnce) {
  // The fabric moved toward the finger between two updates (a simulation step carried it)
  // and now overlaps the free finger on the finger's own side: the finger touches it at once
  // instead of slipping behind it on its next move.
  const Patch patch = flat_patch();
  const FabricProxy proxy(params_for());
  const double r = lying_finger().radius;
  FabricProxyState s = make_fabric_proxy_state(Vec3(0, 0, 0.75 * r));  // 2 mm into the sheet's reach
  const Pose finger{Vec3(0, 0, 0.7 * r), Quat::Identity()};
  const FabricProxyResult out = proxy.update(s, finger, patch.positions, patch.triangles, patch.all, kDt);
  ASSERT_TRUE(out.in_contact);
  EXPECT_NEAR(out.force.z(), 1000.0 * 0.3 * r, 1e-9);
  EXPECT_NEAR(out.force.head<2>().norm(), 0.0, 1e-12);
  // A finger whose axis is already behind the sheet still passes: it came from the back.
  FabricProxyState behind = make_fabric_proxy_state(Vec3(0, 0, -0.001));
  const Pose deeper{Vec3(0, 0, -0.002), Quat::Identity()};
  EXPECT_FALSE(proxy.update(behind, deeper, patch.positions, patch.triangles, patch.all, kDt).in_contact);
}

}  // namespace
}  // namespace tactus::contact
