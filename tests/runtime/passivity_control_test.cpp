// The contact's passivity observer and controller (haptics/passivity_control.hpp): it takes
// out of a press-and-release what an active contact would return beyond what went in, and it
// only ever weakens the part of the force along the hand's motion.
#include "haptics/passivity_control.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <string>

#include "report/report.hpp"
#include "runtime/session.hpp"
#include "scene/scene.hpp"

namespace tactus::runtime {
using haptics::PassivityControl;
namespace {

constexpr double kDt = 1e-3;
constexpr double kStiffness = 2000.0;  // [N/m]

/// A contact that pushes back harder while the hand withdraws than while it presses (by
/// `gain`), as a local model can at its updates; the surface at z = 0, the force along +z.
Vec3 active_spring(double z, double vz, double gain) {
  if (z >= 0.0) return Vec3::Zero();
  return Vec3(0.0, 0.0, kStiffness * -z * (vz > 0.0 ? gain : 1.0));
}

struct Cycle {
  double work = 0.0;    ///< net work of the rendered force on the hand [J]
  double stored = 0.0;  ///< largest stored energy ½·F²/k [J]
};

/// The hand presses 5 mm at 20 mm/s, holds 0.1 s and withdraws at the same speed.
Cycle press_and_release(double gain, bool control) {
  PassivityControl pc(control);
  Cycle c;
  Vec3 last_position(0.0, 0.0, 0.002), last_force = Vec3::Zero();
  const double speed = 0.02, depth = 0.005;
  const double t_in = (0.002 + depth) / speed, t_hold = t_in + 0.1, t_end = t_hold + t_in + 0.05;
  for (double t = 0.0; t < t_end; t += kDt) {
    double z = 0.0, vz = 0.0;
    if (t < t_in) z = 0.002 - speed * t, vz = -speed;
    else if (t < t_hold) z = -depth;
    else z = -depth + speed * (t - t_hold), vz = speed;
    const Vec3 position(0.0, 0.0, z), velocity(0.0, 0.0, vz);
    c.work += last_force.dot(position - last_position);
    const Vec3 model = active_spring(z, vz, gain);
    const Vec3 force = pc.apply(model, model.z() > 0.0, position, velocity, kDt);
    c.stored = std::max(c.stored, 0.5 * model.squaredNorm() / kStiffness);
    last_force = force;
    last_position = position;
  }
  return c;
}

TEST(PassivityControl, TakesOutWhatAnActiveContactWouldReturn) {
  // 5% more force on the way out: about 5% of the stored energy returned beyond what went in.
  const Cycle raw = press_and_release(1.05, false), controlled = press_and_release(1.05, true);
  EXPECT_GT(raw.work, 0.04 * raw.stored);
  // The observer sees a frame's work after the fact, so the controlled cycle may return at
  // most one frame's worth beyond what went in: the largest F·v·dt, at full depth.
  const double one_frame = kStiffness * 0.005 * 1.05 * 0.02 * kDt;
  EXPECT_LT(controlled.work, one_frame);
  EXPECT_LT(controlled.work, 0.1 * raw.work);
}

TEST(PassivityControl, LeavesAPassiveContactAlone) {
  // A contact weaker on the way out (it absorbs energy) is never touched.
  const Cycle raw = press_and_release(0.9, false), controlled = press_and_release(0.9, true);
  EXPECT_LT(raw.work, 0.0);
  EXPECT_EQ(controlled.work, raw.work);
}

TEST(PassivityControl, OnlyWeakensThePartOfTheForceAlongTheMotion) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  PassivityControl pc(true);
  Vec3 position = Vec3::Zero();
  int acted = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 force(n(rng), n(rng), n(rng)), velocity = 0.01 * Vec3(n(rng), n(rng), n(rng));
    position += velocity * kDt;
    const Vec3 out = pc.apply(force, true, position, velocity, kDt);
    const Vec3 removed = force - out;
    if (removed.norm() > 0.0) ++acted;
    // What is taken away lies along the motion and is at most the force's part along it.
    const Vec3 along = velocity.normalized();
    EXPECT_NEAR(removed.cross(along).norm(), 0.0, 1e-12);
    EXPECT_GE(removed.dot(along), -1e-15);
    EXPECT_LE(removed.dot(along), std::max(0.0, force.dot(along)) + 1e-12);
    EXPECT_LE(out.norm(), force.norm() + 1e-12);
  }
  EXPECT_GT(acted, 100);  // random forces do net work on the hand, so it did act
}

TEST(PassivityControl, NearAStandstillItDampsNoHarderThanTheDevicesMaxDamping) {
  // A 6 N press holding the hand still while the contact owes the hand energy (a debt of
  // 10 mJ): the measured velocity is noise of about 1 mm/s in every direction. Taking the
  // whole part of the force along it away swung the force about by up to 5.8 N a frame (the
  // liver_cspace scene); a damper of at most max_damping takes b·|v|.
  constexpr double kMaxDamping = 100.0;  // [N·s/m]
  PassivityControl pc(true, kMaxDamping);
  const Vec3 press(0.0, 0.0, 6.0);
  (void)pc.apply(Vec3(0.0, 0.0, 10.0), true, Vec3::Zero(), Vec3::Zero(), kDt);
  (void)pc.apply(press, true, Vec3(0.0, 0.0, 0.001), Vec3::Zero(), kDt);
  ASSERT_NEAR(pc.observed_work(), 0.01, 1e-12);
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, 1e-3 / std::sqrt(3.0));
  Vec3 position(0.0, 0.0, 0.001), last = press;
  double largest_step = 0.0, largest_speed = 0.0;
  int acted = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 velocity(n(rng), n(rng), n(rng));
    position += 1e-7 * velocity.normalized();  // the hand all but still
    const Vec3 out = pc.apply(press, true, position, velocity, kDt);
    const double taken = (press - out).norm();
    if (taken > 0.0) ++acted;
    EXPECT_LE(taken, kMaxDamping * velocity.norm() * (1.0 + 1e-12));
    largest_step = std::max(largest_step, (out - last).norm());
    largest_speed = std::max(largest_speed, velocity.norm());
    last = out;
  }
  EXPECT_GT(acted, 500);  // the debt stands, so it acts whenever the motion is along the press
  // From frame to frame the force moves by at most twice b·|v|: under 1 N here.
  EXPECT_LE(largest_step, 2.0 * kMaxDamping * largest_speed + 1e-12);
  EXPECT_LT(largest_step, 1.0);
}

TEST(PassivityControl, ADebtOutlivesTheContactButACreditDoesNot) {
  PassivityControl pc(true);
  const Vec3 up(0.0, 0.0, 1.0), still = Vec3::Zero();
  // The hand is pushed 1 mm out by 1 N: 1 mJ of debt.
  (void)pc.apply(up, true, Vec3::Zero(), still, kDt);
  (void)pc.apply(Vec3::Zero(), false, Vec3(0.0, 0.0, 0.001), still, kDt);
  EXPECT_NEAR(pc.observed_work(), 1e-3, 1e-12);
  for (int i = 0; i < 100; ++i) (void)pc.apply(Vec3::Zero(), false, Vec3(0.0, 0.0, 0.001), still, kDt);
  EXPECT_NEAR(pc.observed_work(), 1e-3, 1e-12);
  // The next contact pushing the hand out is cut to nothing until the debt is paid (1 N at
  // 20 mm/s: a damper of 50 N·s/m, within the default max_damping of 100).
  const Vec3 out = pc.apply(up, true, Vec3(0.0, 0.0, 0.001), Vec3(0.0, 0.0, 0.02), kDt);
  EXPECT_NEAR(out.z(), 0.0, 1e-12);

  // A credit: the hand pressed 1 mm against 1 N.
  PassivityControl fresh(true);
  (void)fresh.apply(up, true, Vec3::Zero(), still, kDt);
  (void)fresh.apply(up, true, Vec3(0.0, 0.0, -0.001), still, kDt);
  EXPECT_NEAR(fresh.observed_work(), -1e-3, 1e-12);
  // A frame without contact keeps it (the contact has not ended) ...
  (void)fresh.apply(Vec3::Zero(), false, Vec3(0.0, 0.0, -0.001), still, kDt);
  EXPECT_NEAR(fresh.observed_work(), -1e-3, 1e-12);
  // ... 20 ms without contact end it, and the credit with it.
  for (int i = 0; i < 25; ++i) (void)fresh.apply(Vec3::Zero(), false, Vec3(0.0, 0.0, -0.001), still, kDt);
  EXPECT_EQ(fresh.observed_work(), 0.0);
}

TEST(PassivityControl, PassesANonFiniteForceOnToTheSafetyLayerAndOffDoesNothing) {
  PassivityControl pc(true);
  (void)pc.apply(Vec3(0.0, 0.0, 1.0), true, Vec3::Zero(), Vec3::Zero(), kDt);
  (void)pc.apply(Vec3(0.0, 0.0, 1.0), true, Vec3(0.0, 0.0, 0.001), Vec3(0.0, 0.0, 1.0), kDt);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Vec3 out = pc.apply(Vec3(nan, 0.0, 1.0), true, Vec3(0.0, 0.0, 0.002), Vec3(0.0, 0.0, 1.0), kDt);
  EXPECT_TRUE(std::isnan(out.x()));  // the safety layer replaces it by zero and counts it
  // It sent nothing, so it did no work, and the observer still counts afterwards.
  (void)pc.apply(Vec3::Zero(), true, Vec3(nan, 0.0, 0.0), Vec3(0.0, 0.0, 1.0), kDt);  // a glitched pose too
  EXPECT_TRUE(std::isfinite(pc.observed_work()));
  const double before = pc.observed_work();
  (void)pc.apply(Vec3(0.0, 0.0, 1.0), true, Vec3(0.0, 0.0, 0.003), Vec3::Zero(), kDt);
  (void)pc.apply(Vec3(0.0, 0.0, 1.0), true, Vec3(0.0, 0.0, 0.004), Vec3::Zero(), kDt);
  EXPECT_NEAR(pc.observed_work(), before + 1e-3, 1e-12);

  PassivityControl off(false);
  const Vec3 f(0.3, -0.2, 1.0);
  EXPECT_EQ(off.apply(f, true, Vec3::Zero(), Vec3(0.0, 0.0, 1.0), kDt), f);
  EXPECT_EQ(off.observed_work(), 0.0);
}

TEST(PassivityControl, TheRunReportSaysHowOftenItActed) {
  // The stiff press with the default local model: the controller acts at the first touch and
  // late in the release (docs/contact-mechanics.md), and the report says so; switched off,
  // it never does.
  for (const bool on : {true, false}) {
    scene::Model m = scene::load_scene(std::filesystem::path(TACTUS_SOURCE_DIR) / "tests/fixtures/scenes/stiff_press.toml");
    for (scene::Algorithm& a : m.algorithms) a.passivity_control = on;
    SessionOptions o;
    o.scheduling = Scheduling::lockstep;
    const SessionReport r = run_session(m, o);
    ASSERT_EQ(r.devices.size(), 1u);
    const std::string text = report::format_report(r);
    if (on) {
      EXPECT_GT(r.devices[0].passivity_frames, 0u);
      EXPECT_GT(r.devices[0].passivity_energy, 0.0);
      EXPECT_NE(text.find("passivity control " + std::to_string(r.devices[0].passivity_frames) + " frames"), std::string::npos)
          << text;
    } else {
      EXPECT_EQ(r.devices[0].passivity_frames, 0u);
      EXPECT_NE(text.find("passivity control 0 frames (0.000 mJ"), std::string::npos) << text;
    }
  }
}

}  // namespace
}  // namespace tactus::runtime
