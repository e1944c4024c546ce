// The needle end to end: scene keys and their errors, and a lockstep run of the bundled
// layered block (scenes/needle_block.toml) through the haptic, interaction and simulation
// loops.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "runtime/loop_set.hpp"
#include "runtime/needle_report.hpp"
#include "report/report.hpp"
#include "runtime/session.hpp"
#include "scene/scene.hpp"

namespace tactus {
namespace {

namespace fs = std::filesystem;

// Two slabs and a scripted needle; `layers` and `extra` complete the needle algorithm.
std::string needle_scene(const std::string& algorithm_keys) {
  return R"([materials.soft]
young_modulus = 5e4
poisson_ratio = 0.45
density = 1100

[bodies.top]
kind = "tet_mass_spring"
material = "soft"
mesh = { generator = "box", size = [0.02, 0.02, 0.004], cells = [2, 2, 1], translate = [0, 0, -0.002] }
time_step = 0.005
[[bodies.top.fixed]]
name = "rim"
side = "x_min"

[bodies.bottom]
kind = "tet_mass_spring"
material = "soft"
mesh = { generator = "box", size = [0.02, 0.02, 0.01], cells = [2, 2, 2], translate = [0, 0, -0.009] }
time_step = 0.005
[[bodies.bottom.fixed]]
name = "base"
side = "z_min"

[devices.hand]
type = "scripted"
max_force = 8.0
trajectory = { type = "needle_line", entry = [0, 0, 0.005], target = [0, 0, -0.01], speed = 0.01 }

[tools.needle]
type = "needle"
device = "hand"

[algorithms.insertion]
type = "needle"
tool = "needle"
)" + algorithm_keys + "\n";
}

std::string error_of(const std::string& text) {
  try {
    scene::parse_scene(text, "n.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(NeedleScene, LayersAreReadWithDefaults) {
  const scene::Model m = scene::parse_scene(
      needle_scene(R"(layers = [{ body = "bottom", rupture_force = 4.5, coulomb_friction = 10 }, { body = "top" }])"),
      "n.toml");
  const auto& p = std::get<scene::NeedleParams>(m.algorithms.at(0).params);
  ASSERT_EQ(p.layers.size(), 2u);
  EXPECT_EQ(p.layers[0].body, 1u);
  EXPECT_EQ(p.layers[0].rupture_force, 4.5);
  EXPECT_EQ(p.layers[0].coulomb_friction, 10.0);
  EXPECT_EQ(p.layers[0].stiffness, haptics::NeedleLayer{}.stiffness);
  EXPECT_EQ(p.layers[1].body, 0u);
  EXPECT_EQ(p.layers[1].rupture_force, haptics::NeedleLayer{}.rupture_force);
  EXPECT_EQ(m.algorithms[0].bodies, (std::vector<std::size_t>{1, 0}));
}

TEST(NeedleScene, WithoutLayersEveryBodyIsALayer) {
  const scene::Model m = scene::parse_scene(needle_scene(""), "n.toml");
  const auto& p = std::get<scene::NeedleParams>(m.algorithms.at(0).params);
  ASSERT_EQ(p.layers.size(), 2u);
  EXPECT_EQ(p.layers[0].body, 0u);
  EXPECT_EQ(p.layers[1].body, 1u);
}

TEST(NeedleScene, BadLayersAreLocatedErrors) {
  EXPECT_EQ(error_of(needle_scene(R"(layers = [{ body = "topp" }])")),
            "n.toml:36:20: algorithms.insertion.layers[0].body: undefined body 'topp'; did you mean 'top'?");
  EXPECT_EQ(error_of(needle_scene(R"(layers = [{ body = "top", rupture_force = -1 }])")),
            "n.toml:36:43: algorithms.insertion.layers[0].rupture_force: -1 is out of range: must be > 0");
  EXPECT_NE(error_of(needle_scene(R"(layers = [{ body = "top", rupture_force = 9 }])"))
                .find("layers[0].rupture_force: 9 N is not below the device's max_force (8 N)"),
            std::string::npos);
  EXPECT_NE(error_of(needle_scene(R"(layers = [{ body = "top" }, { body = "top" }])"))
                .find("layers[1].body: body 'top' is already a layer of this needle"),
            std::string::npos);
  EXPECT_NE(error_of(needle_scene(R"(layers = [{ body = "top", stiffnes = 5 }])")).find("stiffnes"),
            std::string::npos);
  EXPECT_NE(error_of(needle_scene("layers = []")).find("layers: needs at least one layer"), std::string::npos);
  EXPECT_NE(error_of(needle_scene("bodies = [\"top\"]\nlayers = [{ body = \"top\" }]"))
                .find("a needle takes its bodies from 'layers'"),
            std::string::npos);
  EXPECT_NE(error_of(needle_scene(R"(layers = [{ body = "top", viscous_friction = -2 }])")).find("layers[0].viscous_friction: -2 is out of range: must be >= 0"),
            std::string::npos);
}

TEST(NeedleSession, LockstepRunRupturesTheLayersInAnatomicalOrderAtTheirThresholds) {
  const scene::Model m = scene::load_scene(fs::path(TACTUS_SOURCE_DIR) / "scenes/needle_block.toml");
  runtime::SessionOptions o;
  o.scheduling = runtime::Scheduling::lockstep;
  o.keep_frames = true;
  const runtime::SessionReport r = runtime::run_session(m, o);

  ASSERT_EQ(r.needles.size(), 1u);
  const runtime::NeedleReport& n = r.needles.front();
  EXPECT_EQ(n.layers, 3u);
  ASSERT_EQ(n.ruptures.size(), 3u);
  const char* anatomical[] = {"skin", "fascia", "muscle"};
  const auto& layers = std::get<scene::NeedleParams>(m.algorithms.front().params).layers;
  for (std::size_t k = 0; k < 3; ++k) {
    const runtime::NeedleRuptureReport& p = n.ruptures[k];
    EXPECT_EQ(p.layer, anatomical[k]);
    EXPECT_EQ(p.threshold, layers[k].rupture_force);
    // Tolerance: 1 % of the threshold (one 2 kHz frame at 10 mm/s adds at most 0.01 N).
    EXPECT_GE(p.force, p.threshold);
    EXPECT_LE(p.force, 1.01 * p.threshold) << p.layer;
    if (k > 0) {
      EXPECT_GT(p.t, n.ruptures[k - 1].t);
    }
  }
  EXPECT_EQ(r.events.at("rupture"), 3u);
  // A straight scripted insertion stays on its planned path.
  EXPECT_LT(n.max_deviation, 1e-9);

  // What the hand felt: finite, below the device limit, never clamped, and at each rupture
  // the resistance drops.
  const double max_force = m.devices.front().max_force;
  ASSERT_FALSE(r.frames.empty());
  for (const runtime::HapticFrame& f : r.frames) {
    ASSERT_TRUE(f.force.allFinite());
    EXPECT_LT(f.force.norm(), max_force);
  }
  EXPECT_EQ(r.devices.front().safety.clamped, 0u);
  const double dt = 1.0 / m.rates.haptic;
  for (const runtime::NeedleRuptureReport& p : n.ruptures) {
    double before = 0.0, after = 0.0;
    for (const runtime::HapticFrame& f : r.frames) {
      if (std::abs(f.t - (p.t - dt)) < 0.25 * dt) before = f.force.norm();
      if (std::abs(f.t - (p.t + 2 * dt)) < 0.25 * dt) after = f.force.norm();
    }
    EXPECT_GT(before, 0.9 * p.threshold) << p.layer;
    EXPECT_LT(after, 0.5 * before) << p.layer;
  }
  // The end-of-run report names the layers and the forces.
  const std::string text = report::format_report(r);
  EXPECT_NE(text.find("needle (hand): 3 of 3 layers passed"), std::string::npos) << text;
  EXPECT_NE(text.find("2. fascia"), std::string::npos);
  EXPECT_NE(report::report_json(r).find("\"needles\": [{\"device\": \"hand\""), std::string::npos);
}

TEST(NeedleReport, ANeedleThatNeverTouchedSaysSoInsteadOfCountingNoLayersPassed) {
  // Femoral S1 and S2 hold the needle still: "0 of 3 layers passed" read as a failed insertion.
  runtime::NeedleReport idle;
  idle.device = "needle";
  idle.layers = 3;
  const std::string text = runtime::format_needle_report(idle);
  EXPECT_NE(text.find("needle (needle): never touched a layer"), std::string::npos) << text;
  EXPECT_EQ(text.find("layers passed"), std::string::npos) << text;
  EXPECT_NE(runtime::needle_report_json(idle).find("\"touched\": false"), std::string::npos);
  runtime::NeedleReport pressed = idle;
  pressed.touched = true;
  EXPECT_NE(runtime::format_needle_report(pressed).find("0 of 3 layers passed"), std::string::npos);
}

TEST(NeedleSession, TheLayerDentsUnderTheNeedleBeforeItTears) {
  const scene::Model m = scene::load_scene(fs::path(TACTUS_SOURCE_DIR) / "scenes/needle_block.toml");
  runtime::SessionOptions o;
  o.scheduling = runtime::Scheduling::lockstep;
  runtime::Loops loops = runtime::build_loops(m, o);
  // The scene's lockstep order, stopped while the skin resists (it tears near t = 1.2 s).
  std::uint64_t sim_steps = 0, inter_steps = 0;
  for (std::uint64_t k = 0;; ++k) {
    const double t = static_cast<double>(k) / m.rates.haptic;
    if (t > 1.18) break;
    for (; static_cast<double>(sim_steps) / m.rates.simulation <= t; ++sim_steps)
      loops.simulation->step(static_cast<double>(sim_steps) / m.rates.simulation, 0, 0, false);
    for (; static_cast<double>(inter_steps) / m.rates.interaction <= t; ++inter_steps)
      loops.interaction->step(static_cast<double>(inter_steps) / m.rates.interaction, 0, 0, false);
    loops.haptic.front()->step(t, 0, 0, false);
  }
  const auto* needle = loops.haptic.front()->needle();
  ASSERT_NE(needle, nullptr);
  const std::size_t skin = 0;
  ASSERT_EQ(m.bodies[skin].name, "skin");
  EXPECT_EQ(needle->stage(0), haptics::NeedleStage::deforming);
  EXPECT_TRUE(needle->ruptures().empty());
  // The skin's top node under the needle has moved down, far more than away from it; the
  // muscle below has not been touched (the layers are separate bodies).
  const auto lowest_shift = [&](std::size_t body, const Vec3& near) {
    const auto& rest = m.bodies[body].simulation_vertices();
    const VecX& x = *loops.simulation->positions(body);
    std::size_t best = 0;
    for (std::size_t i = 1; i < rest.size(); ++i)
      if ((rest[i] - near).norm() < (rest[best] - near).norm()) best = i;
    return x[static_cast<Eigen::Index>(3 * best + 2)] - rest[best].z();
  };
  EXPECT_LT(lowest_shift(skin, Vec3(0, 0, 0)), lowest_shift(skin, Vec3(0.015, 0.015, 0)) - 1e-3);
  EXPECT_GT(lowest_shift(2, Vec3(0, 0, -0.005)), -1e-4);
}

}  // namespace
}  // namespace tactus
