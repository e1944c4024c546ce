// Offscreen snapshots of a run: the image shows the skin, and the contact pressure where
// the scripted finger touches it.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "core/error.hpp"
#include "scene/scene.hpp"
#include "viewer/debug_views.hpp"
#include "viewer/snapshot.hpp"

namespace tactus::viewer {
namespace {

scene::Model nodule_scene() {
  const std::string path = std::string(TACTUS_SOURCE_DIR) + "/scenes/nodule.toml";
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return scene::parse_scene(text, path);
}

Vec3 pixel(const Snapshot& s, int x, int y) {
  const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(s.width) + static_cast<std::size_t>(x)) * 3;
  return Vec3(s.rgb[i], s.rgb[i + 1], s.rgb[i + 2]) / 255.0;
}

/// Skin-like: warm, red over green over blue, and light (the skin colour under any shading).
bool skin_like(const Vec3& c) { return c.x() > 0.35 && c.x() > c.y() + 0.04 && c.y() > c.z() && c.x() - c.z() > 0.12; }

/// Mean colour difference of two images over a disc of `radius` pixels around (cx, cy).
double mean_difference(const Snapshot& a, const Snapshot& b, double cx, double cy, int radius) {
  double sum = 0.0;
  int n = 0;
  for (int y = static_cast<int>(cy) - radius; y <= static_cast<int>(cy) + radius; ++y)
    for (int x = static_cast<int>(cx) - radius; x <= static_cast<int>(cx) + radius; ++x) {
      if (x < 0 || y < 0 || x >= a.width || y >= a.height) continue;
      if ((x - cx) * (x - cx) + (y - cy) * (y - cy) > radius * radius) continue;
      sum += (pixel(a, x, y) - pixel(b, x, y)).norm();
      ++n;
    }
  return n ? sum / n : 0.0;
}

Snapshot touching_snapshot(const scene::Model& model) {
  SnapshotOptions o;
  o.time = 1.0;  // the raster scan presses the skin by then
  o.width = 320;
  o.height = 240;
  return take_snapshot(model, o);
}

TEST(ViewerSnapshot, ShowsTheSkinAndThePressureWhereTheFingerTouches) {
  const scene::Model model = nodule_scene();
  Snapshot s;
  try {
    s = touching_snapshot(model);
  } catch (const std::runtime_error& e) {
    GTEST_SKIP() << "no offscreen OpenGL context here: " << e.what();
  }
  ASSERT_EQ(s.rgb.size(), 320u * 240u * 3u);
  ASSERT_FALSE(s.frame.arrows.empty()) << "the scripted finger should be in contact at t = 1 s";

  // Not empty: many distinct colours, and skin is the most common kind of pixel.
  std::size_t skin = 0, background = 0, grey = 0;
  const Vec3 corner = pixel(s, 0, 0);
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const Vec3 c = pixel(s, x, y);
      if (skin_like(c)) ++skin;
      if ((c - corner).norm() < 0.02) ++background;
      else if (std::abs(c.x() - c.z()) < 0.05 && std::abs(c.y() - c.z()) < 0.05) ++grey;  // the floor
    }
  const double total = s.width * s.height;
  EXPECT_GT(skin / total, 0.25);
  EXPECT_GT(skin, background);
  EXPECT_GT(skin, grey);

  // The pressure colour: the same frame drawn without pressure differs around the projected
  // contact point and nowhere far from it.
  const Vec3 contact = s.frame.arrows.front().origin;
  double cx = 0, cy = 0;
  ASSERT_TRUE(s.camera.project(contact, s.width, s.height, cx, cy));
  ASSERT_TRUE(cx >= 0 && cy >= 0 && cx < s.width && cy < s.height);
  ViewOptions plain;
  plain.show_pressure = false;
  const Snapshot without = render_offscreen(s.frame, s.camera, plain, s.width, s.height);
  EXPECT_GT(mean_difference(s, without, cx, cy, 4), 0.05) << "no pressure colour at (" << cx << ", " << cy << ")";
  const double far_x = cx < s.width / 2.0 ? s.width - 20.0 : 20.0;
  EXPECT_LT(mean_difference(s, without, far_x, s.height / 2.0, 8), 0.01);
}

TEST(ViewerSnapshot, BadOptionsAreInputErrors) {
  int w = 0, h = 0;
  EXPECT_THROW(parse_size("12x800", "--size", w, h), InputError);
  EXPECT_THROW(parse_size("640by480", "--size", w, h), InputError);
  parse_size("640x480", "--size", w, h);
  EXPECT_EQ(w, 640);
  EXPECT_EQ(h, 480);
  EXPECT_THROW(parse_camera("30", "--camera"), InputError);
  EXPECT_THROW(parse_camera("30,95", "--camera"), InputError);
  EXPECT_THROW(parse_camera("30,20,-1", "--camera"), InputError);
  const CameraSpec c = parse_camera("45,20,0.3", "--camera");
  EXPECT_DOUBLE_EQ(c.azimuth, 45.0);
  EXPECT_DOUBLE_EQ(c.distance, 0.3);
  SnapshotOptions o;
  o.time = -1.0;
  EXPECT_THROW(take_snapshot(nodule_scene(), o), InputError);
}

// A scene without a device (no haptic loop to run): its bodies are stepped alone under their
// loads. The cantilever's 1 mN tip load bends it by 0.40 mm when static (Timoshenko,
// docs/validation.md); after 1 s of implicit steps from rest the tip is on its way there,
// between a quarter of it and the dynamic overshoot's twice.
TEST(ViewerSnapshot, RendersASceneWithoutADevice) {
  const std::string path = std::string(TACTUS_SOURCE_DIR) + "/scenes/cantilever.toml";
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const scene::Model model = scene::parse_scene(text, path);
  ASSERT_TRUE(model.devices.empty());
  SnapshotOptions o;
  o.time = 1.0;
  o.width = 160;
  o.height = 120;
  Snapshot s;
  try {
    s = take_snapshot(model, o);
  } catch (const std::runtime_error& e) {
    GTEST_SKIP() << "no offscreen OpenGL context here: " << e.what();
  }
  EXPECT_NEAR(s.frame.t, 1.0, 1e-9);
  ASSERT_EQ(s.frame.surfaces.size(), 1u);
  const auto& rest = model.bodies[0].surface.vertices;
  const auto& now = s.frame.surfaces[0].positions;
  ASSERT_EQ(now.size(), rest.size());
  double tip = 0.0;  // the end face, at x = 0.05 m (the box is centred)
  for (std::size_t v = 0; v < rest.size(); ++v)
    if (rest[v].x() > 0.0499) tip = std::min(tip, now[v].z() - rest[v].z());
  EXPECT_LT(tip, -0.25 * 0.40e-3) << "tip displacement " << tip;
  EXPECT_GT(tip, -2.0 * 0.40e-3) << "tip displacement " << tip;
}

}  // namespace
}  // namespace tactus::viewer

namespace tactus::viewer {
namespace {

// The constraint-plane view: a square on the touched surface's tangent plane, for a tool
// that touches, and none for one that does not.
TEST(DebugViews, ConstraintPlaneOnlyWhereTheToolTouches) {
  const scene::Model model = scene::default_scene();
  DebugViews debug(model);
  ViewOptions view;
  view.show_planes = true;
  view.show_bvh = false;
  FrameView frame;
  SurfaceView flat;  // a unit square in z = 0.02, counter-clockwise seen from +z
  flat.positions = {Vec3(0, 0, 0.02), Vec3(1, 0, 0.02), Vec3(1, 1, 0.02), Vec3(0, 1, 0.02)};
  flat.triangles = {{0, 1, 2}, {0, 2, 3}};
  frame.surfaces.push_back(flat);
  ToolView tool;
  tool.seen = true;
  tool.touching = true;
  tool.radius = 0.005;
  tool.contact_point = Vec3(0.1, 0.1, 0.02);
  debug.add({tool}, view, frame);
  ASSERT_EQ(frame.quads.size(), 1u);
  EXPECT_TRUE(frame.quads[0].centre.isApprox(tool.contact_point));
  EXPECT_NEAR(frame.quads[0].normal.dot(Vec3::UnitZ()), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(frame.quads[0].half, 0.01);

  frame.quads.clear();
  tool.touching = false;
  debug.add({tool}, view, frame);
  EXPECT_TRUE(frame.quads.empty());
  tool.touching = true;
  view.show_planes = false;
  debug.add({tool}, view, frame);
  EXPECT_TRUE(frame.quads.empty());
}

}  // namespace
}  // namespace tactus::viewer
