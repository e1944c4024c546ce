// What is written over the view, laid out without OpenGL: each device's force top right,
// the pressure colour bar with its units, the bodies' legend, the value at each arrow, the
// name of the body under the pointer; and the capped arrow and the bodies' colours.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "viewer/overlay.hpp"
#include "plate.hpp"

namespace tactus::viewer {
namespace {

using test::plate;

const OverlayText* find_text(const Overlay& o, const std::string& part) {
  for (const OverlayText& t : o.texts)
    if (t.text.find(part) != std::string::npos) return &t;
  return nullptr;
}

FrameView two_layer_frame() {
  FrameView f;
  SurfaceView host = plate("tissue", 0.05, 2);
  host.recessed = true;
  f.surfaces.push_back(host);
  f.surfaces.push_back(plate("skin", 0.05, 9));
  f.status.push_back({"hand 1.20 N"});
  f.status.push_back({"needle 0.40 N: depth 12.0 mm, 1 of 3 layers passed: skin"});
  f.arrows.push_back({Vec3(0.01, 0.0, 0.0), Vec3(0, 0, 1.2), 0.01, 0.03, Colour(1, 1, 0), "hand 1.20 N"});
  f.pressure_full_scale = 19099.0;
  return f;
}

TEST(ViewerOverlay, StatusColourBarLegendAndArrowValues) {
  const FrameView f = two_layer_frame();
  const OrbitCamera camera = OrbitCamera::framing(frame_bounds(f), 30.0, 60.0);
  const int width = 640, height = 480;
  const Overlay o = build_overlay(f, camera, ViewOptions{}, width, height);

  // Both devices, right-aligned at the top right, one above the other.
  const OverlayText* hand = find_text(o, "hand 1.20 N");
  const OverlayText* needle = find_text(o, "layers passed: skin");
  ASSERT_NE(hand, nullptr);
  ASSERT_NE(needle, nullptr);
  EXPECT_TRUE(hand->right_aligned);
  EXPECT_GT(hand->x, width - 40);
  EXPECT_LT(hand->y, needle->y);
  EXPECT_LT(needle->y, height / 4);

  // The colour bar: one rect per pixel row, blue at the bottom, red at the top, in kPa
  // (19.1 kPa full scale: ticks every 5 kPa).
  const ColourBarPlace bar = colour_bar_place(width, height);
  std::vector<const OverlayRect*> rows;
  for (const OverlayRect& r : o.rects)
    if (r.x0 == bar.x0 && r.x1 == bar.x1) rows.push_back(&r);
  ASSERT_EQ(static_cast<int>(rows.size()), bar.y1 - bar.y0);
  const auto top = std::min_element(rows.begin(), rows.end(), [](auto* a, auto* b) { return a->y0 < b->y0; });
  const auto bottom = std::max_element(rows.begin(), rows.end(), [](auto* a, auto* b) { return a->y0 < b->y0; });
  EXPECT_GT((*top)->colour.x(), 0.9);
  EXPECT_GT((*bottom)->colour.z(), 0.8);
  EXPECT_NE(find_text(o, "pressure [kPa]"), nullptr);
  for (const char* tick : {"0", "5", "10", "15"})
    EXPECT_TRUE(std::any_of(o.texts.begin(), o.texts.end(), [&](const OverlayText& t) { return t.text == tick; }))
        << tick;
  EXPECT_FALSE(std::any_of(o.texts.begin(), o.texts.end(), [](const OverlayText& t) { return t.text == "20"; }));

  // The legend names both bodies beside a swatch of their colour.
  for (const SurfaceView& s : f.surfaces) {
    const auto named = std::find_if(o.texts.begin(), o.texts.end(), [&](const OverlayText& t) { return t.text == s.name; });
    ASSERT_NE(named, o.texts.end()) << s.name;
    const OverlayText* name = &*named;
    EXPECT_TRUE(std::any_of(o.rects.begin(), o.rects.end(), [&](const OverlayRect& r) {
      return r.colour.isApprox(s.colour) && std::abs(r.y0 - name->y) < 6;
    })) << s.name;
  }

  // The arrow's value beside its tip.
  double tx = 0.0, ty = 0.0;
  ASSERT_TRUE(camera.project(Vec3(0.01, 0.0, 0.012), width, height, tx, ty));
  const auto label = std::find_if(o.texts.begin(), o.texts.end(),
                                  [](const OverlayText& t) { return t.text == "hand 1.20 N" && !t.right_aligned; });
  ASSERT_NE(label, o.texts.end());
  EXPECT_NEAR(label->x, tx + 8, 2.0);
  EXPECT_NEAR(label->y, ty - 8, 2.0);

  // Without pressure or forces shown: no colour bar, no arrow value.
  ViewOptions plain;
  plain.show_pressure = false;
  plain.show_forces = false;
  const Overlay p = build_overlay(f, camera, plain, width, height);
  EXPECT_EQ(find_text(p, "pressure"), nullptr);
  EXPECT_EQ(std::count_if(p.texts.begin(), p.texts.end(), [](const OverlayText& t) { return t.text == "hand 1.20 N"; }),
            1);
}

TEST(ViewerOverlay, TheBodyUnderThePointerIsNamedAndTheLayerWinsOverItsHost) {
  const FrameView f = two_layer_frame();
  const OrbitCamera camera = OrbitCamera::framing(frame_bounds(f), 30.0, 60.0);
  double cx = 0.0, cy = 0.0;
  ASSERT_TRUE(camera.project(Vec3(0.0, 0.0, 0.0), 640, 480, cx, cy));
  const auto picked = pick_surface(f, camera, 640, 480, cx, cy);
  ASSERT_TRUE(picked.has_value());
  EXPECT_EQ(f.surfaces[*picked].name, "skin");
  const Overlay o = build_overlay(f, camera, ViewOptions{}, 640, 480, std::pair{cx, cy});
  const auto hover = std::find_if(o.texts.begin(), o.texts.end(), [&](const OverlayText& t) {
    return t.text == "skin" && std::abs(t.x - (cx + 14)) < 1.0;
  });
  EXPECT_NE(hover, o.texts.end());
  // Off the plate (the top-left corner looks past it): nothing.
  EXPECT_FALSE(pick_surface(f, camera, 640, 480, 1.0, 1.0).has_value());
}

TEST(ViewerOverlay, ArrowsAreCappedAndBodiesColouredByWhatTheyAre) {
  ArrowView a;
  a.length_per_newton = 0.01;
  a.max_length = 0.03;
  a.force = Vec3(0, 0, 1.5);
  EXPECT_DOUBLE_EQ(a.length(), 0.015);
  a.force = Vec3(0, 0, 60.0);  // a spike draws no longer than the cap
  EXPECT_DOUBLE_EQ(a.length(), 0.03);
  a.force = Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0);
  EXPECT_EQ(a.length(), 0.0);

  const Colour artery = body_colour("femoral_artery", 0), vein = body_colour("femoral_vein", 0);
  EXPECT_GT(artery.x(), artery.z() + 0.5);
  EXPECT_GT(vein.z(), vein.x() + 0.5);
  EXPECT_FALSE(body_colour("skin", 3).isApprox(body_colour("fascia_lata", 3)));
  EXPECT_FALSE(body_colour("fascia_lata", 0).isApprox(body_colour("inguinal_ligament", 0)));
  EXPECT_TRUE(body_colour("Skin_Upper", 0).isApprox(body_colour("skin", 5)));  // by name, any case
  EXPECT_FALSE(body_colour("plate", 0).isApprox(body_colour("block", 1)));     // else by index
  // Two bodies of one kind (the femoral scene's two fasciae) still differ.
  const std::vector<Colour> c = body_colours({"skin", "fascia_lata", "fascia_iliaca", "femur", "hip"});
  for (std::size_t i = 0; i < c.size(); ++i)
    for (std::size_t j = i + 1; j < c.size(); ++j) EXPECT_GT((c[i] - c[j]).norm(), 0.1) << i << " " << j;
}

}  // namespace
}  // namespace tactus::viewer
