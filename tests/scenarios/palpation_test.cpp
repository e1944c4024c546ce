// The nodule palpation trainer end to end (scenes/nodule.toml, lockstep): the force map
// shows each nodule where it is, the trainee feedback matches the frames, and the recording
// keeps it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "report/force_map.hpp"
#include "runtime/recording_reader.hpp"
#include "runtime/session.hpp"
#include "scene/scene.hpp"

namespace tactus::runtime {
namespace {

namespace fs = std::filesystem;

fs::path temp_file(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "tactus_palpation_test";
  fs::create_directories(dir);
  return dir / name;
}

/// One lockstep run of the bundled scene.
struct NoduleRun {
  scene::Model model;
  SessionReport report;
  Recording recording;
};

const NoduleRun& nodule_run() {
  static const NoduleRun run = [] {
    NoduleRun r;
    r.model = scene::load_scene(fs::path(TACTUS_SOURCE_DIR) / "scenes/nodule.toml");
    SessionOptions o;
    o.scheduling = Scheduling::lockstep;
    o.keep_frames = true;
    o.record = temp_file("nodule.tacrec");
    r.report = run_session(r.model, o);
    r.recording = read_recording(*o.record);
    return r;
  }();
  return run;
}

double raster_spacing(const scene::Model& m) {
  const auto& scripted = std::get<scene::ScriptedDevice>(m.devices.at(0).source);
  return std::get<haptics::RasterPath>(scripted.trajectory).spacing;
}

// The scene runs once (it takes seconds, minutes under sanitizers); each part below checks
// one thing about that run.

void check_force_map(const NoduleRun& run) {
  const scene::Body& skin = run.model.bodies.at(0);
  ASSERT_EQ(skin.nodules.size(), 2u);
  const report::ForceMap map = report::build_force_map(run.model, 0, run.report.frames);
  const double spacing = raster_spacing(run.model);
  EXPECT_DOUBLE_EQ(map.cell, spacing);

  double finger = 0.0;
  for (const auto& t : run.model.tools) finger = std::get<scene::SphereTool>(t.shape).radius;
  std::vector<double> nodule_peaks;
  for (const scene::Nodule& n : skin.nodules) {
    // The largest cell near the nodule (within its radius and two lines more).
    double best = -1.0;
    Vec2 where = Vec2::Zero();
    for (int row = 0; row < map.rows; ++row)
      for (int column = 0; column < map.columns; ++column) {
        const Vec2 c = map.cell_center(column, row);
        const std::size_t i = map.index(column, row);
        if ((c - n.center.head<2>()).norm() <= n.radius + 2.0 * spacing && map.samples[i] > 0 && map.mean[i] > best) {
          best = map.mean[i];
          where = c;
        }
      }
    ASSERT_GT(best, 0.0) << n.name;
    EXPECT_LE((where - n.center.head<2>()).norm(), spacing + 1e-12)
        << n.name << ": peak at " << where.transpose() << ", nodule at " << n.center.head<2>().transpose();
    nodule_peaks.push_back(best);
  }
  // Bare skin, away from both nodules (beyond nodule + finger + a line) and from the rim of
  // the scan: lower everywhere than over either nodule.
  double bare_max = 0.0, bare_sum = 0.0;
  int bare_cells = 0;
  for (int row = 1; row + 1 < map.rows; ++row)
    for (int column = 1; column + 1 < map.columns; ++column) {
      const Vec2 c = map.cell_center(column, row);
      bool near = false;
      for (const scene::Nodule& n : skin.nodules)
        near = near || (c - n.center.head<2>()).norm() <= n.radius + finger + spacing;
      const std::size_t i = map.index(column, row);
      if (near || map.samples[i] == 0) continue;
      bare_max = std::max(bare_max, map.mean[i]);
      bare_sum += map.mean[i];
      ++bare_cells;
    }
  ASSERT_GT(bare_cells, 20);
  const double bare_mean = bare_sum / bare_cells;
  for (const double peak : nodule_peaks) {
    EXPECT_GT(peak, bare_max);
    EXPECT_GT(peak, 1.5 * bare_mean);
  }
  // The rigid nodule is felt harder than the soft one.
  EXPECT_GT(nodule_peaks[0], nodule_peaks[1]);
}

void check_png(const NoduleRun& run) {
  const report::ForceMap map = report::build_force_map(run.model, 0, run.report.frames);
  const fs::path png = temp_file("map.png");
  fs::remove(png);
  const std::string legend = report::write_force_map_png(map, png);
  EXPECT_NE(legend.find("viridis"), std::string::npos);
  std::ifstream in(png, std::ios::binary);
  std::string head(24, '\0');
  in.read(head.data(), 24);
  ASSERT_TRUE(in);
  EXPECT_EQ(head.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  // IHDR width and height, big-endian.
  auto be32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 4; ++k) v = (v << 8) | static_cast<unsigned char>(head[at + k]);
    return v;
  };
  const report::ForceMapLayout layout = report::force_map_layout(map);
  EXPECT_EQ(be32(16), static_cast<std::uint32_t>(layout.width));
  EXPECT_EQ(be32(20), static_cast<std::uint32_t>(layout.height));
  EXPECT_EQ(layout.plot_width, map.columns * layout.cell_pixels);
  // The nodules of the scene are outlined on it.
  EXPECT_EQ(map.nodules.size(), 2u);
  EXPECT_THROW(report::write_force_map_png(map, temp_file("no_such_folder") / "x" / "map.png"), InputError);
}

void check_feedback(const NoduleRun& run) {
  ASSERT_TRUE(run.report.palpation.has_value());
  const PalpationFeedback& f = *run.report.palpation;

  std::uint64_t contact = 0, over = 0;
  double peak = 0.0, sum = 0.0;
  for (const HapticFrame& fr : run.report.frames) {
    if (!fr.contact) continue;
    ++contact;
    const double force = fr.force.norm();
    peak = std::max(peak, force);
    sum += force;
    over += force > run.model.feedback.safe_force;
  }
  ASSERT_GT(contact, 1000u);
  EXPECT_EQ(f.contact_frames, contact);
  EXPECT_DOUBLE_EQ(f.peak_force, peak);
  EXPECT_NEAR(f.mean_force, sum / static_cast<double>(contact), 1e-12);
  EXPECT_EQ(f.safe_force, run.model.feedback.safe_force);
  EXPECT_EQ(f.over_limit_frames, over);
  EXPECT_NEAR(f.over_limit_time, static_cast<double>(over) / run.model.rates.haptic, 1e-12);

  // The scan covers the middle of the patch, not its held rim.
  EXPECT_GT(f.coverage, 0.5);
  EXPECT_LT(f.coverage, 0.95);

  // First contact over each nodule: the scan runs line by line upwards from y = min, so it
  // reaches the soft nodule (y < 0) before the hard one; at that time the finger is over it.
  ASSERT_EQ(f.nodules.size(), 2u);
  ASSERT_TRUE(f.nodules[0].time && f.nodules[1].time);
  EXPECT_EQ(f.nodules[0].nodule, "hard");
  EXPECT_LT(*f.nodules[1].time, *f.nodules[0].time);
  const auto& scripted = std::get<scene::ScriptedDevice>(run.model.devices.at(0).source);
  const auto& skin = run.model.bodies.at(0);
  for (std::size_t i = 0; i < 2; ++i) {
    const Vec3 p = haptics::position_at(scripted.trajectory, *f.nodules[i].time);
    EXPECT_LE((p.head<2>() - skin.nodules[i].center.head<2>()).norm(), skin.nodules[i].radius + 1e-9);
  }
}

void check_recording(const NoduleRun& run) {
  ASSERT_TRUE(run.recording.complete);
  ASSERT_TRUE(run.report.palpation.has_value());
  const PalpationFeedback& f = *run.report.palpation;
  auto note = [&](const std::string& text) -> const Event* {
    for (const Event& e : run.recording.events)
      if (e.kind == EventKind::note && e.text.find(text) != std::string::npos) return &e;
    return nullptr;
  };
  const Event* coverage = note("palpation coverage");
  ASSERT_NE(coverage, nullptr);
  EXPECT_EQ(coverage->value, f.coverage);
  const Event* peak = note("palpation peak force");
  ASSERT_NE(peak, nullptr);
  EXPECT_EQ(peak->value, f.peak_force);
  const Event* soft = note("nodule skin.soft");
  ASSERT_NE(soft, nullptr);
  EXPECT_EQ(soft->value, *f.nodules[1].time);
  EXPECT_NE(note("time above the safe force"), nullptr);
}

// docs/scenes.md's trainee feedback and force-map legend for this lockstep run, as printed
// (a lockstep run repeats bit for bit; 1 % leaves room for another compiler's rounding).
// A local patch cut short of its radius once let the finger reach the patch's rim over the
// soft nodule: the force jumped to 4.4 N with three contact losses, and the map's strongest
// cell moved off the hard nodule. With the push held constant over each simulation step the
// skin swung between two depths: peak 1.959 N, mean 0.383 N, largest frame 1.810 N.
// While the scan started with the finger 11 mm into the skin, its touch-down set the peak
// (1.135 N) and the largest single frame (1.081 N) through the proxy's jitter in the first
// 20 ms, and exceeded the safe force for 5 frames. The finger now comes down onto the skin
// first (`approach`): the peak is a press over the hard nodule. The force steps at the
// skin's updates are smoothed (`force_smoothing`, 5 ms).
void check_documented_numbers(const NoduleRun& run) {
  const auto count = [&](const char* kind) {
    const auto it = run.report.events.find(kind);
    return it == run.report.events.end() ? std::uint64_t{0} : it->second;
  };
  EXPECT_EQ(count("contact_begin"), 1u) << "the finger touches down once and never loses the skin";
  EXPECT_EQ(count("contact_end"), 0u);
  const PalpationFeedback& f = *run.report.palpation;
  EXPECT_NEAR(f.peak_force, 0.866, 0.01 * 0.866);
  EXPECT_NEAR(f.mean_force, 0.406, 0.01 * 0.406);
  EXPECT_NEAR(f.coverage, 0.708, 0.005);
  EXPECT_EQ(f.over_limit_frames, 0u);
  const report::ForceMap map = report::build_force_map(run.model, 0, run.report.frames);
  EXPECT_NEAR(map.max_peak(), 0.864, 0.01 * 0.864);
  double strongest = 0.0;
  Vec2 where = Vec2::Zero();
  for (int row = 0; row < map.rows; ++row)
    for (int column = 0; column < map.columns; ++column)
      if (map.samples[map.index(column, row)] > 0 && map.mean[map.index(column, row)] > strongest) {
        strongest = map.mean[map.index(column, row)];
        where = map.cell_center(column, row);
      }
  EXPECT_NEAR(strongest, 0.764, 0.01 * 0.764);
  // Once the scan starts (t = 0.2 s, after the approach) the force in contact stays between
  // 0.23 and 0.87 N, and no frame differs from the one before by more than 0.37 N (at 3.75 s,
  // over the soft nodule with the finger 8.6 mm below the proxy: at a skin update the
  // frictionless proxy slides 3 mm across the new shape, then alternates between two faces for
  // a few frames; 0.50 N without the force smoothing; the touch-down's was 0.63 N).
  // docs/scenes.md: 52 frames step by more than 0.2 N (383 without the force smoothing).
  double low = 1e9, high = 0.0, jump = 0.0;
  int over_0_2 = 0;
  const HapticFrame* last = nullptr;
  for (const HapticFrame& frame : run.report.frames) {
    if (last) {
      const double step = (frame.force - last->force).norm();
      jump = std::max(jump, step);
      if (step > 0.2) ++over_0_2;
    }
    last = &frame;
    if (frame.t < 0.2 || !frame.contact) continue;
    low = std::min(low, frame.force.norm());
    high = std::max(high, frame.force.norm());
  }
  EXPECT_NEAR(low, 0.226, 0.01 * 0.226);
  EXPECT_NEAR(high, 0.866, 0.01 * 0.866);
  EXPECT_NEAR(jump, 0.371, 0.01 * 0.371);
  EXPECT_NEAR(over_0_2, 52, 2);
  EXPECT_NEAR(where.x(), -0.012, 1e-9);  // over the hard nodule, at (-14, +12) mm
  EXPECT_NEAR(where.y(), 0.012, 1e-9);
}

TEST(Palpation, NoduleSceneEndToEnd) {
  const NoduleRun& run = nodule_run();
  {
    SCOPED_TRACE("force map: each nodule stands out where it is");
    check_force_map(run);
  }
  {
    SCOPED_TRACE("force map image");
    check_png(run);
  }
  {
    SCOPED_TRACE("trainee feedback against the frames");
    check_feedback(run);
  }
  {
    SCOPED_TRACE("feedback stored in the recording");
    check_recording(run);
  }
  {
    SCOPED_TRACE("the numbers docs/scenes.md prints");
    check_documented_numbers(run);
  }
}

TEST(Palpation, ScenesWithoutNodulesGetNoFeedback) {
  SessionOptions o;
  o.scheduling = Scheduling::lockstep;
  o.duration = 0.05;
  const SessionReport r = run_session(scene::default_scene(), o);
  EXPECT_FALSE(r.palpation.has_value());
}

}  // namespace
}  // namespace tactus::runtime
