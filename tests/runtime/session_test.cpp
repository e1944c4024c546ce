// The loops end to end: lockstep determinism, bit-exact replay, stability with a simulated
// operator, safety in the loop, recordings that survive a kill, clear errors.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "haptics/force_algorithm.hpp"
#include "haptics/haptic_step.hpp"
#include "runtime/recording_reader.hpp"
#include "runtime/session.hpp"
#include "scene/scene.hpp"

namespace tactus::runtime {
namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "tactus_session_test";
  fs::create_directories(dir);
  return dir / name;
}

scene::Model data_scene(const std::string& name) {
  return scene::load_scene(fs::path(TACTUS_SOURCE_DIR) / "tests/fixtures/scenes" / name);
}

SessionOptions lockstep(double duration) {
  SessionOptions o;
  o.scheduling = Scheduling::lockstep;
  o.duration = duration;
  o.keep_frames = true;
  return o;
}

bool same_frames(const std::vector<HapticFrame>& a, const std::vector<HapticFrame>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].t != b[i].t || a[i].position != b[i].position || a[i].force != b[i].force || a[i].flags != b[i].flags)
      return false;
  return true;
}

TEST(Session, DefaultSceneTouchesTheTissue) {
  const SessionReport r = run_session(scene::default_scene(), lockstep(0.0));
  // The press trajectory: 10 mm down at 10 mm/s, 1 s hold, back up: 3 s in all.
  EXPECT_NEAR(r.simulated_time, 3.0, 0.002);
  ASSERT_EQ(r.devices.size(), 1u);
  EXPECT_GT(r.devices[0].contact_frames, 2000u);
  // 8 mm into a 30 kPa block through an 800 N/m coupling: a few newtons, below the
  // 6.4 N the coupling alone would give on a rigid surface (the tissue yields).
  EXPECT_GT(r.devices[0].max_force_sent, 1.0);
  EXPECT_LT(r.devices[0].max_force_sent, 6.4);
  EXPECT_EQ(r.loops.size(), 3u);
  EXPECT_EQ(r.loops[0].steps, r.frames.size());
  EXPECT_NEAR(static_cast<double>(r.loops[0].steps), 3000.0, 3.0);
}

TEST(Session, LockstepRunsAreBitIdentical) {
  const scene::Model m = scene::default_scene();
  const SessionReport a = run_session(m, lockstep(1.5));
  const SessionReport b = run_session(m, lockstep(1.5));
  ASSERT_GT(a.frames.size(), 1000u);
  EXPECT_TRUE(same_frames(a.frames, b.frames));
}

TEST(Session, LockstepReplayReproducesForcesBitForBit) {
  const fs::path file = temp_file("replay.tacrec");
  const scene::Model m = data_scene("stiff_press.toml");  // the operator's motion depends on the forces
  SessionOptions o = lockstep(1.2);
  o.record = file;
  const SessionReport original = run_session(m, o);

  const Recording rec = read_recording(file);
  ASSERT_TRUE(rec.complete);
  ASSERT_EQ(rec.frames.size(), original.frames.size());
  SessionOptions r = lockstep(rec.frames.back().t);
  r.replay = recorded_motion(rec, file.string());
  const SessionReport replayed = run_session(m, r);
  ASSERT_EQ(replayed.frames.size(), rec.frames.size());
  std::size_t in_contact = 0;
  for (std::size_t i = 0; i < rec.frames.size(); ++i) {
    ASSERT_EQ(replayed.frames[i].force, rec.frames[i].force) << "frame " << i;
    in_contact += rec.frames[i].contact;
  }
  EXPECT_GT(in_contact, 500u);  // the comparison covers real contact, not free space
}

TEST(Session, SimulatedOperatorOnStiffTissueIsStable) {
  // 2000 N/m coupling (the device's maximum) against 500 kPa skin, no damping anywhere in the
  // contact, hand coupled by 300 N/m: press, hold 1 s, release.
  const SessionReport r = run_session(data_scene("stiff_press.toml"), lockstep(0.0));
  ASSERT_GT(r.frames.size(), 1900u);
  double work = 0.0, normal_work = 0.0, f_max = 0.0;
  double hold_early_min = 1e9, hold_early_max = 0.0, hold_late_min = 1e9, hold_late_max = 0.0;
  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    const HapticFrame& f = r.frames[i];
    ASSERT_TRUE(f.force.allFinite());
    ASSERT_LE(f.force.norm(), 10.0);
    f_max = std::max(f_max, f.force.norm());
    if (i > 0) {
      work += r.frames[i - 1].force.dot(f.position - r.frames[i - 1].position);
      normal_work += r.frames[i - 1].force.z() * (f.position.z() - r.frames[i - 1].position.z());
    }
    const double fz = f.force.z();
    if (f.t >= 0.7 && f.t < 0.9) hold_early_min = std::min(hold_early_min, fz), hold_early_max = std::max(hold_early_max, fz);
    if (f.t >= 1.2 && f.t < 1.4) hold_late_min = std::min(hold_late_min, fz), hold_late_max = std::max(hold_late_max, fz);
  }
  ASSERT_GT(f_max, 1.0);  // the contact was real
  // No growing oscillation: during the hold the force ripple (from the 100 Hz surface
  // updates) stays below 2% of the force and does not grow.
  const double mean = 0.5 * (hold_late_min + hold_late_max);
  EXPECT_LT(hold_late_max - hold_late_min, 0.02 * mean);
  EXPECT_LE(hold_late_max - hold_late_min, 1.05 * (hold_early_max - hold_early_min) + 1e-6);
  // Passivity over the closed press-release cycle, against the peak energy stored in the
  // coupling spring (½F²/k): along the press the contact returns less than it took (within
  // 1%); the small lateral forces of the asymmetric tet mesh, rendered from a surface that
  // lags by a simulation period, may return a little (3.7% measured), never more than 10%.
  const double stored = f_max * f_max / (2.0 * 2000.0);
  EXPECT_LT(normal_work, 0.01 * stored) << "net work of the normal force on the hand " << normal_work << " J";
  EXPECT_LT(work, 0.10 * stored) << "net work done on the hand " << work << " J";
}

TEST(Session, EmergencyStopZeroesEveryLaterForce) {
  SessionOptions o = lockstep(2.0);
  o.emergency_stop_at = 1.0;
  const SessionReport r = run_session(scene::default_scene(), o);
  std::size_t after = 0;
  bool force_before = false;
  for (const HapticFrame& f : r.frames) {
    if (f.t < 1.0) force_before |= f.force.norm() > 0.5;
    if (f.t < 1.0) continue;
    ++after;
    EXPECT_EQ(f.force, Vec3::Zero()) << "t = " << f.t;
    EXPECT_TRUE(f.flags & frame_emergency_stop);
  }
  EXPECT_TRUE(force_before);
  EXPECT_GT(after, 900u);
  EXPECT_EQ(r.devices[0].safety.emergency_stops, 1u);
  EXPECT_EQ(r.events.at("emergency_stop"), 1u);
}

TEST(Session, ForceNeverExceedsTheDeviceLimit) {
  std::string text(scene::default_scene_text());
  const auto at = text.find("max_force = 10.0");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 16, "max_force = 1.0");
  const SessionReport r = run_session(scene::parse_scene(text, "limited.toml"), lockstep(2.0));
  for (const HapticFrame& f : r.frames) ASSERT_LE(f.force.norm(), 1.0 + 1e-12);
  EXPECT_GT(r.devices[0].safety.clamped, 100u);
  EXPECT_GE(r.events.at("force_clamped"), 1u);
}

TEST(Session, RealTimeRecordingReplaysInLockstepAtTheSameInstantsAndPoses) {
  // A real-time run's frames are stamped with the instants a lockstep run visits, so a
  // lockstep replay of its recording reads, at each frame, the pose recorded for that frame.
  const fs::path file = temp_file("realtime.tacrec");
  SessionOptions o;
  o.scheduling = Scheduling::real_time;
  o.duration = 0.5;
  o.record = file;
  run_session(scene::default_scene(), o);
  const Recording rec = read_recording(file);
  ASSERT_GT(rec.frames.size(), 100u);
  SessionOptions r = lockstep(rec.frames.back().t);
  r.replay = recorded_motion(rec, file.string());
  const SessionReport replayed = run_session(scene::default_scene(), r);
  std::size_t matched = 0;
  for (const HapticFrame& f : rec.frames) {
    // Frame k of the lockstep run is at k / 1000 s; a real-time frame may have been skipped.
    const auto k = static_cast<std::size_t>(std::llround(f.t * 1000.0));
    ASSERT_LT(k, replayed.frames.size());
    const HapticFrame& g = replayed.frames[k];
    ASSERT_EQ(g.t, f.t) << "frame " << f.frame;
    ASSERT_EQ(g.position, f.position) << "t = " << f.t;
    ++matched;
  }
  EXPECT_EQ(matched, rec.frames.size());
}

TEST(Session, KilledRunLeavesAReadableRecording) {
  const fs::path file = temp_file("killed.tacrec");
  fs::remove(file);
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, STDOUT_FILENO);
    dup2(null, STDERR_FILENO);
    execl(TACTUS_BINARY, TACTUS_BINARY, "-q", "run", "--duration", "30", "--record", file.c_str(), nullptr);
    _exit(127);
  }
  // Killed one second after its first frame reached the file: how long the run takes to
  // start (a sanitized build on a busy machine) must not decide what is checked.
  auto frames_on_disk = [&] {
    try {
      return read_recording(file).frames.size();
    } catch (const std::exception&) {
      return std::size_t{0};  // no header yet
    }
  };
  for (int i = 0; i < 600 && frames_on_disk() == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  std::this_thread::sleep_for(std::chrono::seconds(1));
  kill(pid, SIGKILL);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run was meant to be killed";
  const Recording rec = read_recording(file);
  EXPECT_FALSE(rec.complete);
  // The writer flushes at least every 50 ms: most of that second of 1 kHz frames survives.
  EXPECT_GT(rec.frames.size(), 500u);
  for (std::size_t i = 1; i < rec.frames.size(); ++i) ASSERT_EQ(rec.frames[i].frame, rec.frames[i - 1].frame + 1);
}

TEST(Session, TwoDevicesPinchTheTissueEachWithItsOwnLoop) {
  // A two-finger tool: each finger on its own device, pressing the block's top from two
  // places; a third device drives nothing and is only read and recorded.
  std::string text(scene::default_scene_text());
  const auto devices = text.find("[devices.hand]");
  text = text.substr(0, devices) + R"(
[devices.thumb]
type = "scripted"
trajectory = { type = "press", position = [-0.02, 0.0, 0.03], depth = 0.01, speed = 0.01, hold = 0.5 }

[devices.index]
type = "scripted"
trajectory = { type = "press", position = [0.02, 0.0, 0.03], depth = 0.006, speed = 0.01, hold = 0.5 }

[devices.idle]
type = "scripted"
trajectory = { type = "waypoints", points = [{ time = 0.0, position = [0, 0, 0.1] }, { time = 1.0, position = [0, 0, 0.1] }] }

[tools.pinch]
type = "two_fingers"
devices = ["thumb", "index"]

[algorithms.touch]
type = "proxy"
tool = "pinch"
stiffness = 800.0
)";
  const SessionReport r = run_session(scene::parse_scene(text, "pinch.toml"), lockstep(0.0));
  ASSERT_EQ(r.devices.size(), 3u);
  ASSERT_EQ(r.loops.size(), 5u);  // three haptic loops, simulation, interaction
  EXPECT_GT(r.devices[0].contact_frames, 500u);
  EXPECT_GT(r.devices[1].contact_frames, 300u);
  EXPECT_EQ(r.devices[2].contact_frames, 0u);
  // The deeper press of the thumb is felt as the larger force.
  EXPECT_GT(r.devices[0].max_force_sent, r.devices[1].max_force_sent);
  EXPECT_GT(r.devices[1].max_force_sent, 0.5);
  std::size_t per_device[3] = {0, 0, 0};
  for (const HapticFrame& f : r.frames) ++per_device[f.device];
  EXPECT_EQ(per_device[0], per_device[1]);
  EXPECT_EQ(per_device[0], per_device[2]);
}

TEST(Session, TheDefaultSceneRunsWithAMultiSurfaceAlgorithm) {
  // The default scene with its proxy replaced by a multi-surface algorithm (one layer).
  std::ifstream in(fs::path(TACTUS_SOURCE_DIR) / "scenes/default.toml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string proxy = "type = \"proxy\"\ntool = \"finger\"\nstiffness = 800.0\ndamping = 1.0";
  ASSERT_NE(text.find(proxy), std::string::npos);
  text.replace(text.find(proxy), proxy.size(), "type = \"multi_surface\"\ntool = \"finger\"");
  const SessionReport r = run_session(scene::parse_scene(text, "multi.toml"), lockstep(0.5));
  ASSERT_EQ(r.devices.size(), 1u);
  EXPECT_EQ(r.devices.front().safety.non_finite, 0u);
  EXPECT_GT(r.events.count("contact_begin"), 0u);  // the press reaches the block in 0.2 s
}

// A force law written outside the engine: a spring pushing the tool up out of the plane z = 0.
class SpringWall final : public haptics::ForceAlgorithm {
 public:
  explicit SpringWall(double stiffness) : stiffness_(stiffness) {}
  [[nodiscard]] std::unique_ptr<haptics::AlgorithmState> make_state() const override {
    return std::make_unique<haptics::AlgorithmState>();
  }
  [[nodiscard]] haptics::Rendering render(const haptics::FrameInputs& frame, haptics::AlgorithmState&) const override {
    haptics::Rendering r;
    r.surface_time = frame.t;  // the wall is no simulated surface: never stale for the watchdog
    r.touching = frame.position.z() < 0.0;
    if (r.touching) r.force = Vec3(0.0, 0.0, -stiffness_ * frame.position.z());
    return r;
  }

 private:
  double stiffness_;
};

TEST(Session, CustomizeHapticsAddsAForceAlgorithmTheSceneLacks) {
  // A device with no tool feels nothing from the scene; the hook gives it the wall.
  const scene::Model m = scene::parse_scene(R"(
[bodies.block]
kind = "rigid"
mesh = { generator = "box", size = [0.02, 0.02, 0.02], translate = [0, 0, -0.5] }
[devices.hand]
type = "scripted"
[devices.hand.trajectory]
type = "waypoints"
points = [ { time = 0.0, position = [0, 0, 0.01] }, { time = 0.5, position = [0, 0, -0.01] } ]
)",
                                            "wall.toml");
  SessionOptions o = lockstep(0.5);
  std::vector<std::size_t> customized;
  o.customize_haptics = [&](const scene::Model&, std::size_t index, haptics::HapticModel& model) {
    customized.push_back(index);
    EXPECT_EQ(model.contact(), nullptr);  // the scene gave it no algorithm
    model.algorithms.push_back(std::make_shared<SpringWall>(300.0));
  };
  const SessionReport r = run_session(m, o);
  EXPECT_EQ(customized, std::vector<std::size_t>{0});
  // Past the 5 ms ramp in, every frame sends the spring's force at the pose it read.
  std::size_t checked = 0;
  for (const HapticFrame& f : r.frames) {
    if (f.flags & frame_ramping) continue;
    const double expected = f.position.z() < 0.0 ? -300.0 * f.position.z() : 0.0;
    ASSERT_NEAR(f.force.z(), expected, 1e-12) << "t = " << f.t;
    EXPECT_EQ(f.contact, f.position.z() < 0.0 ? 1 : 0);
    checked += f.contact;
  }
  EXPECT_GT(checked, 200u);
  // 10 mm below the wall at the end: 3 N.
  EXPECT_NEAR(r.devices[0].max_force_sent, 3.0, 0.01);
}

TEST(Session, CustomizeHapticsCannotGiveADeviceTwoContactAlgorithms) {
  SessionOptions o = lockstep(0.1);
  o.customize_haptics = [](const scene::Model&, std::size_t, haptics::HapticModel& model) {
    model.algorithms.push_back(std::make_shared<SpringWall>(300.0));  // beside the scene's proxy
  };
  EXPECT_THROW(run_session(scene::default_scene(), o), std::invalid_argument);
}

TEST(Session, ReplayOfADeviceTheSceneLacksIsAnError) {
  SessionOptions o = lockstep(0.1);
  o.replay["elsewhere"] = RecordedMotion{{haptics::TimedPose{}}, "other.tacrec"};
  EXPECT_THROW(run_session(scene::default_scene(), o), InputError);
}

}  // namespace
}  // namespace tactus::runtime
