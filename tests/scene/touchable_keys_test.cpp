// A scene of many objects: [lod], and bodies.<name>.levels and .properties of rigid bodies;
// every way they can be wrong, located.
#include <gtest/gtest.h>

#include <string>

#include "core/error.hpp"
#include "scene/scene.hpp"

namespace tactus::scene {
namespace {

std::string scene_with(const std::string& body_keys, const std::string& extra = "", const std::string& kind = "rigid") {
  return R"([materials.foam]
young_modulus = 1e4
poisson_ratio = 0.3
density = 60
[bodies.ball]
kind = ")" + kind + R"("
material = "foam"
mesh = { generator = "sphere", radius = 0.05, subdivisions = 2 }
)" + body_keys + "\n" + extra;
}

std::string touchable_error(const std::string& text) {
  try {
    (void)parse_scene(text, "room.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

bool has(const std::string& message, const std::string& part) { return message.find(part) != std::string::npos; }

TEST(TouchableKeys, LevelsPropertiesAndTheSelectionAreRead) {
  const Model m = parse_scene(scene_with(R"(levels = { coarse_levels = 3, reduction = 0.3, subdivision_levels = 0, raise_force = 3.0, lower_force = 1.5, hold_time = 0.2 }
[bodies.ball.properties]
resolution = 64
stiffness = 700.0
static_friction = 0.5
kinetic_friction = 0.4
roughness_amplitude = 1e-4
roughness_wavelength = 0.002
[[bodies.ball.properties.paint]]
center = [0.0, 0.0, 0.05]
radius = 0.01
stiffness = 1400.0
[[bodies.ball.properties.paint]]
center = [0.0, 0.0, -0.05]
radius = 0.02
young_modulus = 2e5
poisson_ratio = 0.3
)",
                                             "[lod]\nhaptic_budget = 8e-6\ninfluence_radius = 0.1\nblend_time = 0.004\nselect = false\n"),
                                  "room.toml");
  const Body& b = m.bodies.at(0);
  ASSERT_TRUE(b.levels && b.properties);
  EXPECT_EQ(b.levels->build.coarse_levels, 3);
  EXPECT_DOUBLE_EQ(b.levels->build.reduction, 0.3);
  EXPECT_EQ(b.levels->build.subdivision_levels, 0);
  EXPECT_DOUBLE_EQ(b.levels->raise_force, 3.0);
  EXPECT_DOUBLE_EQ(b.levels->lower_force, 1.5);
  EXPECT_DOUBLE_EQ(b.levels->hold_time, 0.2);
  using property_images::Channel;
  EXPECT_EQ(b.properties->resolution, 64);
  EXPECT_DOUBLE_EQ(b.properties->base[Channel::stiffness], 700.0);
  EXPECT_DOUBLE_EQ(b.properties->base[Channel::roughness_wavelength], 0.002);
  EXPECT_DOUBLE_EQ(b.properties->paint[0].values[Channel::stiffness], 1400.0);
  EXPECT_DOUBLE_EQ(b.properties->paint[0].values[Channel::static_friction], 0.5);  // the body's
  EXPECT_EQ(b.properties->paint[0].mask, property_images::mask_of(Channel::stiffness));
  ASSERT_EQ(b.properties->paint.size(), 2u);
  EXPECT_DOUBLE_EQ(b.properties->paint[1].values[Channel::young_modulus], 2e5);
  EXPECT_DOUBLE_EQ(b.properties->paint[1].values[Channel::poisson_ratio], 0.3);
  EXPECT_EQ(b.properties->paint[1].mask,
            property_images::mask_of(Channel::young_modulus) | property_images::mask_of(Channel::poisson_ratio));
  EXPECT_EQ(b.properties->base[Channel::young_modulus], 0.0);  // unset: the body's material
  EXPECT_DOUBLE_EQ(m.level_selection.haptic_budget, 8e-6);
  EXPECT_DOUBLE_EQ(m.level_selection.influence_radius, 0.1);
  EXPECT_DOUBLE_EQ(m.level_selection.blend_time, 0.004);
  EXPECT_FALSE(m.level_selection.select);
}

TEST(TouchableKeys, EveryWrongKeyIsLocated) {
  std::string e = touchable_error(scene_with("[bodies.ball.properties]\nstiffness = -5.0\n"));
  EXPECT_TRUE(has(e, "room.toml:") && has(e, "bodies.ball.properties.stiffness")) << e;
  e = touchable_error(scene_with("[bodies.ball.properties]\nstatic_friction = 0.2\nkinetic_friction = 0.5\n"));
  EXPECT_TRUE(has(e, "bodies.ball.properties") && has(e, "kinetic_friction 0.5 exceeds static_friction 0.2")) << e;
  e = touchable_error(scene_with("[bodies.ball.properties]\npoisson_ratio = 0.7\n"));
  EXPECT_TRUE(has(e, "bodies.ball.properties.poisson_ratio")) << e;
  e = touchable_error(scene_with("[bodies.ball.properties]\nroughness_amplitude = 1e-4\n"));
  EXPECT_TRUE(has(e, "roughness_wavelength")) << e;
  e = touchable_error(scene_with("[bodies.ball.properties]\n[[bodies.ball.properties.paint]]\ncenter = [0, 0, 0]\nradius = 0.01\n"));
  EXPECT_TRUE(has(e, "bodies.ball.properties.paint") && has(e, "at least one")) << e;
  e = touchable_error(scene_with("[bodies.ball.properties]\nfile = \"nowhere.h5\"\n"));
  EXPECT_TRUE(has(e, "bodies.ball.properties.file") && has(e, "nowhere.h5")) << e;
  e = touchable_error(scene_with("levels = { raise_force = 1.0, lower_force = 2.0 }"));
  EXPECT_TRUE(has(e, "bodies.ball.levels.lower_force") && has(e, "must be below raise_force")) << e;
  e = touchable_error(scene_with("levels = { coarse_levels = 12 }"));
  EXPECT_TRUE(has(e, "bodies.ball.levels.coarse_levels")) << e;
  e = touchable_error(scene_with("levels = { coarse_levels = 1 }", "", "fem"));
  EXPECT_TRUE(has(e, "bodies.ball.levels") && has(e, "for rigid bodies")) << e;
  e = touchable_error(scene_with("", "[lod]\nhaptic_budget = 0.0\n"));
  EXPECT_TRUE(has(e, "lod.haptic_budget")) << e;
  e = touchable_error(scene_with("", "[lod]\nbudget = 1e-5\n"));
  EXPECT_TRUE(has(e, "lod.budget") && has(e, "unknown key")) << e;
}

}  // namespace
}  // namespace tactus::scene
