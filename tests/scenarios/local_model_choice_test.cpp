// Which local model is the default (issue 7, "compare the two on force error against a
// simulation run at the haptic rate, and keep the better as default"): plane, compliance and
// mass_spring on the default scene and on the press-and-slide block, each against the same
// scene simulated at the haptic rate, and on the stiff-tissue stability scene for passivity.
// Lockstep runs: deterministic, so the table it prints is the same on any machine.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <variant>
#include <vector>

#include "runtime/session.hpp"
#include "scene/scene.hpp"

namespace tactus::runtime {
namespace {

namespace fs = std::filesystem;
using LocalModel = contact::LocalModelKind;

constexpr LocalModel kModels[] = {LocalModel::plane, LocalModel::compliance, LocalModel::mass_spring};

const char* name(LocalModel m) {
  switch (m) {
    case LocalModel::plane: return "plane";
    case LocalModel::compliance: return "compliance";
    case LocalModel::mass_spring: return "mass_spring";
  }
  return "?";
}

std::vector<HapticFrame> run(const scene::Model& m) {
  SessionOptions o;
  o.scheduling = Scheduling::lockstep;
  o.keep_frames = true;
  return run_session(m, o).frames;
}

/// The scene with the simulation (and its bodies' steps) at `rate` and every algorithm on `local`.
scene::Model configure(scene::Model m, double rate, LocalModel local) {
  m.rates.simulation = rate;
  for (scene::Body& b : m.bodies) b.time_step = std::min(b.time_step, 1.0 / rate);
  for (scene::Algorithm& a : m.algorithms) {
    a.local_model = local;
    a.force_smoothing = 0.0;  // the models themselves
  }
  return m;
}

scene::Model default_scene_short() {
  scene::Model m = scene::default_scene();
  for (scene::Device& d : m.devices)
    if (auto* scripted = std::get_if<scene::ScriptedDevice>(&d.source))
      if (auto* press = std::get_if<haptics::PressPath>(&scripted->trajectory)) press->hold = 0.3;
  return m;
}

scene::Model press_slide() {
  return scene::load_scene(fs::path(TACTUS_SOURCE_DIR) / "tests/fixtures/scenes/press_slide.toml");
}

struct Error {
  double rms = 0.0, max = 0.0;
};

/// Frame-by-frame force error over the frames where either run touches.
Error compare(const std::vector<HapticFrame>& reference, const std::vector<HapticFrame>& frames) {
  EXPECT_EQ(reference.size(), frames.size());
  Error e;
  double sum2 = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < std::min(reference.size(), frames.size()); ++i) {
    if (!reference[i].contact && !frames[i].contact) continue;
    const double d = (reference[i].force - frames[i].force).norm();
    sum2 += d * d;
    e.max = std::max(e.max, d);
    ++n;
  }
  e.rms = n ? std::sqrt(sum2 / static_cast<double>(n)) : 0.0;
  return e;
}

/// Net work of the normal force on the hand over the stiff press, as a share of the largest
/// stored contact energy F²/(2k) (the measure of runtime_session_test's stability test).
double normal_work_share(LocalModel local, scene::LoadSpread spread) {
  scene::Model m = scene::load_scene(fs::path(TACTUS_SOURCE_DIR) / "tests/fixtures/scenes/stiff_press.toml");
  for (scene::Algorithm& a : m.algorithms) {
    a.local_model = local;
    a.force_smoothing = 0.005;  // as the runtime's passivity check runs it
    a.load_spread = spread;
  }
  const std::vector<HapticFrame> frames = run(m);
  double work = 0.0, f_max = 0.0;
  for (std::size_t i = 1; i < frames.size(); ++i) {
    work += frames[i - 1].force.z() * (frames[i].position.z() - frames[i - 1].position.z());
    f_max = std::max(f_max, frames[i].force.norm());
  }
  return work / (f_max * f_max / (2.0 * 2000.0));
}

struct Passivity {
  double triangle = 0.0, disc = 0.0;  ///< net normal work / stored energy, per load spread
  [[nodiscard]] bool passes() const { return triangle < 0.01 && disc < 0.01; }
};

Passivity passivity(LocalModel model) {
  return {normal_work_share(model, scene::LoadSpread::triangle), normal_work_share(model, scene::LoadSpread::contact_disc)};
}

const LocalModel kDefault = scene::Algorithm{}.local_model;

TEST(LocalModelChoice, TheDefaultKeepsTheStabilityTestsPassivityBound) {
  std::printf("stiff press, net normal work on the hand / stored energy (bound 1%%), force smoothing 5 ms\n");
  std::printf("%-12s  triangle  contact_disc\n", "model");
  for (const LocalModel model : kModels) {
    const Passivity p = passivity(model);
    std::printf("%-12s  %7.2f%%  %11.2f%%\n", name(model), 100 * p.triangle, 100 * p.disc);
    if (model == kDefault) {
      EXPECT_LT(p.triangle, 0.01) << name(model);
      EXPECT_LT(p.disc, 0.01) << name(model);
    }
  }
  std::printf("default: %s\n", name(kDefault));
}

TEST(LocalModelChoice, TheDefaultErrsLeastOfThePassiveModels) {
  struct Row {
    LocalModel model;
    Error default_scene, block;
    double seconds = 0.0;  ///< wall time of the model's default-scene run (a loaded machine: indicative)
  };
  const auto reference_default = run(configure(default_scene_short(), 1000.0, LocalModel::plane));
  const auto reference_block = run(configure(press_slide(), 1000.0, LocalModel::plane));
  std::vector<Row> rows;
  for (const LocalModel model : kModels) {
    const auto start = std::chrono::steady_clock::now();
    const auto frames = run(configure(default_scene_short(), 100.0, model));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    rows.push_back({model, compare(reference_default, frames), compare(reference_block, run(configure(press_slide(), 100.0, model))),
                    seconds});
  }
  std::printf("force error against the 1 kHz simulation [N], simulation at 100 Hz, no force smoothing\n");
  std::printf("%-12s  default scene RMS    max   press-slide block RMS    max   default-scene run [s]\n", "model");
  for (const Row& r : rows)
    std::printf("%-12s  %17.4f %7.3f  %21.4f %7.3f  %20.2f\n", name(r.model), r.default_scene.rms, r.default_scene.max,
                r.block.rms, r.block.max, r.seconds);
  std::printf("default: %s\n", name(kDefault));
  const Row& d = *std::find_if(rows.begin(), rows.end(), [&](const Row& r) { return r.model == kDefault; });
  const Row& plane = rows.front();
  if (kDefault != LocalModel::plane) {
    EXPECT_LT(d.default_scene.rms, plane.default_scene.rms);
    EXPECT_LT(d.block.rms, plane.block.rms);
  }
  // No model that keeps the passivity bound errs less than the default on both scenes.
  for (const Row& r : rows) {
    if (r.model == kDefault || !(r.default_scene.rms < d.default_scene.rms && r.block.rms < d.block.rms)) continue;
    EXPECT_FALSE(passivity(r.model).passes()) << name(r.model) << " errs less than " << name(kDefault) << " and is passive";
  }
}

}  // namespace
}  // namespace tactus::runtime
