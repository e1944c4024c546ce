#include "haptics/safety.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

#include "core/error.hpp"

namespace tactus::haptics {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kFrame = 1e-3;

SafetyConfig config() {
  SafetyConfig c;
  c.max_force = 8.0;
  c.max_torque = 0.5;
  c.ramp_time = 0.005;
  c.fade_time = 0.05;
  c.watchdog_timeout = 0.1;
  return c;
}

/// Fresh, free-space input at time t.
SafetyInput input(const Vec3& force, double t, bool contact = false) {
  SafetyInput in;
  in.force = force;
  in.contact = contact;
  in.last_simulation_update = t;
  return in;
}

TEST(ForceSafety, PassesForcesWithinLimitsUnchanged) {
  ForceSafety safety(config());
  const SafetyOutput out = safety.apply(input(Vec3(1, -2, 3), 0.0), 0.0);
  EXPECT_EQ(out.force, Vec3(1, -2, 3));
  EXPECT_EQ(out.flags, 0);
}

TEST(ForceSafety, ClampsMagnitudeAndKeepsDirection) {
  ForceSafety safety(config());
  SafetyInput in = input(Vec3(30, 40, 0), 0.0);
  in.torque = Vec3(0, 0, -2);
  const SafetyOutput out = safety.apply(in, 0.0);
  EXPECT_NEAR(out.force.norm(), 8.0, 1e-10);
  EXPECT_LE(out.force.norm(), 8.0);
  EXPECT_NEAR(out.force.normalized().dot(Vec3(0.6, 0.8, 0)), 1.0, 1e-15);
  EXPECT_NEAR(out.torque.z(), -0.5, 1e-10);
  EXPECT_EQ(out.flags, kSafetyClamped);
  EXPECT_EQ(safety.counters().clamped, 1u);
}

TEST(ForceSafety, ClampsHugeComponentsWithoutOverflow) {
  ForceSafety safety(config());
  const SafetyOutput out = safety.apply(input(Vec3(1e300, -1e300, 1e300), 0.0), 0.0);
  EXPECT_TRUE(out.force.allFinite());
  EXPECT_NEAR(out.force.norm(), 8.0, 1e-10);
  EXPECT_NEAR(out.force.normalized().dot(Vec3(1, -1, 1).normalized()), 1.0, 1e-15);
  EXPECT_EQ(out.flags, kSafetyClamped);
}

TEST(ForceSafety, ReplacesNonFiniteForceAndTorqueByZero) {
  ForceSafety safety(config());
  for (double bad : {kNaN, kInf, -kInf}) {
    SafetyInput in = input(Vec3(1, bad, 1), 0.0);
    in.torque = Vec3(0.1, 0.1, 0.1);
    const SafetyOutput out = safety.apply(in, 0.0);
    EXPECT_EQ(out.force, Vec3::Zero());
    EXPECT_EQ(out.torque, Vec3::Zero());
    EXPECT_EQ(out.flags, kSafetyNonFinite);
  }
  SafetyInput in = input(Vec3(1, 1, 1), 0.0);
  in.torque = Vec3(kNaN, 0, 0);
  EXPECT_EQ(safety.apply(in, 0.0).force, Vec3::Zero());
  EXPECT_EQ(safety.counters().non_finite, 4u);
}

TEST(ForceSafety, RampsInLinearlyAtContactOnset) {
  ForceSafety safety(config());
  const Vec3 f(0, 0, 5);
  safety.apply(input(Vec3::Zero(), 0.0), 0.0);
  for (int k = 0; k <= 8; ++k) {
    const double t = 0.010 + k * kFrame;
    const SafetyOutput out = safety.apply(input(f, t, true), t);
    const double expected = std::min(k / 5.0, 1.0);
    EXPECT_NEAR(out.force.z(), 5.0 * expected, 1e-9) << k;
    EXPECT_EQ((out.flags & kSafetyRamping) != 0, k < 5) << k;
  }
  EXPECT_EQ(safety.counters().ramp_in, 1u);
}

TEST(ForceSafety, FadesOutFromTheLastForceAtRelease) {
  ForceSafety safety(config());
  const Vec3 f(3, 0, -4);
  for (int k = 0; k < 20; ++k) safety.apply(input(f, k * kFrame, true), k * kFrame);
  // Contact lost: the proxy force drops to zero, the output must not.
  for (int k = 0; k <= 7; ++k) {
    const double t = 0.020 + k * kFrame;
    const SafetyOutput out = safety.apply(input(Vec3::Zero(), t, false), t);
    const double expected = std::max(1.0 - k / 5.0, 0.0);
    EXPECT_LE((out.force - expected * f).norm(), 1e-9) << k;
    EXPECT_EQ((out.flags & kSafetyRamping) != 0, k < 5) << k;
  }
  EXPECT_EQ(safety.counters().ramp_out, 1u);
}

TEST(ForceSafety, AContactLostForAFrameGoesOnFromTheForceSent) {
  // A contact flag that drops for one frame inside a touch (a grazing contact at the edge of
  // a patch): the release starts to blend out, and when the contact comes back the force
  // must go on from where it is, not restart its onset ramp from zero.
  ForceSafety safety(config());
  const Vec3 f(0, 4, 2);
  for (int k = 0; k < 20; ++k) safety.apply(input(f, k * kFrame, true), k * kFrame);
  Vec3 last = safety.apply(input(Vec3::Zero(), 0.020, false), 0.020).force;
  EXPECT_LE((last - f).norm(), 1e-9);  // the release's first frame still sends the contact force
  double largest_step = 0.0;
  for (int k = 1; k <= 10; ++k) {
    const double t = 0.020 + k * kFrame;
    const Vec3 sent = safety.apply(input(f, t, true), t).force;
    largest_step = std::max(largest_step, (sent - last).norm());
    last = sent;
  }
  EXPECT_LE(largest_step, 1e-9);
  EXPECT_LE((last - f).norm(), 1e-9);
  // Lost for two frames: the release has blended a fifth of the way out; the onset blends back.
  safety.apply(input(Vec3::Zero(), 0.031, false), 0.031);
  const Vec3 out = safety.apply(input(Vec3::Zero(), 0.032, false), 0.032).force;
  EXPECT_LE((out - 0.8 * f).norm(), 1e-9);
  const Vec3 back = safety.apply(input(f, 0.033, true), 0.033).force;
  EXPECT_LE((back - 0.8 * f).norm(), 1e-9);
  const Vec3 next = safety.apply(input(f, 0.034, true), 0.034).force;
  EXPECT_LE((next - (0.8 * 0.8 + 0.2) * f).norm(), 1e-9);
  EXPECT_EQ(safety.counters().ramp_in, 3u);
  EXPECT_EQ(safety.counters().ramp_out, 2u);
}

TEST(ForceSafety, WatchdogFadesOverFadeTimeCountsOneTripAndRampsBackIn) {
  ForceSafety safety(config());
  const Vec3 f(0, 6, 0);
  double t = 0.0;
  for (; t < 1.0; t += kFrame) safety.apply(input(f, t, true), t);
  // The simulation stops publishing at 1.0 s; the watchdog trips after 0.1 s of silence.
  const double last_update = 1.0;
  const auto stale = [&](double now) {
    SafetyInput in = input(f, now, true);
    in.last_simulation_update = last_update;
    return safety.apply(in, now);
  };
  EXPECT_EQ(stale(1.05).force, f);
  EXPECT_EQ(stale(1.0995).flags & kSafetyWatchdog, 0);
  const SafetyOutput first = stale(1.1005);
  EXPECT_NE(first.flags & kSafetyWatchdog, 0);
  EXPECT_NEAR(first.force.y(), 6.0 * (1.0 - 0.001 / 0.05), 1e-9);  // one frame of fade
  double previous = first.force.y();
  double now = 1.1005;
  for (int k = 2; k <= 80; ++k) {
    now += kFrame;
    const SafetyOutput out = stale(now);
    EXPECT_LE(out.force.y(), previous + 1e-12);
    EXPECT_NEAR(out.force.y(), 6.0 * std::max(1.0 - k * kFrame / 0.05, 0.0), 1e-9) << k;
    EXPECT_NE(out.flags & kSafetyWatchdog, 0);
    previous = out.force.y();
  }
  EXPECT_EQ(previous, 0.0);
  EXPECT_EQ(safety.counters().watchdog_trips, 1u);
  // Fresh again: back to full force over ramp_time, not in one frame.
  for (int k = 1; k <= 7; ++k) {
    now += kFrame;
    const SafetyOutput out = safety.apply(input(f, now, true), now);
    EXPECT_NEAR(out.force.y(), 6.0 * std::min(k / 5.0, 1.0), 1e-9) << k;
    EXPECT_EQ((out.flags & kSafetyRamping) != 0, k < 5) << k;
  }
  EXPECT_EQ(safety.counters().ramp_in, 2u);  // the contact onset and the recovery
  // A second stall is a second trip.
  stale(1.5);
  EXPECT_EQ(safety.counters().watchdog_trips, 2u);
}

TEST(ForceSafety, DeviceNotAliveFadesAndCountsOneStall) {
  ForceSafety safety(config());
  const Vec3 f(2, 0, 0);
  for (int k = 0; k < 100; ++k) {
    SafetyInput in = input(f, k * kFrame);
    in.device_alive = k < 10;
    const SafetyOutput out = safety.apply(in, k * kFrame);
    if (k >= 60) {
      EXPECT_EQ(out.force, Vec3::Zero()) << k;
    }
    EXPECT_EQ((out.flags & kSafetyWatchdog) != 0, k >= 10) << k;
  }
  EXPECT_EQ(safety.counters().device_stalls, 1u);
  EXPECT_EQ(safety.counters().watchdog_trips, 0u);
}

TEST(ForceSafety, EmergencyStopLatchesUntilResetThenRampsIn) {
  ForceSafety safety(config());
  const Vec3 f(1, 1, 1);
  safety.apply(input(f, 0.0), 0.0);
  SafetyInput stop = input(f, 0.001);
  stop.emergency_stop = true;
  EXPECT_EQ(safety.apply(stop, 0.001).force, Vec3::Zero());
  for (int k = 2; k < 50; ++k) {
    const SafetyOutput out = safety.apply(input(f, k * kFrame), k * kFrame);
    EXPECT_EQ(out.force, Vec3::Zero());
    EXPECT_EQ(out.flags & kSafetyEmergencyStop, kSafetyEmergencyStop);
  }
  EXPECT_TRUE(safety.emergency_stopped());
  EXPECT_EQ(safety.counters().emergency_stops, 1u);
  safety.reset_emergency_stop();
  EXPECT_FALSE(safety.emergency_stopped());
  EXPECT_NEAR(safety.apply(input(f, 0.050), 0.050).force.x(), 0.2, 1e-9);
  EXPECT_EQ(safety.apply(input(f, 0.060), 0.060).force, f);
}

TEST(ForceSafety, CountersAreASnapshot) {
  ForceSafety safety(config());
  const SafetyCounters before = safety.counters();
  safety.apply(input(Vec3(100, 0, 0), 0.0), 0.0);
  EXPECT_EQ(before.clamped, 0u);
  EXPECT_EQ(safety.counters().clamped, 1u);
}

TEST(ForceSafety, RejectsUnsafeConfigurations) {
  for (auto broken : {+[](SafetyConfig& c) { c.max_force = 0.0; }, +[](SafetyConfig& c) { c.max_force = kInf; },
                      +[](SafetyConfig& c) { c.max_torque = -1.0; }, +[](SafetyConfig& c) { c.ramp_time = kNaN; },
                      +[](SafetyConfig& c) { c.fade_time = -0.1; },
                      +[](SafetyConfig& c) { c.watchdog_timeout = 0.0; }}) {
    SafetyConfig c = config();
    broken(c);
    EXPECT_THROW(ForceSafety{c}, InputError);
  }
}

/// Values chosen to break arithmetic: non-finite, huge, denormal, limits, signed zeros.
double adversarial(std::mt19937& rng) {
  static constexpr std::array<double, 14> pool = {
      kNaN, kInf, -kInf, 1e300, -1e300, std::numeric_limits<double>::max(), 4.9e-324, -1e-310,
      0.0, -0.0, 8.0, 8.0000000001, 1e-3, std::numeric_limits<double>::min()};
  std::uniform_int_distribution<int> pick(0, 3);
  if (pick(rng) == 0) return pool[std::uniform_int_distribution<std::size_t>(0, pool.size() - 1)(rng)];
  return std::normal_distribution<double>(0.0, 20.0)(rng);
}

TEST(ForceSafety, OutputIsAlwaysFiniteAndWithinLimitsForAnyInput) {
  std::mt19937 rng(2024);
  std::uniform_int_distribution<int> coin(0, 1);
  std::uniform_int_distribution<int> rare(0, 49);
  std::uniform_real_distribution<double> step(0.0, 0.004);
  const SafetyConfig c = config();
  std::uint64_t clamped_frames = 0, nan_frames = 0;
  for (int sequence = 0; sequence < 1500; ++sequence) {
    SafetyConfig ci = c;
    if (sequence % 3 == 1) ci.ramp_time = 0.0;
    if (sequence % 5 == 2) ci.fade_time = 0.0;
    ForceSafety safety(ci);
    double t = 0.0, last_update = 0.0;
    const int mode = sequence % 4;  // 1: contact flips every frame, 2: stalls, 3: time anomalies
    for (int frame = 0; frame < 300; ++frame) {
      t += mode == 3 && rare(rng) == 0 ? 1.0 : step(rng);
      if (coin(rng) || mode != 2) last_update = t;
      SafetyInput in;
      in.force = Vec3(adversarial(rng), adversarial(rng), adversarial(rng));
      in.torque = Vec3(adversarial(rng), adversarial(rng), adversarial(rng));
      in.contact = mode == 1 ? frame % 2 == 0 : coin(rng) == 1;
      in.last_simulation_update = mode == 3 && rare(rng) == 0 ? kNaN : last_update;
      in.device_alive = rare(rng) != 0;
      in.emergency_stop = rare(rng) == 0 && rare(rng) < 5;
      if (rare(rng) == 0) safety.reset_emergency_stop();
      const double now = mode == 3 && rare(rng) == 0 ? kNaN : t;
      const SafetyOutput out = safety.apply(in, now);
      ASSERT_TRUE(out.force.allFinite()) << sequence << ":" << frame;
      ASSERT_TRUE(out.torque.allFinite()) << sequence << ":" << frame;
      ASSERT_LE(out.force.norm(), c.max_force) << sequence << ":" << frame;
      ASSERT_LE(out.torque.norm(), c.max_torque) << sequence << ":" << frame;
    }
    clamped_frames += safety.counters().clamped;
    nan_frames += safety.counters().non_finite;
  }
  // The inputs did exercise both guards.
  EXPECT_GT(clamped_frames, 10000u);
  EXPECT_GT(nan_frames, 10000u);
}

TEST(ForceSafety, ContactFlippingEveryFrameNeverPassesAStep) {
  // Worst case for the ramps: a full-scale force with contact toggling each frame. The
  // output must stay far below a full step each frame: at most the limit times one frame
  // of the ramp, 8 N · 1 ms / 5 ms, and never above the limit.
  ForceSafety safety(config());
  double largest_step = 0.0;
  double largest = 0.0;
  Vec3 last = Vec3::Zero();
  for (int frame = 0; frame < 1000; ++frame) {
    const double t = frame * kFrame;
    const SafetyOutput out = safety.apply(input(Vec3(0, 0, 100), t, frame % 2 == 0), t);
    largest_step = std::max(largest_step, (out.force - last).norm());
    largest = std::max(largest, out.force.norm());
    last = out.force;
  }
  EXPECT_LE(largest_step, 8.0 * kFrame / 0.005 + 1e-9);
  EXPECT_LE(largest, 8.0);
}

}  // namespace
}  // namespace tactus::haptics
