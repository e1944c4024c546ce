#include "viewer/overlay.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace tactus::viewer {
namespace {

constexpr int kMargin = 12;
constexpr int kLine = 20;  // line pitch [px]
const Colour kTextColour(0.95, 0.95, 0.95);

raster::Rgb to_rgb(const Colour& c) {
  const auto channel = [](double v) { return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(v, 0.0, 1.0))); };
  return {channel(c.x()), channel(c.y()), channel(c.z())};
}

/// Möller–Trumbore: the ray's parameter at the triangle, or infinity.
double ray_triangle(const Vec3& origin, const Vec3& direction, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a, p = direction.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-18) return std::numeric_limits<double>::infinity();
  const Vec3 s = origin - a;
  const double u = s.dot(p) / det;
  if (u < 0.0 || u > 1.0) return std::numeric_limits<double>::infinity();
  const Vec3 q = s.cross(e1);
  const double v = direction.dot(q) / det;
  if (v < 0.0 || u + v > 1.0) return std::numeric_limits<double>::infinity();
  const double t = e2.dot(q) / det;
  return t > 0.0 ? t : std::numeric_limits<double>::infinity();
}

}  // namespace

ColourBarPlace colour_bar_place(int width, int height) {
  ColourBarPlace p;
  p.x1 = width - 64;
  p.x0 = p.x1 - 16;
  p.y0 = kMargin + 5 * kLine;
  p.y1 = p.y0 + std::clamp(height / 3, 60, 260);
  return p;
}

Overlay build_overlay(const FrameView& frame, const OrbitCamera& camera, const ViewOptions& options, int width,
                      int height, const std::optional<std::pair<double, double>>& hovered) {
  Overlay o;
  // Each device's force; a needle's depth and layers.
  for (std::size_t i = 0; i < frame.status.size(); ++i)
    o.texts.push_back({width - kMargin, kMargin + static_cast<int>(i) * kLine, frame.status[i].text,
                       frame.status[i].colour, true});

  // The pressure colour bar: 0 at the bottom, full scale at the top, in kPa.
  if (options.show_pressure && frame.pressure_full_scale > 0.0) {
    const ColourBarPlace bar = colour_bar_place(width, height);
    const int rows = bar.y1 - bar.y0;
    for (int r = 0; r < rows; ++r)
      o.rects.push_back({bar.x0, bar.y0 + r, bar.x1, bar.y0 + r + 1, pressure_colour(1.0 - (r + 0.5) / rows)});
    const double full_kpa = 1e-3 * frame.pressure_full_scale;
    o.texts.push_back({bar.x1, bar.y0 - kLine - 4, "pressure [kPa]", kTextColour, true});
    const double step = raster::nice_step(full_kpa, 4.0);
    for (double v = 0.0; v <= full_kpa * (1.0 + 1e-9); v += step) {
      const int y = bar.y1 - static_cast<int>(std::lround(v / full_kpa * rows));
      o.rects.push_back({bar.x1, y, bar.x1 + 5, y + 1, kTextColour});
      o.texts.push_back({bar.x1 + 8, y - 8, raster::tick_label(v, step), kTextColour, false});
    }
  }

  // The legend, bottom right: each body's name beside its colour (a body of several
  // regions: each region's).
  std::vector<std::pair<std::string, Colour>> named;
  for (const SurfaceView& s : frame.surfaces) {
    if (!s.legend.empty())
      named.insert(named.end(), s.legend.begin(), s.legend.end());
    else if (!s.name.empty())
      named.emplace_back(s.name, s.colour);
  }
  if (named.size() > 1) {
    int y = height - kMargin - static_cast<int>(named.size()) * kLine;
    for (const auto& [name, colour] : named) {
      o.rects.push_back({width - kMargin - 14, y + 2, width - kMargin, y + 16, colour});
      o.texts.push_back({width - kMargin - 20, y, name, kTextColour, true});
      y += kLine;
    }
  }

  // Each arrow's value at its tip.
  if (options.show_forces)
    for (const ArrowView& a : frame.arrows) {
      const double length = a.length();
      if (a.label.empty() || !(length > 1e-6)) continue;
      double x = 0.0, y = 0.0;
      if (camera.project(a.origin + a.force.normalized() * length, width, height, x, y))
        o.texts.push_back({static_cast<int>(x) + 8, static_cast<int>(y) - 8, a.label, a.colour, false});
    }

  // The body under the pointer.
  if (hovered)
    if (const auto picked = pick_surface(frame, camera, width, height, hovered->first, hovered->second))
      o.texts.push_back({static_cast<int>(hovered->first) + 14, static_cast<int>(hovered->second) + 10,
                         frame.surfaces[*picked].name, kTextColour, false});
  return o;
}

void paint(const Overlay& overlay, raster::Image& image) {
  for (const OverlayRect& r : overlay.rects) raster::fill_rect(image, r.x0, r.y0, r.x1, r.y1, to_rgb(r.colour));
  for (const OverlayText& t : overlay.texts) {
    const int x = t.right_aligned ? t.x - raster::text_width(t.text, kOverlayTextSize) : t.x;
    // A dark shadow keeps light text readable on a light surface.
    raster::draw_text(image, x + 1, t.y + 1, t.text, kOverlayTextSize, {0, 0, 0});
    raster::draw_text(image, x, t.y, t.text, kOverlayTextSize, to_rgb(t.colour));
  }
}

std::optional<std::size_t> pick_surface(const FrameView& frame, const OrbitCamera& camera, int width, int height,
                                        double x, double y) {
  if (width <= 0 || height <= 0) return std::nullopt;
  const Vec3 eye = camera.eye();
  const Vec3 forward = (camera.target - eye).normalized();
  const double half = std::tan(camera.fov_y * std::numbers::pi / 360.0);
  const double aspect = static_cast<double>(width) / height;
  const double nx = 2.0 * x / width - 1.0, ny = 1.0 - 2.0 * y / height;
  const Vec3 direction = (forward + nx * half * aspect * camera.right() + ny * half * camera.up()).normalized();
  std::optional<std::size_t> best;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t s = 0; s < frame.surfaces.size(); ++s) {
    const SurfaceView& surface = frame.surfaces[s];
    const auto n = static_cast<mesh::Index>(surface.positions.size());
    for (const mesh::Triangle& t : surface.triangles) {
      if (t[0] < 0 || t[1] < 0 || t[2] < 0 || t[0] >= n || t[1] >= n || t[2] >= n) continue;
      const double hit = ray_triangle(eye, direction, surface.positions[static_cast<std::size_t>(t[0])],
                                      surface.positions[static_cast<std::size_t>(t[1])],
                                      surface.positions[static_cast<std::size_t>(t[2])]);
      // A layer on its host's boundary wins the tie, as it does on screen.
      const double bias = surface.recessed ? 1e-9 : 0.0;
      if (hit + bias < nearest) {
        nearest = hit + bias;
        best = s;
      }
    }
  }
  return best;
}

}  // namespace tactus::viewer
