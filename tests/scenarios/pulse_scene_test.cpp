// The pulse and the multiple-surface algorithm end to end: how a tool's algorithms compose
// (a contact algorithm plus a pulse, `enabled` honoured), and a lockstep run of the bundled
// scenes/pulse_demo.toml whose force trace has the configured rate and duty cycle.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "core/counting_allocator.hpp"
#include "core/error.hpp"
#include "haptics/algorithms/pulse.hpp"
#include "haptics/algorithms/multi_surface_algorithm.hpp"
#include "haptics/algorithms/proxy_on_patch.hpp"
#include "haptics/algorithms/pulse_overlay.hpp"
#include "compile/device_setup.hpp"
#include "runtime/loop_set.hpp"
#include "runtime/session.hpp"
#include "scene/scene.hpp"

namespace tactus {
namespace {

namespace fs = std::filesystem;

/// A block, a vessel inside it and a fingertip; `algorithms` completes the scene.
std::string scene_with(const std::string& algorithms) {
  return R"([materials.soft]
young_modulus = 5e4
poisson_ratio = 0.45
density = 1050

[bodies.block]
kind = "fem"
material = "soft"
mesh = { generator = "box", size = [0.04, 0.02, 0.02], cells = [2, 1, 1], translate = [0, 0, -0.01] }
[[bodies.block.fixed]]
side = "z_min"

[bodies.vessel]
kind = "rigid"
mesh = { generator = "box", size = [0.03, 0.004, 0.004], translate = [0, 0, -0.008] }

[devices.hand]
type = "scripted"
trajectory = { type = "press", position = [0, 0, 0.01], depth = 0.004 }

[tools.finger]
type = "sphere"
device = "hand"
radius = 0.008
)" + algorithms;
}

const std::string kPulse = R"(
[algorithms.beat]
type = "pulse"
tool = "finger"
body = "vessel"
sources = 3
)";
const std::string kProxy = R"(
[algorithms.touch]
type = "proxy"
tool = "finger"
bodies = ["block"]
)";

TEST(PulseScene, ThePulseComposesWithTheContactAlgorithmInAnyOrder) {
  for (const std::string& text : {scene_with(kProxy + kPulse), scene_with(kPulse + kProxy)}) {
    const scene::Model m = scene::parse_scene(text, "p.toml");
    const compile::DeviceSetup s = compile::setup_device(m, 0);
    EXPECT_NE(s.model.find<haptics::ProxyOnPatch>(), nullptr);  // the default local model: a patch
    const auto* pulse = s.model.find<haptics::PulseOverlay>();
    ASSERT_NE(pulse, nullptr);
    // Three sources along the vessel's long axis (x), at the centres of its thirds.
    const auto& sources = pulse->pulse().config().sources;
    ASSERT_EQ(sources.size(), 3u);
    double xs = 0.0;
    for (const Vec3& p : sources) {
      EXPECT_NEAR(p.y(), 0.0, 1e-12);
      EXPECT_NEAR(p.z(), -0.008, 1e-12);
      xs += std::abs(p.x());
    }
    EXPECT_NEAR(xs, 0.01 + 0.01, 1e-12);  // −0.01, 0, 0.01
  }
}

TEST(PulseScene, EnabledIsHonouredAndAPulseNeedsSomethingToPressWith) {
  const scene::Model off = scene::parse_scene(scene_with(kProxy + kPulse + "enabled = false\n"), "p.toml");
  EXPECT_EQ(compile::setup_device(off, 0).model.find<haptics::PulseOverlay>(), nullptr);
  const scene::Model alone = scene::parse_scene(scene_with(kPulse), "p.toml");
  try {
    (void)compile::setup_device(alone, 0);
    ADD_FAILURE() << "a pulse without a contact algorithm was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("algorithm 'beat': a pulse is felt by pressing"), std::string::npos) << e.what();
  }
  const scene::Model no_contact =
      scene::parse_scene(scene_with(kProxy + "enabled = false\n" + kPulse), "p.toml");
  EXPECT_THROW((void)compile::setup_device(no_contact, 0), InputError);
}

TEST(PulseScene, MultiSurfaceTakesItsLayersOutermostFirst) {
  const scene::Model m = scene::parse_scene(scene_with(R"(
[algorithms.palpate]
type = "multi_surface"
tool = "finger"
bodies = ["block", "vessel"]
stiffness = 5000
)"),
                                            "p.toml");
  const compile::DeviceSetup s = compile::setup_device(m, 0);
  const auto* multi = s.model.find<haptics::MultiSurfaceAlgorithm>();
  ASSERT_NE(multi, nullptr);
  EXPECT_EQ(multi->bodies(), (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(multi->config().layers, 2u);
  EXPECT_EQ(multi->config().radius, 0.008);
  // Never stiffer than the device renders stably (max_stiffness defaults to 2000 N/m).
  EXPECT_EQ(multi->config().stiffness, 2000.0);
  EXPECT_GT(s.needle_length, 0.0);  // the interaction loop casts its ray
}

TEST(PulseSession, TheForceTraceHasTheConfiguredRateAndDutyCycle) {
  const scene::Model m = scene::load_scene(fs::path(TACTUS_SOURCE_DIR) / "scenes/pulse_demo.toml");
  const scene::Algorithm* a = m.find_algorithm("pulse");
  ASSERT_NE(a, nullptr);
  const auto& p = std::get<scene::PulseParams>(a->params);
  runtime::SessionOptions o;
  o.scheduling = runtime::Scheduling::lockstep;
  o.keep_frames = true;
  const runtime::SessionReport r = runtime::run_session(m, o);
  ASSERT_GT(r.frames.size(), 5000u);

  const double max_force = m.devices.front().max_force;
  bool touched = false;
  for (const runtime::HapticFrame& f : r.frames) {
    ASSERT_TRUE(f.force.allFinite()) << f.t;
    EXPECT_LT(f.force.norm(), max_force);
    touched = touched || f.contact;
    if (!touched) {
      EXPECT_EQ(f.force.norm(), 0.0) << "a pulse felt before pressing, at " << f.t;
    }
  }
  EXPECT_EQ(r.devices.front().safety.clamped, 0u);
  EXPECT_EQ(r.events.at("contact_begin"), 1u);  // one press, no chatter

  // Edges of the beats: frame-to-frame changes of the force magnitude larger than 0.05 N.
  // The pulse steps by about 0.24 N here, while the press itself, on smoothed and blended
  // planes, changes the force by about 1e-5 N a frame (measured on this scene).
  std::vector<double> rises, falls;
  std::vector<double> steps;
  for (std::size_t k = 1; k < r.frames.size(); ++k) {
    const runtime::HapticFrame &f = r.frames[k], &before = r.frames[k - 1];
    if (!f.contact || !before.contact) continue;
    const double change = f.force.norm() - before.force.norm();
    if (change > 0.05) {
      rises.push_back(f.t);
      steps.push_back(change);
      // The step is the pulse law's A · fade(d) · orientation at the fingertip's centre: at
      // most A · fade(d) for the nearest source, and at least 90% of it (the push direction
      // is within 25° of the source's direction above the artery).
      const Vec3 centre = f.position;  // the scene's device map is the identity
      double d = std::numeric_limits<double>::infinity();
      for (const Vec3& s : haptics::pulse_sources_along_axis(m.bodies[p.body].simulation_vertices(), p.sources))
        d = std::min(d, (centre - s).norm());
      const double fade = d < p.range ? std::pow(1.0 - d / p.range, 2) : 0.0;
      EXPECT_LE(change, p.amplitude * fade + 1e-6) << f.t;
      EXPECT_GE(change, 0.9 * p.amplitude * fade) << f.t;
    }
    if (change < -0.05) falls.push_back(f.t);
  }
  // The hold lasts 6 s: 8 to 10 beats at 90 beats/min.
  ASSERT_GE(rises.size(), 8u);
  ASSERT_EQ(falls.size(), rises.size());
  const double period = 60.0 / p.rate;
  const double haptic_period = 1.0 / m.rates.haptic;
  // Within one haptic period: the edges are seen on its frames.
  const double measured_period = (rises.back() - rises.front()) / static_cast<double>(rises.size() - 1);
  EXPECT_NEAR(measured_period, period, haptic_period);
  for (std::size_t i = 0; i < rises.size(); ++i) {
    EXPECT_GT(falls[i], rises[i]);
    EXPECT_NEAR(falls[i] - rises[i], p.duty_cycle * period, haptic_period) << "beat " << i;
    if (i > 0) {
      EXPECT_NEAR(rises[i] - rises[i - 1], period, haptic_period) << "beat " << i;
    }
  }
}

TEST(PulseSession, TheHapticLoopAllocatesNothingWhilePressingThroughThePulse) {
  const scene::Model m = scene::load_scene(fs::path(TACTUS_SOURCE_DIR) / "scenes/pulse_demo.toml");
  runtime::SessionOptions o;
  o.scheduling = runtime::Scheduling::lockstep;
  runtime::Loops loops = runtime::build_loops(m, o);
  std::uint64_t sim_steps = 0, inter_steps = 0, haptic_allocations = 0;
  // The scene's lockstep order up to 2 s: the press (contact at 0.2 s) and two beats.
  for (std::uint64_t k = 0; k <= 2000; ++k) {
    const double t = static_cast<double>(k) / m.rates.haptic;
    for (; static_cast<double>(sim_steps) / m.rates.simulation <= t; ++sim_steps)
      loops.simulation->step(static_cast<double>(sim_steps) / m.rates.simulation, 0, 0, false);
    for (; static_cast<double>(inter_steps) / m.rates.interaction <= t; ++inter_steps)
      loops.interaction->step(static_cast<double>(inter_steps) / m.rates.interaction, 0, 0, false);
    testing::AllocationCounter counter;
    loops.haptic.front()->step(t, 0, 0, false);
    haptic_allocations += counter.count();
  }
  EXPECT_EQ(haptic_allocations, 0u);
  EXPECT_GT(loops.haptic.front()->stats().steps, 2000u);
}

}  // namespace
}  // namespace tactus
