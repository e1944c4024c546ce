// The viewer's side of a scene of many objects: graphics impostors by projected size within a
// triangle budget, the haptic loop's levels drawn, and the brush painting the object it
// touches (so that the haptic loop, which shares the images, feels it at once).
#include "viewer/touchables_view.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>

#include "scene/scene.hpp"

namespace tactus::viewer {
namespace {

using property_images::Channel;

const char* kScene = R"([bodies.near]
kind = "rigid"
mesh = { generator = "sphere", radius = 0.05, subdivisions = 3 }
levels = { coarse_levels = 2, subdivision_levels = 0 }
[bodies.near.properties]
resolution = 64
stiffness = 300.0
[bodies.far]
kind = "rigid"
mesh = { generator = "sphere", radius = 0.05, subdivisions = 3, translate = [2.0, 0.0, 0.0] }
levels = { coarse_levels = 2, subdivision_levels = 0 }
)";

TEST(TouchablesView, GraphicsLevelsGoToWhatLooksLargestWithinTheBudget) {
  const scene::Model m = scene::parse_scene(kScene, "room.toml");
  const compile::Touchables t = compile::load_touchables(m);
  const auto finest = static_cast<std::int32_t>(t.objects[0]->levels->levels.size() - 1);
  // Budget for one sphere a level above its coarsest: the near one (0.25 m from the eye, eight
  // times larger on screen) gets it, and the total stays within the budget.
  const auto triangles = [&](std::size_t object, std::int32_t level) {
    return t.objects[object]->levels->levels[static_cast<std::size_t>(level)].mesh.triangles.size();
  };
  const LevelCosts cost = level_triangles(t);
  ASSERT_EQ(cost[1].size(), t.objects[1]->levels->levels.size());
  EXPECT_EQ(cost[1][0], static_cast<double>(triangles(1, 0)));
  const double budget = static_cast<double>(triangles(0, 1) + triangles(1, 0));
  const auto levels = choose_graphics_levels(t, Vec3(0, 0, 0.25), 800.0, cost, budget);
  EXPECT_EQ(levels[0], 1);
  EXPECT_EQ(levels[1], 0);
  EXPECT_LE(static_cast<double>(triangles(0, levels[0]) + triangles(1, levels[1])), budget);
  // Seen from beside the far one, the other way round.
  const auto turned = choose_graphics_levels(t, Vec3(2.0, 0, 0.25), 800.0, cost, budget);
  EXPECT_EQ(turned[0], 0);
  EXPECT_EQ(turned[1], 1);
  // Plenty of budget: both finest; none: both coarsest.
  EXPECT_EQ(choose_graphics_levels(t, Vec3(0, 0, 0.25), 800.0, cost, 1e9)[1], finest);
  EXPECT_EQ(choose_graphics_levels(t, Vec3(0, 0, 0.25), 800.0, cost, 0.0)[0], 0);

  FrameView frame;
  frame.surfaces.resize(2);
  show_levels(t, levels, true, frame);
  EXPECT_EQ(frame.surfaces[0].triangles.size(), triangles(0, levels[0]));
  EXPECT_EQ(frame.surfaces[1].triangles.size(), triangles(1, levels[1]));
}

TEST(TouchablesView, TheBrushPaintsTheObjectItTouchesAndTheSavedFileReadsBack) {
  const scene::Model m = scene::parse_scene(kScene, "room.toml");
  const compile::Touchables t = compile::load_touchables(m);
  PaintBrush brush;
  brush.radius = 0.01;
  brush.values[Channel::stiffness] = 900.0;
  brush.mask = property_images::mask_of(Channel::stiffness);
  EXPECT_EQ(paint_at(t, m, Vec3(0, 0, 0.0505), brush), "near");
  EXPECT_EQ(paint_at(t, m, Vec3(2.0, 0, 0.05), brush), "");   // far has no images
  EXPECT_EQ(paint_at(t, m, Vec3(0, 0, 0.2), brush), "");      // nothing within the brush
  // The run's copy of the touchables shares the images: the haptic loop sees the stroke.
  const compile::Touchables run_copy = t;
  EXPECT_DOUBLE_EQ(run_copy.objects[0]->properties->lookup(Vec3(0, 0, 0.05), Vec3::UnitZ()).properties[Channel::stiffness],
                   900.0);
  const auto dir = std::filesystem::temp_directory_path() / ("tactus_brush_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto files = save_property_images(t, m, dir);
  ASSERT_EQ(files.size(), 1u);
  EXPECT_EQ(files[0].filename(), "near.properties.h5");
  EXPECT_TRUE(std::filesystem::exists(files[0]));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace tactus::viewer
