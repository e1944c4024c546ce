// The interaction step driven by hand, with no loop: the contact plane under a tool, the
// reach, the needle's layer crossings, and the parts timed only with a clock given.
#include <gtest/gtest.h>

#include <array>

#include "runtime/interaction_step.hpp"
#include "scene/scene.hpp"

namespace tactus::runtime {
namespace {

// A 10 cm sheet at z = 0 and a block 1 cm thick below it (top at z = -0.01).
const scene::Model& two_layers() {
  static const scene::Model m = scene::parse_scene(R"(
[materials.skin]
model = "mass_spring"
young_modulus = 1e5
density = 1000.0

[bodies.sheet]
kind = "rigid"
mesh = { generator = "grid_plate", size = [0.1, 0.1], cells = [4, 4] }

[bodies.block]
kind = "rigid"
mesh = { generator = "box", size = [0.1, 0.1, 0.01], cells = 2, translate = [0.0, 0.0, -0.015] }
)", "two_layers.toml");
  return m;
}

struct Rig {
  InteractionModel model;
  InteractionState state;
  SurfaceSnapshot surfaces;
  explicit Rig(std::vector<InteractionTarget> targets)
      : model(make_interaction_model(two_layers(), std::move(targets))), state(make_interaction_state(model)) {
    surfaces.step = 7;
    for (const scene::Body& b : two_layers().bodies) surfaces.positions.push_back(b.surface.vertices);
  }
};

TEST(InteractionStep, ThePlaneGoesThroughTheClosestPointAndFacesTheTool) {
  Rig run({{"hand", {0, 1}, 0.02, 0, 0.0}});
  const std::array<ToolState, 1> tools{{{Vec3(0.01, 0.02, 0.005), Vec3::Zero(), true}}};
  LocalContact contact;
  LocalContact* contacts[] = {&contact};
  haptics::NeedleSurfaces* needles[] = {nullptr};
  run.surfaces.t = 0.25;
  interaction_step(run.model, run.state, {&run.surfaces, tools, nullptr}, {contacts, needles, {}});
  EXPECT_TRUE(contact.valid);
  EXPECT_EQ(contact.body, 0);  // the sheet, 5 mm below, not the block 15 mm below
  EXPECT_NEAR((contact.point - Vec3(0.01, 0.02, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(contact.normal.z(), 1.0, 1e-12);
  EXPECT_EQ(contact.surface_time, 0.25);
  EXPECT_EQ(run.state.tree_step, 7u);  // the trees follow the snapshot they were built from
}

TEST(InteractionStep, BeyondTheReachThereIsNoContact) {
  Rig run({{"hand", {0}, 0.02, 0, 0.0}});
  const std::array<ToolState, 1> far{{{Vec3(0.0, 0.0, 0.05), Vec3::Zero(), true}}};
  const std::array<ToolState, 1> lost{{{Vec3(0.0, 0.0, 0.001), Vec3::Zero(), false}}};
  LocalContact contact;
  LocalContact* contacts[] = {&contact};
  haptics::NeedleSurfaces* needles[] = {nullptr};
  interaction_step(run.model, run.state, {&run.surfaces, far, nullptr}, {contacts, needles, {}});
  EXPECT_FALSE(contact.valid);
  interaction_step(run.model, run.state, {&run.surfaces, lost, nullptr}, {contacts, needles, {}});
  EXPECT_FALSE(contact.valid);  // a tool the haptic loop has not placed yet touches nothing
}

TEST(InteractionStep, ANeedleFindsWhereItsLineCrossesEachLayer) {
  // A 5 cm needle pointing down with its tip 12 mm under the sheet: it has passed the sheet
  // and is inside the block (entered at its top, z = -0.01; its bottom, z = -0.02, ahead).
  Rig run({{"needle", {0, 1}, 0.005, 0, 0.05}});
  const std::array<ToolState, 1> tools{{{Vec3(0.003, 0.004, -0.012), Vec3(0, 0, -1), true}}};
  LocalContact contact;
  haptics::NeedleSurfaces needle;
  LocalContact* contacts[] = {&contact};
  haptics::NeedleSurfaces* needles[] = {&needle};
  interaction_step(run.model, run.state, {&run.surfaces, tools, nullptr}, {contacts, needles, {}});
  ASSERT_TRUE(needle.layers[0].entry_found);
  EXPECT_NEAR(needle.layers[0].entry.z(), 0.0, 1e-12);
  ASSERT_TRUE(needle.layers[1].entry_found);
  EXPECT_NEAR(needle.layers[1].entry.z(), -0.01, 1e-12);
  EXPECT_FALSE(needle.layers[1].exit_found);  // 8 mm ahead of the tip, past the 5 mm reach
  EXPECT_FALSE(contact.valid);  // a needle gets crossings, not a plane
  const std::array<ToolState, 1> deeper{{{Vec3(0.003, 0.004, -0.018), Vec3(0, 0, -1), true}}};
  interaction_step(run.model, run.state, {&run.surfaces, deeper, nullptr}, {contacts, needles, {}});
  ASSERT_TRUE(needle.layers[1].exit_found);
  EXPECT_NEAR(needle.layers[1].exit.z(), -0.02, 1e-12);
}

Nanos fake_clock() {
  static Nanos t = 0;
  return t += 1000;
}

TEST(InteractionStep, PartsAreTimedOnlyWithTheLoopsClock) {
  Rig run({{"hand", {0, 1}, 0.02, 0, 0.0}});
  const std::array<ToolState, 1> tools{{{Vec3(0.0, 0.0, 0.005), Vec3::Zero(), true}}};
  LocalContact contact;
  LocalContact* contacts[] = {&contact};
  haptics::NeedleSurfaces* needles[] = {nullptr};
  std::vector<PartStats> parts(3);
  interaction_step(run.model, run.state, {&run.surfaces, tools, nullptr}, {contacts, needles, parts});
  for (const PartStats& p : parts) EXPECT_EQ(p.time.count(), 0u);
  run.state = make_interaction_state(run.model);
  interaction_step(run.model, run.state, {&run.surfaces, tools, fake_clock}, {contacts, needles, parts});
  EXPECT_EQ(parts[0].time.count(), 2u);  // one query per body
  EXPECT_EQ(parts[1].time.count(), 1u);  // the device's handling
  EXPECT_EQ(parts[2].time.count(), 1u);  // the trees built
}

}  // namespace
}  // namespace tactus::runtime
