// Every bundled scenario, run whole in lockstep, touches the way it means to: no contact
// chatter (contacts or gaps shorter than 50 ms inside a touch) and no jolt (a change of the
// force sent to the hand of more than 1 N from one frame to the next), except where a needle
// tears a layer, whose give is the point.
//
// 1 N a frame: the smooth scenarios step by at most 0.37 N (the bone press, the stiffest
// tissue); a trainee's hand takes 1 N within a millisecond on a contact of a few newtons as a
// jolt. 50 ms: a touch that lasts less, or a lift shorter than that, is no intended touch at
// the speeds of these scenarios (2-80 mm/s). Short contacts and gaps are also counted apart
// where they are felt: the force reaches 0.05 N in one or on the frames either side of it.
// That line is a choice (a twentieth of the palpation trainers' 1 N safe force): it tells a
// grazing contact whose flag flickers at a few millinewtons from a touch that comes and goes.
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
constexpr double kFelt = 0.05;         // [N]
constexpr double kRuptureWindow = 0.003;  // [s]: a tearing layer's give

struct Smoothness {
  int short_segments = 0;  ///< contacts or gaps under kShortSegment, not the first or last
  int felt_short_segments = 0;  ///< of those, the ones where the force reaches kFelt
  double max_jump = 0.0;   ///< [N], needle ruptures left out
  double jump_time = 0.0;  ///< [s]
};

struct KnownDefect {
  const char* scene;
  const char* device;
  int short_segments;
  int felt_short_segments;
  double max_jump;  // [N]
};

const std::vector<KnownDefect> kKnownDefects = {
    // The fingertip grazes a sheet sagging away from it, in contact at 0.1-35 mN, and the
    // contact flag flickers at the simulation rate, mostly without a felt force. Which
    // flickers come near a felt force follows round-off and the path: with the local patch's
    // response in single precision 438 flickers, 2 of them beside 0.09-0.16 N (before: 440,
    // none); since the scan comes down onto the sheet from 7 mm above it (`approach`) 360,
    // 3 of them beside 0.050-0.066 N. When the scan started 3 mm into the sheet the contact
    // law on the local patch rang while the sheet settled under it (1.47 N at t = 0.03 s);
    // landing from above, the largest step was 0.36 N, within the general bound. Since the
    // safety layer's onset blends from the force sent (a contact back within its release no
    // longer restarts from zero) the force holds through a flicker instead of dipping, and
    // the flag flickers more in the same stretches of the scan (377 contact onsets where it
    // had 242): 561, 7 of them beside 0.051-0.107 N, where the force sent holds through the
    // flips (at 10.870-10.875 s it stays at 0.051 N over five of them). The largest step is
    // 0.50 N (0.339 s), the contact law ringing on the patch as the probe lands.
    {"skin_patch", "probe", 561, 7, kMaxJump},
    // A simulated operator's hand brought down onto the coarse organ from above (`approach`)
    // grazes its surface where the scan runs off it (4.62 s and 14.64 s): 4 contacts or gaps
    // under 50 ms at 1.5-8 mN, none felt. When the hand started inside the organ, its first
    // published surface (t = 0.04 s) landed around it, the safety layer ramped the push-out
    // in over 5 ms to 6.2 N and the passivity controller cut it to 2.9 N: 3.6 N in a frame.
    // Between the organ's 25 Hz steps the hand feels a local patch softer than the organ, and
    // the force steps at each step: up to 0.95 N in a frame, 0.64 N (at 1.28 s) since the
    // steps are smoothed over 5 ms (`force_smoothing`).
    {"liver_cspace", "hand", 4, 0, 0.7},
    // Fingertips on a hanging fabric (V-proxy on the fabric's local patch): at each simulation
    // update the global step has carried the fabric about 40 µm further along the push than
    // the local patch under the finger did, so the force drops by k·40 µm (7.6 mN at 190 N/m)
    // for a frame, a 100 Hz sawtooth; where the press is lighter than that (the thumb held on
    // a swinging sheet, the index rubbing) the touch is lost for that frame. Seed 002 §IV
    // hands the local patch's geometry back to the global model at each step, which the
    // runtime does not do (tried: it made real-time runs unstable, docs/BENCHMARKS.md). When
    // the pads open after the lift (4.23 s) the V-proxies meet
    // the bunched fabric afresh; their force now comes in over 20 ms (it stepped by 1.09 N
    // and 0.94 N). The slipping pinch stepped the force by 0.58 N and 0.71 N at 2.71 s when it
    // took hold of a fold of the sheet off the pads' plane; it holds no such point since, and
    // the largest steps are 0.12 N (thumb, 4.19 s) and 0.28 N (index, 4.25 s, where the
    // V-proxy's contact chatters for 90 ms after the release). The flicker count follows how
    // the fabric swings, which each change of the hand-over or of the sheet's solve moves:
    // before the hand-over 62 / 24 (thumb, short / felt) and 231 / 24 (index); with it 72 / 26
    // and 223 / 20; with it and the sheet solved directly (CHOLMOD instead of CG at 1e-4)
    // 70 / 23 and 223 / 27, 293 / 50 for the pair; with the patch's response in single
    // precision 70 / 23 and 225 / 29; with the pinch holding no fold 50 / 6 and 237 / 39 (the
    // index's release chatter, 4.23-4.32 s, 22 short contacts where it had 10, up to 0.29 N
    // where it reached 0.48 N). A contact back while its release blended out restarted the
    // safety layer's onset ramp from zero, a dip of the whole contact force (0.09-0.21 N at
    // 4.23-4.27 s on the index); since the onset blends from the force sent 34 / 0 and 377 / 32,
    // largest steps 0.114 N (thumb, 4.200 s) and 0.222 N (index, 4.280 s); since the grasp
    // starts where the pads close on the sheet (one held point for both fingers) 34 / 0 and
    // 373 / 27, largest steps 0.117 N (thumb, 3.850 s) and 0.181 N (index, 4.277 s). The
    // index's extra flickers are in its light rub (0.8-1.6 s, 10-20 mN: 174 contact onsets
    // where it had 107), where the force sent now holds through each of them. Most of those
    // flickers were one defect: fabric sliding under a V-proxy carried it past the friction
    // cone, millimetres off the finger, where it lost the sheet and found it again a frame
    // later. Since the proxy slips on such fabric with the kinetic force, and the grasp holds
    // the sheet between the pads in the simulation, the index has 0 / 0 and 0.123 N (5.600 s,
    // skin on skin). The thumb then has 28 / 17 and 0.170 N (4.228 s): the pinch's hold is
    // at the pads when they open (it lagged 13 mm behind them), and the stretched sheet springs
    // back onto the thumb, which it touches for 70 ms at up to 0.40 N, slipping down its pad; the
    // V-proxy loses it where the sheet curves round the pad (a face's plane, not the sheet,
    // under the proxy) and finds it again. Since the hold along the pads' plane holds the point
    // in the whole plane in the simulation (the real-time grasp's 0.3-0.5 N steps at updates,
    // gone) the release goes otherwise: the thumb 24 / 13 and 0.172 N (4.224 s), the index
    // one unfelt touch of 24 mN at 4.261 s (1 / 0).
    {"fabric", "thumb", 24, 13, 0.173},
    {"fabric", "index", 1, 0, 0.13},
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
  // The device's contacts and gaps: when each began and the largest force in it or on the
  // frames either side of it.
  struct Segment {
    double begin = 0.0, peak = 0.0;
  };
  std::vector<Segment> segments;
  for (const HapticFrame& f : r.frames) {
    if (f.device != device) continue;
    const double force = f.force.norm();
    if (last) {
      const double jump = (f.force - last->force).norm();
      if (jump > s.max_jump && !tearing(f.t)) s.max_jump = jump, s.jump_time = f.t;
      if (f.contact != last->contact) segments.push_back({f.t, std::max(force, last->force.norm())});
    }
    if (!segments.empty()) segments.back().peak = std::max(segments.back().peak, force);
    if (segments.size() > 1 && segments.back().begin == f.t)
      segments[segments.size() - 2].peak = std::max(segments[segments.size() - 2].peak, force);
    last = &f;
  }
  // Segments between two changes are whole contacts or gaps inside the run.
  for (std::size_t i = 1; i < segments.size(); ++i)
    if (segments[i].begin - segments[i - 1].begin < kShortSegment) {
      ++s.short_segments;
      if (segments[i - 1].peak >= kFelt) ++s.felt_short_segments;
    }
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
    std::printf("%s / %s: %d short contacts or gaps (%d felt), largest step %.3f N at %.3f s%s\n",
                GetParam().c_str(), name.c_str(), s.short_segments, s.felt_short_segments, s.max_jump, s.jump_time,
                known ? " (known defect)" : "");
    EXPECT_LE(s.short_segments, known ? known->short_segments : 0);
    EXPECT_LE(s.felt_short_segments, known ? known->felt_short_segments : 0);
    EXPECT_LE(s.max_jump, known ? known->max_jump : kMaxJump) << "at t = " << s.jump_time;
  }
}

// Every bundled scene with a device but liver.toml, whose whole run (30 s of lockstep on a
// 12,298-tet neo-Hookean body, about 6 s of wall clock per simulated second here) is too long
// for the suite: its first 2.5 s run below.
const std::vector<std::string> kScenarios = {"default",         "nodule",           "tissues",
                                             "needle_block",    "pulse_demo",       "skin_patch",
                                             "femoral",         "femoral_s1_idle",  "femoral_s2_palpation",
                                             "femoral_s3_needle", "femoral_labels",  "liver_cspace",
                                             "fabric",          "room"};

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
  // Within kMaxJump, as every scene. Until 2026-11-29 the force's direction flipped from frame
  // to frame by up to 1.47 N from t = 0.15 s on: the finger's load went to the contact
  // triangle's three corners, dug a pit in the 2 mm mesh, and the finger touched its rim here
  // and there. Shared over the Hertz disc (load_spread = "contact_disc") the largest step is
  // 0.544 N, at the hand's landing (0.099 s); 0.294 N at 2.13 s since the passivity
  // controller damps no harder than the device's max_damping.
  EXPECT_LE(s.short_segments, 0);
  EXPECT_LE(s.max_jump, kMaxJump) << "at t = " << s.jump_time;
}

// A scene added to scenes/ joins the list above (or says here why not).
TEST(ScenarioSmoothness, CoversEveryBundledSceneWithADevice) {
  std::vector<std::string> listed = kScenarios;
  listed.push_back("liver");  // left out above, and why
  // Felt from their spaces, which probe_scene_test.cpp and pair_scene_test.cpp build and run,
  // bounding the largest step as here. Simulated, with the weight their spaces leave out, the
  // organ sags below the tools' reach and no frame touches it.
  listed.insert(listed.end(), {"liver_probe", "liver_pair"});
  for (const auto& entry : fs::directory_iterator(fs::path(TACTUS_SOURCE_DIR) / "scenes")) {
    if (entry.path().extension() != ".toml") continue;
    if (scene::load_scene(entry.path()).devices.empty()) continue;
    const std::string name = entry.path().stem().string();
    EXPECT_NE(std::find(listed.begin(), listed.end(), name), listed.end()) << name;
  }
}

}  // namespace
}  // namespace tactus::runtime
