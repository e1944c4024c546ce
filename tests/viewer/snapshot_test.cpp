// Offscreen snapshots of a run: the image shows the skin, and the contact pressure where
// the scripted finger touches it.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>

#include "core/error.hpp"
#include "mesh/generators.hpp"
#include "scene/scene.hpp"
#include "viewer/debug_views.hpp"
#include "viewer/overlay.hpp"
#include "viewer/offscreen.hpp"
#include "viewer/snapshot.hpp"
#include "viewer/touchables_view.hpp"
#include "plate.hpp"

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

using test::plate;

/// A skin sheet lying on its host's top face (as the femoral scene's layers do), tessellated
/// differently, and a needle entering it away from the centre.
FrameView layered_frame(bool recessed_host) {
  FrameView f;
  SurfaceView host = plate("tissue", 0.05, 3, Colour(0.1, 0.8, 0.1));
  host.recessed = recessed_host;
  f.surfaces.push_back(host);
  f.surfaces.push_back(plate("skin", 0.05, 23, Colour(0.9, 0.1, 0.1)));
  f.needles.push_back({Vec3(0.025, 0.025, -0.004), Vec3(0.0, 0.34, -0.94).normalized(), 0.05, 0.00035});
  return f;
}

/// Renders two frames offscreen with one camera; the reason when no OpenGL context can be made.
std::optional<std::string> render_pair(const FrameView& first, const ViewOptions& first_view, const FrameView& second,
                                       const ViewOptions& second_view, const OrbitCamera& camera, int width,
                                       int height, Snapshot& a, Snapshot& b) {
  try {
    a = render_offscreen(first, camera, first_view, width, height);
    b = render_offscreen(second, camera, second_view, width, height);
  } catch (const std::runtime_error& e) {
    return std::string(e.what());
  }
  return std::nullopt;
}

/// Pixels in the box of `half` pixels around (cx, cy) where green beats red: the host showing
/// through the skin.
int host_pixels(const Snapshot& s, double cx, double cy, int half) {
  int n = 0;
  for (int y = static_cast<int>(cy) - half; y <= static_cast<int>(cy) + half; ++y)
    for (int x = static_cast<int>(cx) - half; x <= static_cast<int>(cx) + half; ++x) {
      const Vec3 c = pixel(s, x, y);
      n += c.y() > c.x();
    }
  return n;
}

// What the visual frame budget charges a touchable object's graphics level: its draw time
// through the renderer, measured per level (the values depend on the machine; that there is
// one for every level, finite and positive, does not).
TEST(ViewerSnapshot, EachGraphicsLevelHasAMeasuredDrawTime) {
  const scene::Model m = scene::parse_scene(R"([bodies.ball]
kind = "rigid"
mesh = { generator = "sphere", radius = 0.05, subdivisions = 3 }
levels = { coarse_levels = 2, subdivision_levels = 1 }
)",
                                            "ball.toml");
  const compile::Touchables t = compile::load_touchables(m);
  std::optional<OffscreenContext> context;
  try {
    context.emplace();
  } catch (const std::runtime_error& e) {
    GTEST_SKIP() << "no offscreen OpenGL context here: " << e.what();
  }
  const LevelCosts times = measure_level_draw_times(t, ViewOptions{});
  ASSERT_EQ(times.size(), 1u);
  ASSERT_EQ(times[0].size(), t.objects[0]->levels->levels.size());
  for (const double ms : times[0]) {
    EXPECT_TRUE(std::isfinite(ms));
    EXPECT_GE(ms, 1e-3);
    EXPECT_LT(ms, 1e4);
  }
}

TEST(ViewerSnapshot, ALayerOnItsHostsFaceShowsWithoutZFighting) {
  const FrameView fighting = layered_frame(false), fixed = layered_frame(true);
  const OrbitCamera camera = OrbitCamera::framing(frame_bounds(fixed), 30.0, 60.0);
  ViewOptions view;
  view.show_pressure = false;
  Snapshot a, b;
  if (const auto why = render_pair(fighting, view, fixed, view, camera, 320, 240, a, b))
    GTEST_SKIP() << "no offscreen OpenGL context here: " << *why;
  double cx = 0.0, cy = 0.0;
  ASSERT_TRUE(camera.project(Vec3(-0.01, -0.01, 0.0), 320, 240, cx, cy));
  // Drawn in the same depth, the two faces fight: the host's green shows through in places.
  EXPECT_GT(host_pixels(a, cx, cy, 20), 0) << "the defect this guards against did not show";
  // With the host recessed, the skin wins every pixel.
  EXPECT_EQ(host_pixels(b, cx, cy, 20), 0);
}

// A kept (static) surface looks as the same surface drawn afresh, its contact pressure
// included: the renderer keeps the geometry and draws the pressed triangles over it.
TEST(ViewerSnapshot, AKeptSurfaceLooksAsOneDrawnAfresh) {
  const mesh::TriMesh plate = mesh::grid_plate(0.06, 0.06, 24, 24);
  FrameView fresh;
  SurfaceView& s = fresh.surfaces.emplace_back();
  s.positions = plate.vertices;
  s.triangles = plate.triangles;
  s.pressure.assign(s.positions.size(), 0.0);
  for (std::size_t v = 0; v < s.positions.size(); ++v)
    if (s.positions[v].head<2>().norm() < 0.01) s.pressure[v] = 0.5 * fresh.pressure_full_scale;
  FrameView kept = fresh;
  kept.surfaces[0].static_id = &plate;
  const OrbitCamera camera = OrbitCamera::framing(frame_bounds(fresh), 30.0, 60.0);
  Snapshot a, b;
  if (const auto why = render_pair(fresh, ViewOptions{}, kept, ViewOptions{}, camera, 320, 240, a, b))
    GTEST_SKIP() << "no offscreen OpenGL context here: " << *why;
  // Pressure-coloured (green-yellow at half scale) pixels at the centre in both, and the two
  // pictures alike: every pixel within a few levels (rasterized twice, the contact's
  // triangles pulled forward in depth).
  double cx = 0.0, cy = 0.0;
  ASSERT_TRUE(camera.project(Vec3::Zero(), 320, 240, cx, cy));
  const Vec3 centre_a = pixel(a, static_cast<int>(cx), static_cast<int>(cy));
  const Vec3 centre_b = pixel(b, static_cast<int>(cx), static_cast<int>(cy));
  EXPECT_GT(centre_a.y(), centre_a.z()) << "the contact's colour at the centre";
  EXPECT_LT((centre_a - centre_b).norm(), 0.05);
  int differing = 0;
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x) differing += (pixel(a, x, y) - pixel(b, x, y)).norm() > 0.05;
  EXPECT_LT(differing, 320 * 240 / 200) << "pixels that differ";
}

TEST(ViewerSnapshot, TheNeedlesShaftIsDrawnFromTipToHub) {
  const FrameView with = layered_frame(true);
  FrameView without = with;
  without.needles.clear();
  const OrbitCamera camera = OrbitCamera::framing(frame_bounds(with), 30.0, 60.0);
  ViewOptions view;
  view.show_pressure = false;
  Snapshot a, b;
  if (const auto why = render_pair(with, view, without, view, camera, 320, 240, a, b))
    GTEST_SKIP() << "no offscreen OpenGL context here: " << *why;
  // Every point of the shaft above the skin, projected, differs from the frame without it.
  const NeedleView& n = with.needles.front();
  int drawn = 0, samples = 0;
  for (double d = 0.01; d < 0.045; d += 0.0025, ++samples) {
    double x = 0.0, y = 0.0;
    ASSERT_TRUE(camera.project(n.tip - d * n.axis, 320, 240, x, y));
    drawn += (pixel(a, static_cast<int>(x), static_cast<int>(y)) - pixel(b, static_cast<int>(x), static_cast<int>(y))).norm() > 0.1;
  }
  EXPECT_EQ(drawn, samples);
}

TEST(ViewerSnapshot, ThePressureColourBarIsDrawnWithItsLabels) {
  FrameView f = layered_frame(true);
  f.status.push_back({"hand 1.20 N"});
  const OrbitCamera camera = OrbitCamera::framing(frame_bounds(f), 30.0, 60.0);
  Snapshot s, plain;
  ViewOptions off;
  off.show_pressure = false;
  if (const auto why = render_pair(f, ViewOptions{}, f, off, camera, 480, 360, s, plain))
    GTEST_SKIP() << "no offscreen OpenGL context here: " << *why;
  const ColourBarPlace bar = colour_bar_place(480, 360);
  const int x = (bar.x0 + bar.x1) / 2;
  EXPECT_LT((pixel(s, x, bar.y0) - pressure_colour(1.0)).norm(), 0.05);
  EXPECT_LT((pixel(s, x, bar.y1 - 1) - pressure_colour(0.0)).norm(), 0.05);
  EXPECT_GT((pixel(s, x, bar.y0) - pixel(plain, x, bar.y0)).norm(), 0.2);
  if (!raster::text_available()) GTEST_SKIP() << "no font: no labels";
  // The status line top right: light text on the dark background.
  int lit = 0;
  for (int y = 10; y < 30; ++y)
    for (int xx = 380; xx < 470; ++xx) lit += pixel(s, xx, y).minCoeff() > 0.8;
  EXPECT_GT(lit, 30) << "no status text at the top right";
}

// The femoral trainer mid-insertion (scenario S3: the first pass reaches the skin at about
// 4 s): both devices' forces written, the needle drawn, its depth and the layers it passed
// named; the pressure scale set by the hand, not the needle.
TEST(ViewerSnapshot, FemoralNeedleDepthAndLayersAreShown) {
  const scene::Model model = scene::load_scene(std::string(TACTUS_SOURCE_DIR) + "/scenes/femoral_s3_needle.toml");
  SnapshotOptions o;
  o.time = 8.0;
  o.width = 320;
  o.height = 240;
  Snapshot s;
  try {
    s = take_snapshot(model, o);
  } catch (const std::runtime_error& e) {
    GTEST_SKIP() << "no offscreen OpenGL context here: " << e.what();
  }
  ASSERT_EQ(s.frame.needles.size(), 1u);
  EXPECT_NEAR(s.frame.needles[0].length, 0.08, 1e-12);
  ASSERT_EQ(s.frame.status.size(), 2u);
  EXPECT_EQ(s.frame.status[0].text.rfind("hand ", 0), 0u) << s.frame.status[0].text;
  const std::string& needle = s.frame.status[1].text;
  EXPECT_NE(needle.find("layers passed: skin"), std::string::npos) << needle;
  const double depth_mm = std::stod(needle.substr(needle.find("depth ") + 6));
  EXPECT_GT(depth_mm, 5.0) << needle;
  EXPECT_LT(depth_mm, 40.0) << needle;
  // 6 N over a disc of the 10 mm finger's radius: 19.1 kPa (the 0.35 mm needle would give 16 MPa).
  EXPECT_NEAR(s.frame.pressure_full_scale, 6.0 / (3.14159265358979 * 0.01 * 0.01), 1.0);
  // The skin's host is drawn behind it.
  for (const SurfaceView& surface : s.frame.surfaces) EXPECT_EQ(surface.recessed, surface.name == "tissue") << surface.name;
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
