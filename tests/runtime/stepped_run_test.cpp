// A lockstep run stepped frame by frame by its caller: the frames of run_session's lockstep
// scheduler bit for bit, and devices whose pose the caller sets.
#include <gtest/gtest.h>

#include <stdexcept>

#include "core/error.hpp"
#include "runtime/devices.hpp"
#include "runtime/session.hpp"
#include "runtime/stepped_run.hpp"
#include "scene/scene.hpp"

namespace tactus::runtime {
namespace {

SessionOptions keeping_frames() {
  SessionOptions o;
  o.scheduling = Scheduling::lockstep;
  o.keep_frames = true;
  return o;
}

void expect_same_frames(const std::vector<HapticFrame>& a, const std::vector<HapticFrame>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].t, b[i].t) << i;
    ASSERT_EQ(a[i].position, b[i].position) << i;
    ASSERT_EQ(a[i].force, b[i].force) << i;
    ASSERT_EQ(a[i].proxy, b[i].proxy) << i;
    ASSERT_EQ(a[i].contact, b[i].contact) << i;
    ASSERT_EQ(a[i].flags, b[i].flags) << i;
  }
}

TEST(SteppedRun, StepsTheFramesOfALockstepSessionBitForBit) {
  const scene::Model m = scene::default_scene();
  SessionOptions o = keeping_frames();
  o.duration = 1.5;
  const SessionReport whole = run_session(m, o);

  SteppedRun run(m, keeping_frames());
  EXPECT_EQ(run.frames(), 0u);
  while (run.frames() < whole.frames.size()) run.step();
  EXPECT_DOUBLE_EQ(run.time(), 1.5);
  EXPECT_EQ(run.latest_frames()[0].t, run.time());
  EXPECT_EQ(run.latest_frames()[0].force, whole.frames.back().force);
  ASSERT_NE(run.positions(0), nullptr);
  EXPECT_GT(run.positions(0)->size(), 0);
  const SessionReport stepped = run.finish();
  expect_same_frames(stepped.frames, whole.frames);
  EXPECT_GT(stepped.devices[0].contact_frames, 500u);  // the comparison covers contact
  EXPECT_EQ(stepped.devices[0].contact_frames, whole.devices[0].contact_frames);
  EXPECT_DOUBLE_EQ(stepped.simulated_time, 1.5);
}

TEST(SteppedRun, AControlledDeviceFedTheScriptedPosesFeelsTheSameForces) {
  const scene::Model m = scene::default_scene();
  SessionOptions o = keeping_frames();
  o.duration = 1.5;
  const SessionReport whole = run_session(m, o);

  SteppedRun run(m, keeping_frames(), {m.devices[0].name});
  ASSERT_TRUE(run.controlled(0));
  const auto script = make_device(m, 0);  // the scene's device, read by hand here
  while (run.frames() < whole.frames.size()) {
    run.set_pose(0, script->read(static_cast<double>(run.frames()) / m.rates.haptic));
    run.step();
  }
  const SessionReport stepped = run.finish();
  EXPECT_STREQ(stepped.devices[0].kind.c_str(), "controlled");
  expect_same_frames(stepped.frames, whole.frames);
}

TEST(SteppedRun, RefusesWhatItCannotDo) {
  const scene::Model m = scene::default_scene();
  EXPECT_THROW(SteppedRun(m, {}, {"no such device"}), InputError);
  SteppedRun run(m, {});
  EXPECT_FALSE(run.controlled(0));
  EXPECT_THROW(run.set_pose(0, {}), std::invalid_argument);
  run.step();
  (void)run.finish();
  EXPECT_TRUE(run.finished());
  EXPECT_THROW(run.step(), std::logic_error);
  EXPECT_EQ(run.latest_frames().size(), 1u);  // still readable
}

}  // namespace
}  // namespace tactus::runtime
