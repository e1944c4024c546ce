#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "haptics/device.hpp"
#include "haptics/devices/replay_device.hpp"
#include "haptics/devices/scripted_device.hpp"
#include "haptics/devices/simulated_operator.hpp"

namespace tactus::haptics {
namespace {

bool bit_identical(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), sizeof(double) * 3) == 0; }

bool bit_identical(const DevicePose& a, const DevicePose& b) {
  return bit_identical(a.position, b.position) &&
         std::memcmp(a.orientation.coeffs().data(), b.orientation.coeffs().data(), sizeof(double) * 4) == 0 &&
         a.buttons == b.buttons;
}

/// A target that steps from a to b within 10 ms and then stays.
WaypointsPath step(const Vec3& a, const Vec3& b) {
  WaypointsPath p;
  p.points = {{0.0, a}, {0.01, b}};
  return p;
}

// ---- ScriptedDevice -------------------------------------------------------------------------

TEST(ScriptedDevice, ReadsTrajectoryPlusTremorAndRecordsForces) {
  PressPath press;
  press.position = Vec3(0.01, 0.02, 0.03);
  press.depth = 0.004;
  press.speed = 0.01;
  press.hold = 0.2;
  const Tremor tremor{0.0005, 9.0};
  ScriptedDevice device(press, tremor, DeviceLimits{}, 3);
  EXPECT_STREQ(device.kind(), "scripted");
  for (double t : {0.0, 0.1, 0.45, 0.7, 2.0}) {
    const DevicePose pose = device.read(t);
    EXPECT_EQ(pose.position, position_at(press, t) + tremor_at(tremor, t, 3)) << t;
    EXPECT_EQ(pose.buttons, 0u);
  }
  device.write(Vec3(1, 2, 3), Vec3(0.1, 0, 0));
  EXPECT_EQ(device.last_force(), Vec3(1, 2, 3));
  EXPECT_EQ(device.last_torque(), Vec3(0.1, 0, 0));
  // The force moves nothing.
  EXPECT_EQ(device.read(0.1).position, position_at(press, 0.1) + tremor_at(tremor, 0.1, 3));
  EXPECT_FALSE(device.finished(1.0));   // duration 0.4 + 0.2 + 0.4 s
  EXPECT_FALSE(device.finished(1.0 - 1e-9));
  EXPECT_TRUE(device.finished(1.0 + 1e-9));
}

TEST(ScriptedDevice, CirclesNeverFinish) {
  ScriptedDevice device(CirclePath{}, Tremor{}, DeviceLimits{});
  EXPECT_FALSE(device.finished(1e9));
}

// ---- SimulatedOperator ----------------------------------------------------------------------

SimulatedOperator make_hand(const Trajectory& target, double damping = 5.0, Tremor tremor = {}) {
  DeviceLimits limits;
  limits.max_stiffness = 2000.0;
  return SimulatedOperator(target, tremor, 0.2, 300.0, damping, limits, 11);
}

TEST(SimulatedOperator, StartsAtRestOnTheTarget) {
  SimulatedOperator hand = make_hand(step(Vec3(0.01, 0, 0), Vec3(0.02, 0, 0)));
  EXPECT_STREQ(hand.kind(), "simulated_operator");
  EXPECT_EQ(hand.hand().position, Vec3(0.01, 0, 0));
  EXPECT_EQ(hand.hand().velocity, Vec3::Zero());
  EXPECT_EQ(hand.read(0.0).position, Vec3(0.01, 0, 0));
}

TEST(SimulatedOperator, SettlesOnAStaticTargetWithoutDeviceForce) {
  const Vec3 goal(0.02, -0.01, 0.03);
  SimulatedOperator hand = make_hand(step(Vec3::Zero(), goal));
  double max_overshoot = 0.0;
  for (int frame = 1; frame <= 3000; ++frame) {
    const Vec3 x = hand.read(frame * 1e-3).position;
    max_overshoot = std::max(max_overshoot, (x - goal).dot(goal.normalized()));
  }
  // ζ = c / (2√(k m)) ≈ 0.32: it overshoots, then the envelope e^{−ζωt} ≈ e^{−37} at 3 s.
  EXPECT_GT(max_overshoot, 1e-3);
  EXPECT_LE((hand.hand().position - goal).norm(), 1e-9);
  EXPECT_LE(hand.hand().velocity.norm(), 1e-8);
  EXPECT_DOUBLE_EQ(hand.hand().device_work, 0.0);
}

TEST(SimulatedOperator, SettlesAtTargetPlusForceOverStiffness) {
  const Vec3 goal(0.01, 0.0, 0.02);
  const Vec3 force(1.5, -3.0, 0.6);
  SimulatedOperator hand = make_hand(step(goal, goal));
  for (int frame = 1; frame <= 4000; ++frame) {
    hand.read(frame * 1e-3);
    hand.write(force, Vec3::Zero());
  }
  const Vec3 expected = goal + force / 300.0;  // k (x* − x) + F = 0
  EXPECT_LE((hand.hand().position - expected).norm(), 1e-9);
  // Work of a constant force = F · displacement.
  EXPECT_NEAR(hand.hand().device_work, force.dot(expected - goal), 1e-9);
  EXPECT_NEAR(hand.hand().kinetic_energy, 0.0, 1e-15);
}

struct WallRun {
  std::vector<double> x;   ///< handle x per frame
  double max_kinetic = 0.0;
  double device_work = 0.0;
  double final_penetration = 0.0;
};

/// The hand pushes its target 2 cm into a virtual wall at x = 0 rendered at 1 kHz from the
/// pose read each frame: F = −K·max(0, x − wall), held for the frame.
WallRun push_into_wall(double wall_stiffness, double hand_damping, double seconds, Tremor tremor = {}) {
  WaypointsPath target;
  target.points = {{0.0, Vec3(-0.01, 0, 0)}, {0.5, Vec3(0.02, 0, 0)}};
  SimulatedOperator hand = make_hand(target, hand_damping, tremor);
  WallRun run;
  const int frames = static_cast<int>(seconds * 1000);
  for (int frame = 0; frame <= frames; ++frame) {
    const double x = hand.read(frame * 1e-3).position.x();
    const double penetration = std::max(0.0, x);
    hand.write(Vec3(-wall_stiffness * penetration, 0, 0), Vec3::Zero());
    run.x.push_back(x);
    run.max_kinetic = std::max(run.max_kinetic, hand.hand().kinetic_energy);
    run.final_penetration = penetration;
  }
  run.device_work = hand.hand().device_work;
  return run;
}

/// Peak-to-peak of x over frames [begin, end).
double swing(const std::vector<double>& x, std::size_t begin, std::size_t end) {
  const auto [lo, hi] = std::minmax_element(x.begin() + static_cast<std::ptrdiff_t>(begin),
                                            x.begin() + static_cast<std::ptrdiff_t>(end));
  return *hi - *lo;
}

TEST(SimulatedOperator, StiffWallUpToMaxStiffnessStaysStableAndPassive) {
  for (double stiffness : {200.0, 1000.0, 2000.0}) {
    const WallRun run = push_into_wall(stiffness, 5.0, 4.0);
    // Equilibrium of the two springs in series: k (x* − x) = K x.
    const double equilibrium = 300.0 * 0.02 / (300.0 + stiffness);
    EXPECT_NEAR(run.x.back(), equilibrium, 1e-6) << stiffness;
    // No growing oscillation: the last second swings less than the second after contact.
    EXPECT_LT(swing(run.x, 3000, 4000), swing(run.x, 600, 1600) + 1e-9) << stiffness;
    EXPECT_LT(swing(run.x, 3000, 4000), 1e-6) << stiffness;
    // Bounded energy: never more kinetic energy than the hand spring could store over
    // the 3 cm the target travels.
    EXPECT_LT(run.max_kinetic, 0.5 * 300.0 * 0.03 * 0.03) << stiffness;
    // Passivity: a spring wall can only take energy out of the hand (−½ K d² at rest);
    // what the 1 ms hold adds must stay a small fraction of that.
    const double stored = 0.5 * stiffness * run.final_penetration * run.final_penetration;
    EXPECT_LT(run.device_work, -0.8 * stored) << stiffness;
  }
}

TEST(SimulatedOperator, UndampedHandOnAStiffWallGainsEnergyWhichTheChecksDetect) {
  // The sample-and-hold wall acts like K·T/2 = 1 N·s/m of negative damping; with no hand
  // damping to absorb it the contact oscillation grows. The checks above must see that.
  const WallRun run = push_into_wall(2000.0, 0.0, 4.0);
  EXPECT_GT(swing(run.x, 3000, 4000), 2.0 * swing(run.x, 600, 1600));
  EXPECT_GT(run.device_work, 0.0);  // the device put energy in: not passive
}

TEST(SimulatedOperator, IdenticalCallSequencesGiveBitIdenticalPoses) {
  const Tremor tremor{0.0008, 8.0};
  const WallRun a = push_into_wall(1500.0, 5.0, 1.5, tremor);
  const WallRun b = push_into_wall(1500.0, 5.0, 1.5, tremor);
  ASSERT_EQ(a.x.size(), b.x.size());
  EXPECT_EQ(std::memcmp(a.x.data(), b.x.data(), a.x.size() * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&a.device_work, &b.device_work, sizeof(double)), 0);
}

TEST(SimulatedOperator, ResultHardlyDependsOnHowTimeIsSliced) {
  CirclePath circle;
  circle.radius = 0.02;
  SimulatedOperator coarse = make_hand(circle);
  SimulatedOperator fine = make_hand(circle);
  const Vec3 once = coarse.read(0.5).position;
  Vec3 sliced;
  for (int i = 1; i <= 500; ++i) sliced = fine.read(i * 1e-3).position;
  EXPECT_LE((once - sliced).norm(), 1e-6);
  EXPECT_GT((once - position_at(circle, 0.0)).norm(), 1e-3);  // it did move
}

TEST(SimulatedOperator, RejectsNonPhysicalHandParameters) {
  EXPECT_THROW(SimulatedOperator(CirclePath{}, Tremor{}, 0.0, 300, 5, DeviceLimits{}), InputError);
  EXPECT_THROW(SimulatedOperator(CirclePath{}, Tremor{}, 0.2, -1, 5, DeviceLimits{}), InputError);
  EXPECT_THROW(SimulatedOperator(CirclePath{}, Tremor{}, 0.2, 300, -5, DeviceLimits{}), InputError);
  EXPECT_THROW(SimulatedOperator(CirclePath{}, Tremor{}, std::nan(""), 300, 5, DeviceLimits{}), InputError);
}

// ---- ReplayDevice ---------------------------------------------------------------------------

DevicePose pose_with(double x, std::uint32_t buttons) {
  DevicePose p;
  p.position = Vec3(x, x / 3.0, 0.1 + 0.2);
  p.orientation = Quat(Eigen::AngleAxisd(x, Vec3(1, 2, 3).normalized()));
  p.buttons = buttons;
  return p;
}

TEST(ReplayDevice, ReturnsTheLatestSampleAtOrBeforeTExactly) {
  const std::vector<TimedPose> samples = {
      {0.1, pose_with(0.7, 0)}, {0.2, pose_with(1.1, 1)}, {0.2, pose_with(1.3, 3)}, {0.5, pose_with(2.9, 2)}};
  ReplayDevice device(samples, DeviceLimits{});
  EXPECT_STREQ(device.kind(), "replay");
  EXPECT_TRUE(bit_identical(device.read(0.0), samples[0].pose));  // before the first
  EXPECT_TRUE(bit_identical(device.read(0.1), samples[0].pose));
  EXPECT_TRUE(bit_identical(device.read(0.15), samples[0].pose));
  EXPECT_TRUE(bit_identical(device.read(0.2), samples[2].pose));  // last of equal times
  EXPECT_TRUE(bit_identical(device.read(0.49), samples[2].pose));
  EXPECT_TRUE(bit_identical(device.read(0.5), samples[3].pose));
  EXPECT_TRUE(bit_identical(device.read(7.0), samples[3].pose));
  EXPECT_TRUE(bit_identical(device.read(0.12), samples[0].pose));  // going back works too
  device.write(Vec3(100, 0, 0), Vec3::Zero());
  EXPECT_TRUE(bit_identical(device.read(0.5), samples[3].pose));
  EXPECT_FALSE(device.finished(0.5));
  EXPECT_TRUE(device.finished(0.5000001));
}

TEST(ReplayDevice, ReplaysARecordedRunBitForBit) {
  // Record a simulated operator with tremor, replay it at the same frame times.
  SimulatedOperator hand = make_hand(CirclePath{}, 5.0, Tremor{0.001, 8.0});
  std::vector<TimedPose> recording;
  for (int i = 0; i < 2000; ++i) {
    const double t = i * 1e-3;
    recording.push_back({t, hand.read(t)});
  }
  ReplayDevice replay(recording, DeviceLimits{});
  for (const TimedPose& s : recording) ASSERT_TRUE(bit_identical(replay.read(s.t), s.pose)) << s.t;
}

TEST(ReplayDevice, RejectsBadRecordingsWithTheSampleAndReason) {
  const auto message = [](std::vector<TimedPose> samples) -> std::string {
    try {
      ReplayDevice device(std::move(samples), DeviceLimits{}, "run.rec");
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_NE(message({}).find("no device samples"), std::string::npos);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::string not_finite = message({{0.0, {}}, {nan, {}}});
  EXPECT_NE(not_finite.find("sample 1"), std::string::npos) << not_finite;
  EXPECT_NE(not_finite.find("run.rec"), std::string::npos) << not_finite;
  const std::string backwards = message({{0.0, {}}, {0.3, {}}, {0.2, {}}});
  EXPECT_NE(backwards.find("sample 2"), std::string::npos) << backwards;
  EXPECT_NE(backwards.find("before"), std::string::npos) << backwards;
  DevicePose bad;
  bad.position.y() = std::numeric_limits<double>::infinity();
  EXPECT_NE(message({{0.0, {}}, {0.1, bad}}).find("sample 1"), std::string::npos);
  EXPECT_EQ(message({{0.0, {}}, {0.0, {}}, {0.1, {}}}), "no error");
}

// ---- WorkspaceMap ---------------------------------------------------------------------------

TEST(WorkspaceMap, RoundTripsPositionsAndKeepsForceMagnitudes) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    WorkspaceMap map;
    map.scale = std::exp(2.0 * u(rng));
    map.rotation = Quat(Eigen::AngleAxisd(3.0 * u(rng), Vec3(u(rng), u(rng), 1.0).normalized()));
    map.offset = Vec3(u(rng), u(rng), u(rng));
    const Vec3 p(u(rng), u(rng), u(rng));
    ASSERT_LE((map.to_device(map.to_scene(p)) - p).norm(), 1e-13);
    ASSERT_LE((map.to_scene(map.to_device(p)) - p).norm(), 1e-13);
    // Distances scale by `scale`.
    const Vec3 q(u(rng), u(rng), u(rng));
    ASSERT_NEAR((map.to_scene(p) - map.to_scene(q)).norm(), map.scale * (p - q).norm(), 1e-12);
    // A scene force maps back by the inverse rotation, unscaled: its device-space version
    // rotated forward gives it back.
    const Vec3 f(u(rng), u(rng), u(rng));
    ASSERT_NEAR(map.force_to_device(f).norm(), f.norm(), 1e-13);
    ASSERT_LE((map.rotation * map.force_to_device(f) - f).norm(), 1e-13);
    const Quat q_device(Eigen::AngleAxisd(u(rng), Vec3::UnitZ()));
    ASSERT_NEAR(map.to_scene(q_device).angularDistance(map.rotation * q_device), 0.0, 1e-12);
  }
}

}  // namespace
}  // namespace tactus::haptics
