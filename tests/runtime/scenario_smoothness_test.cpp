// Every bundled scenario, run whole in lockstep, touches the way it means to: no contact
// chatter (contacts or gaps shorter than 50 ms inside a touch) and no jolt (a change of the
// force sent to the hand of more than 1 N from one frame to the next), except where a needle
// tears a layer, whose give is the point.
//
// 1 N a frame: the smooth scenarios step by at most 0.37 N (the bone press, the stiffest
// tissue); a trainee's hand takes 1 N within a millisecond on a contact of a few newtons as a
// jolt. 50 ms: a touch that lasts less, or a lift shorter than that, is no intended touch at
// the speeds of these scenarios (2-80 mm/s).
//
// Some scenarios do not meet this yet; each is listed with what it measured when the list
// was written and why, and may not get worse. Remove an entry when its cause is fixed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "runtime/session.hpp"
#include "scene/scene.hpp"

namespace tactus::runtime {
namespace {

namespace fs = std::filesystem;

constexpr double kMaxJump = 1.0;       // [N] per haptic frame
constexpr double kShortSegment = 0.05; // [s]
constexpr double kRuptureWindow = 0.003;  // [s]: a tearing layer's give

struct Smoothness {
  int short_segments = 0;  ///< contacts or gaps under kShortSegment, not the first or last
  double max_jump = 0.0;   ///< [N], needle ruptures left out
  double jump_time = 0.0;  ///< [s]
};

struct KnownDefect {
  const char* scene;
  const char* device;
  int short_segments;
  double max_jump;  // [N]
};

// The forces the simulation takes from the hand are applied as a constant load over its
// step (explicit coupling): where the tissue under the finger is softer than the coupling, a
// step overshoots, the finger loses the surface or lands behind it, and the next step swings
// back. Fixing it needs the coupling's stiffness in the simulation's implicit step.
const std::vector<KnownDefect> kKnownDefects = {
    // Touch-down: the scan starts 5 mm into the skin; the sheet drops 7 mm under the first
    // load in one 10 ms step and the proxy is on its far side for a frame (t = 0.02 s).
    {"nodule", "finger", 0, 3.2},
    // A soft sheet that sags away from a fingertip grazing it at 600 N/m.
    {"skin_patch", "probe", 380, 12.8},
    // A simulated operator's hand landing on the organ at 8.5 N (clamped) and bouncing.
    {"liver_cspace", "hand", 26, 7.4},
};

Smoothness measure(const SessionReport& r, std::size_t device, const std::string& name) {
  std::vector<double> ruptures;
  for (const NeedleReport& n : r.needles)
    if (n.device == name)
      for (const NeedleRuptureReport& p : n.ruptures) ruptures.push_back(p.t);
  auto tearing = [&](double t) {
    for (double at : ruptures)
      if (t >= at - 1e-9 && t <= at + kRuptureWindow) return true;
    return false;
  };
  Smoothness s;
  const HapticFrame* last = nullptr;
  std::vector<double> changes;  // times at which contact began or ended
  for (const HapticFrame& f : r.frames) {
    if (f.device != device) continue;
    if (last) {
      const double jump = (f.force - last->force).norm();
      if (jump > s.max_jump && !tearing(f.t)) s.max_jump = jump, s.jump_time = f.t;
      if (f.contact != last->contact) changes.push_back(f.t);
    }
    last = &f;
  }
  // Segments between two changes are whole contacts or gaps inside the run.
  for (std::size_t i = 1; i < changes.size(); ++i)
    if (changes[i] - changes[i - 1] < kShortSegment) ++s.short_segments;
  return s;
}

class ScenarioSmoothness : public ::testing::TestWithParam<std::string> {};

TEST_P(ScenarioSmoothness, NoChatterAndNoJolt) {
  const scene::Model m = scene::load_scene(fs::path(TACTUS_SOURCE_DIR) / "scenes" / (GetParam() + ".toml"));
  ASSERT_FALSE(m.devices.empty());
  SessionOptions o;
  o.scheduling = Scheduling::lockstep;
  o.keep_frames = true;
  const SessionReport r = run_session(m, o);
  ASSERT_GT(r.simulated_time, 0.5);
  for (std::size_t d = 0; d < m.devices.size(); ++d) {
    const std::string& name = m.devices[d].name;
    SCOPED_TRACE(GetParam() + " / " + name);
    const Smoothness s = measure(r, d, name);
    const KnownDefect* known = nullptr;
    for (const KnownDefect& k : kKnownDefects)
      if (GetParam() == k.scene && name == k.device) known = &k;
    std::printf("%s / %s: %d short contacts or gaps, largest step %.3f N at %.3f s%s\n", GetParam().c_str(),
                name.c_str(), s.short_segments, s.max_jump, s.jump_time, known ? " (known defect)" : "");
    EXPECT_LE(s.short_segments, known ? known->short_segments : 0);
    EXPECT_LE(s.max_jump, known ? known->max_jump : kMaxJump) << "at t = " << s.jump_time;
  }
}

// Every bundled scene with a device but liver.toml, whose whole run (30 s of lockstep on a
// 12,298-tet neo-Hookean body, about 6 s of wall clock per simulated second here) is too long
// for the suite: its first 2.5 s run below.
const std::vector<std::string> kScenarios = {"default",         "nodule",           "tissues",
                                             "needle_block",    "pulse_demo",       "skin_patch",
                                             "femoral",         "femoral_s1_idle",  "femoral_s2_palpation",
                                             "femoral_s3_needle", "liver_cspace"};

INSTANTIATE_TEST_SUITE_P(Bundled, ScenarioSmoothness, ::testing::ValuesIn(kScenarios),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

// liver.toml diverged at t = 1.65 s: the finger's load landed on a surface node above thin
// elements, one linearized implicit step pushed the node through them, and the inverted
// elements' next linearization flung the body to 10^13 m, where the Cholesky factorization
// failed ("not positive definite"). Implicit steps that would turn an element inside out are
// now taken in halves (physics/integrator.cpp).
TEST(ScenarioSmoothness, LiverRunsPastTheStepThatTurnedItsElementsInsideOut) {
  const scene::Model m = scene::load_scene(fs::path(TACTUS_SOURCE_DIR) / "scenes/liver.toml");
  SessionOptions o;
  o.scheduling = Scheduling::lockstep;
  o.keep_frames = true;
  o.duration = 2.5;
  const SessionReport r = run_session(m, o);
  EXPECT_GE(r.simulated_time, 2.5 - 1e-9);
  ASSERT_EQ(r.devices.size(), 1u);
  EXPECT_EQ(r.devices[0].safety.non_finite, 0u);
  EXPECT_EQ(r.devices[0].safety.clamped, 0u);
  const Smoothness s = measure(r, 0, m.devices[0].name);
  std::printf("liver / hand, first 2.5 s: %d short contacts or gaps, largest step %.3f N at %.3f s\n",
              s.short_segments, s.max_jump, s.jump_time);
  // Not yet within kMaxJump, as the known defects above: frame-to-frame steps of 1.0-1.25 N
  // from t = 0.15 s on, before the halved step (measured 1.248 N at 1.96 s). May not get worse.
  EXPECT_LE(s.short_segments, 0);
  EXPECT_LE(s.max_jump, 1.3) << "at t = " << s.jump_time;
}

// A scene added to scenes/ joins the list above (or says here why not).
TEST(ScenarioSmoothness, CoversEveryBundledSceneWithADevice) {
  std::vector<std::string> listed = kScenarios;
  listed.push_back("liver");  // left out above, and why
  for (const auto& entry : fs::directory_iterator(fs::path(TACTUS_SOURCE_DIR) / "scenes")) {
    if (entry.path().extension() != ".toml") continue;
    if (scene::load_scene(entry.path()).devices.empty()) continue;
    const std::string name = entry.path().stem().string();
    EXPECT_NE(std::find(listed.begin(), listed.end(), name), listed.end()) << name;
  }
}

}  // namespace
}  // namespace tactus::runtime
