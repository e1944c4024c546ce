// The femoral nerve-block trainer (scenes/femoral*.toml, seed 003): the patient loads with
// its layers carried by the tissue, the four scenarios share it, and lockstep runs of the
// scenarios give what the issue asks: both hands at once for their whole length with finite
// forces within the limits, the needle tearing skin, fascia lata and fascia iliaca in that
// order at their thresholds, and the pulse felt at its rate and duty cycle. The same patient
// built from a label image (femoral_labels.toml) gives the same.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "report/scenario_report.hpp"
#include "runtime/session.hpp"
#include "scene/scene.hpp"

namespace tactus {
namespace {

namespace fs = std::filesystem;

scene::Model load(const std::string& name) { return scene::load_scene(fs::path(TACTUS_SOURCE_DIR) / "scenes" / name); }

runtime::SessionReport run_lockstep(const scene::Model& m, double duration) {
  runtime::SessionOptions o;
  o.scheduling = runtime::Scheduling::lockstep;
  o.duration = duration;
  o.max_duration = 40.0;  // duration 0: the scenario's length (every scenario is under 40 s)
  o.keep_frames = true;
  return runtime::run_session(m, o);
}

/// Every frame finite and within its device's limit, nothing clamped.
void expect_sound(const scene::Model& m, const runtime::SessionReport& r) {
  for (const runtime::HapticFrame& f : r.frames) {
    ASSERT_TRUE(f.force.allFinite() && f.torque.allFinite() && f.proxy.allFinite()) << "device " << f.device << " t " << f.t;
    ASSERT_LE(f.force.norm(), m.devices[f.device].max_force) << "device " << f.device << " t " << f.t;
  }
  for (const runtime::DeviceReport& d : r.devices) EXPECT_EQ(d.safety.clamped, 0u);
}

std::size_t device_index(const scene::Model& m, const std::string& name) {
  for (std::size_t i = 0; i < m.devices.size(); ++i)
    if (m.devices[i].name == name) return i;
  ADD_FAILURE() << "no device " << name;
  return 0;
}

TEST(FemoralScene, ThePatientHasTheSeedsLayersCarriedByItsTissue) {
  const scene::Model m = load("femoral.toml");
  const scene::Body* tissue = m.find_body("tissue");
  ASSERT_NE(tissue, nullptr);
  ASSERT_TRUE(tissue->volume.has_value());
  // Seed 003 §4.3: a behaviour mesh of 1,915 tetrahedra.
  EXPECT_NEAR(static_cast<double>(tissue->volume->tets.size()), 1915.0, 100.0);
  for (const char* layer : {"skin", "fascia_lata", "fascia_iliaca", "inguinal_ligament", "femoral_artery", "femoral_vein"}) {
    const scene::Body* b = m.find_body(layer);
    ASSERT_NE(b, nullptr) << layer;
    EXPECT_EQ(b->kind, scene::BodyKind::embedded) << layer;
    EXPECT_EQ(&m.bodies[*b->host], tissue) << layer;
  }
  for (const char* bone : {"femur", "hip"}) EXPECT_EQ(m.find_body(bone)->kind, scene::BodyKind::rigid) << bone;
  ASSERT_EQ(m.devices.size(), 2u);
}

TEST(FemoralScene, TheScenariosAreThePatientWithOtherHands) {
  const scene::Model base = load("femoral.toml");
  for (const char* name : {"femoral_s1_idle.toml", "femoral_s2_palpation.toml", "femoral_s3_needle.toml"}) {
    const scene::Model s = load(name);
    EXPECT_NE(s.name, base.name) << name;
    ASSERT_EQ(s.bodies.size(), base.bodies.size()) << name;
    for (std::size_t b = 0; b < s.bodies.size(); ++b) {
      EXPECT_EQ(s.bodies[b].name, base.bodies[b].name) << name;
      EXPECT_EQ(s.bodies[b].surface.vertices.size(), base.bodies[b].surface.vertices.size()) << name;
    }
    EXPECT_EQ(s.algorithms.size(), base.algorithms.size()) << name;
    ASSERT_EQ(s.devices.size(), 2u) << name;
  }
}

TEST(FemoralLabelsScene, ThePatientIsItsSegmentationsRegionsAndTheLayersAreTheirSurfaces) {
  const scene::Model m = load("femoral_labels.toml");
  const scene::Body* tissue = m.find_body("tissue");
  ASSERT_NE(tissue, nullptr);
  ASSERT_TRUE(tissue->volume.has_value());
  // Eight labels, eight regions; the fat and the vessels take their own materials.
  std::set<int> regions(tissue->volume->tet_regions.begin(), tissue->volume->tet_regions.end());
  EXPECT_EQ(regions, (std::set<int>{1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(tissue->region_materials.size(), 6u);
  // Every layer is carried by the tissue, vertex on node.
  for (const char* layer : {"skin", "fascia_lata", "fascia_iliaca", "inguinal_ligament", "femoral_artery",
                            "femoral_vein", "femur", "hip"}) {
    const scene::Body* b = m.find_body(layer);
    ASSERT_NE(b, nullptr) << layer;
    EXPECT_EQ(&m.bodies[*b->host], tissue) << layer;
    EXPECT_LT(b->host_mapping->max_outside_distance(), 1e-12) << layer;
  }
  // The layers lie where the segmentation put them (meshes/femoral_labels.py): under the
  // needle's path (x −14 mm, y −23 to −13 mm) the skin at 0, the fascia lata at −8 mm, the
  // fascia iliaca at −13 mm, each within the 1.5 mm facet distance the scene asks for.
  const auto depth_under_needle = [&](const char* layer) {
    const scene::Body& b = *m.find_body(layer);
    double highest = -1.0;
    for (const auto& t : b.surface.triangles) {
      const Vec3 c = (b.surface.vertices[t[0]] + b.surface.vertices[t[1]] + b.surface.vertices[t[2]]) / 3.0;
      if (std::abs(c.x() + 0.014) < 0.006 && c.y() > -0.026 && c.y() < -0.01) highest = std::max(highest, c.z());
    }
    return highest;
  };
  EXPECT_NEAR(depth_under_needle("skin"), 0.0, 0.0015);
  EXPECT_NEAR(depth_under_needle("fascia_lata"), -0.008, 0.0015);
  EXPECT_NEAR(depth_under_needle("fascia_iliaca"), -0.013, 0.0015);
  // The tissue on the bones is held by their labels.
  bool held = false;
  for (const scene::FixedRegion& f : tissue->fixed) held = held || f.selector == "region 6 7";
  EXPECT_TRUE(held);
}

/// Scenario S4 on the generated patient (femoral.toml) and on the segmented one
/// (femoral_labels.toml): the same hands, the same layers, the same feel.
class FemoralS4 : public ::testing::TestWithParam<std::string> {};

TEST_P(FemoralS4, TearsTheLayersInOrderAndTheHandFeelsThePulse) {
  const scene::Model m = load(GetParam());
  const runtime::SessionReport r = run_lockstep(m, 31.0);
  expect_sound(m, r);

  // The needle: skin, then fascia lata, then fascia iliaca, each at its threshold (the spring
  // grows by stiffness × 2.5 µm a frame here, so within 1%).
  ASSERT_EQ(r.needles.size(), 1u);
  const runtime::NeedleReport& n = r.needles.front();
  ASSERT_EQ(n.ruptures.size(), 3u);
  const char* order[] = {"skin", "fascia_lata", "fascia_iliaca"};
  // The times docs/scenes.md gives (lockstep is deterministic): a change that moves them
  // says so there.
  const double documented[2][3] = {{13.598, 16.453, 18.511}, {13.600, 16.437, 18.467}};
  const auto& times = documented[GetParam() == "femoral.toml" ? 0 : 1];
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(n.ruptures[i].layer, order[i]);
    EXPECT_NEAR(n.ruptures[i].t, times[i], 0.002) << order[i];
    EXPECT_GE(n.ruptures[i].force, n.ruptures[i].threshold);
    EXPECT_LT(n.ruptures[i].force, 1.01 * n.ruptures[i].threshold) << order[i];
    if (i > 0) {
      EXPECT_GT(n.ruptures[i].t, n.ruptures[i - 1].t);
    }
  }
  // The loss of resistance: the needle's force drops at each rupture.
  const std::size_t needle = device_index(m, "needle");
  for (const runtime::NeedleRuptureReport& rupture : n.ruptures) {
    double before = 0.0, after = 1e9;
    for (const runtime::HapticFrame& f : r.frames) {
      if (f.device != needle) continue;
      if (f.t < rupture.t && f.t > rupture.t - 0.0025) before = f.force.norm();
      if (f.t > rupture.t && f.t < rupture.t + 0.0025) after = std::min(after, f.force.norm());
    }
    EXPECT_LT(after, before - 0.5 * rupture.threshold) << rupture.layer;
  }

  // The pulse, while the hand holds over the artery (13–30 s): edges of the beats are
  // frame-to-frame steps of the hand's normal force above 0.1 N, 72 beats/min with duty
  // cycle 0.2. Measured: the beats' edges are 0.15–0.18 N on both patients; the press
  // changes by under 0.02 N a frame on the generated one, and by up to 0.064 N on the
  // segmented one where friction lets the skin under the finger slip (13.39 s).
  const scene::Algorithm* a = m.find_algorithm("pulse");
  ASSERT_NE(a, nullptr);
  const auto& p = std::get<scene::PulseParams>(a->params);
  const std::size_t hand = device_index(m, "hand");
  std::vector<double> rises, falls;
  const runtime::HapticFrame* before = nullptr;
  for (const runtime::HapticFrame& f : r.frames) {
    if (f.device != hand) continue;
    if (before && f.t > 13.0 && f.t < 30.0 && f.contact && before->contact) {
      // The pulse acts along the push (here within a few degrees of +z); the normal
      // component leaves out the friction's tangential steps when the skin under the held
      // finger slips as the needle moves it.
      const double change = f.force.z() - before->force.z();
      if (change > 0.1) rises.push_back(f.t);
      if (change < -0.1) falls.push_back(f.t);
    }
    before = &f;
  }
  const double period = 60.0 / p.rate, frame = 1.0 / m.rates.haptic;
  ASSERT_GE(rises.size(), 18u);  // 17 s at 1.2 beats/s: 20 beats
  ASSERT_GE(falls.size(), rises.size() - 1);
  EXPECT_NEAR((rises.back() - rises.front()) / static_cast<double>(rises.size() - 1), period, frame);
  std::size_t checked = 0;
  for (std::size_t i = 0, j = 0; i < rises.size(); ++i) {
    while (j < falls.size() && falls[j] <= rises[i]) ++j;
    if (j == falls.size()) break;
    EXPECT_NEAR(falls[j] - rises[i], p.duty_cycle * period, frame) << "beat at " << rises[i];
    ++checked;
  }
  EXPECT_GE(checked, 18u);
}

INSTANTIATE_TEST_SUITE_P(Patients, FemoralS4, ::testing::Values("femoral.toml", "femoral_labels.toml"),
                         [](const ::testing::TestParamInfo<std::string>& p) {
                           return p.param == "femoral.toml" ? std::string("Generated") : std::string("Segmented");
                         });

TEST(FemoralSession, ScenarioS2DragsTheSkinWithinTheFrictionCone) {
  // The first sweep (4–10 s) moves the hand along +x pressing lightly: friction on the skin
  // (static 0.5, kinetic 0.35 in femoral.toml) drags against the motion, the tangential
  // force never leaves the static cone, and its reaction drags the tissue (the contact load).
  const scene::Model m = load("femoral_s2_palpation.toml");
  const runtime::SessionReport r = run_lockstep(m, 10.0);
  expect_sound(m, r);
  const std::size_t hand = device_index(m, "hand");
  std::size_t frames = 0, against = 0;
  double drag = 0.0, normal = 0.0;
  for (const runtime::HapticFrame& f : r.frames) {
    if (f.device != hand || f.t < 5.0 || f.t > 9.5 || !f.contact) continue;
    ++frames;
    const double tangential = Vec2(f.force.x(), f.force.y()).norm();
    // The cone is the contact plane's; in the scene frame, the dragged skin's plane tilted
    // by up to 5° towards the drag gives Ft/Fz ≤ (μs + tan 5°)/(1 − μs tan 5°) = 0.614.
    const double tilt = std::tan(5.0 * 3.141592653589793 / 180.0);
    EXPECT_LE(tangential, (0.5 + tilt) / (1.0 - 0.5 * tilt) * f.force.z()) << f.t;
    if (f.force.x() < 0.0) ++against;
    drag += -f.force.x();
    normal += f.force.z();
  }
  ASSERT_GT(frames, 4000u);
  EXPECT_GT(static_cast<double>(against), 0.95 * static_cast<double>(frames));
  // On average between the kinetic and the static coefficient: it sticks and slips.
  EXPECT_GT(drag / normal, 0.3);
  EXPECT_LT(drag / normal, 0.5);
}

TEST(FemoralSession, ScenarioS3TearsEveryLayerAtEachOfItsThreeSites) {
  const scene::Model m = load("femoral_s3_needle.toml");
  const runtime::SessionReport r = run_lockstep(m, 0.0);
  expect_sound(m, r);
  ASSERT_EQ(r.needles.size(), 1u);
  const auto& ruptures = r.needles.front().ruptures;
  ASSERT_EQ(ruptures.size(), 9u);
  const char* order[] = {"skin", "fascia_lata", "fascia_iliaca"};
  for (std::size_t i = 0; i < ruptures.size(); ++i) {
    EXPECT_EQ(ruptures[i].layer, order[i % 3]) << i;
    EXPECT_LT(ruptures[i].force, 1.01 * ruptures[i].threshold) << i;
  }
  // The palpation hand idles: never in contact.
  const std::size_t hand = device_index(m, "hand");
  for (const runtime::HapticFrame& f : r.frames)
    if (f.device == hand) {
      ASSERT_FALSE(f.contact) << f.t;
    }
}

TEST(FemoralSession, ScenarioS1NeverTouchesAndTheMeasuresArePrinted) {
  const scene::Model m = load("femoral_s1_idle.toml");
  const runtime::SessionReport r = run_lockstep(m, 0.0);
  expect_sound(m, r);
  EXPECT_GT(r.simulated_time, 34.0);
  for (const runtime::HapticFrame& f : r.frames) {
    ASSERT_FALSE(f.contact) << f.device << " " << f.t;
  }
  const std::string table = report::format_scenario_measures(m, r);
  for (const char* row : {"hand:", "needle:", "CD ", "IN ", "solver step", "embedded surfaces", "refit"})
    EXPECT_NE(table.find(row), std::string::npos) << row << "\n" << table;
}

}  // namespace
}  // namespace tactus
