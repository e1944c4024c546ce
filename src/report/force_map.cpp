#include "report/force_map.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <variant>

#include "core/error.hpp"
#include "core/png.hpp"
#include "compile/device_setup.hpp"
#include "report/palette.hpp"

namespace tactus::report {

// A report reads what a run left: its loops' statistics, frames and events.
using namespace tactus::runtime;
namespace {

const haptics::RasterPath* raster_of(const scene::Device& d) {
  if (const auto* s = std::get_if<scene::ScriptedDevice>(&d.source)) return std::get_if<haptics::RasterPath>(&s->trajectory);
  if (const auto* o = std::get_if<scene::SimulatedOperatorDevice>(&d.source))
    return std::get_if<haptics::RasterPath>(&o->target);
  return nullptr;
}

/// Side cells cover [lo − cell/2, hi + cell/2] with centres from lo.
int cell_count(double lo, double hi, double cell) {
  return std::max(1, static_cast<int>(std::lround((hi - lo) / cell)) + 1);
}

}  // namespace

double ForceMap::max_peak() const {
  double m = 0.0;
  for (std::size_t i = 0; i < peak.size(); ++i)
    if (samples[i] > 0) m = std::max(m, peak[i]);
  return m;
}

ForceMap build_force_map(const scene::Model& model, std::size_t device, const std::vector<HapticFrame>& frames) {
  const scene::Device& d = model.devices.at(device);
  const haptics::WorkspaceMap map = compile::workspace_map(d);
  const Vec3 up_in_device = map.force_to_device(Vec3::UnitZ());
  ForceMap out;
  Vec2 lo, hi;
  if (const haptics::RasterPath* raster = raster_of(d)) {
    // The rectangle's corners in the scene (a rotated device maps it to another box).
    lo = Vec2::Constant(std::numeric_limits<double>::infinity());
    hi = -lo;
    for (const double x : {raster->min.x(), raster->max.x()})
      for (const double y : {raster->min.y(), raster->max.y()}) {
        const Vec2 p = map.to_scene(Vec3(x, y, raster->z)).head<2>();
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    out.cell = raster->spacing * map.scale;
  } else {
    lo = Vec2::Constant(std::numeric_limits<double>::infinity());
    hi = -lo;
    for (const HapticFrame& f : frames)
      if (f.device == device && f.contact) {
        const Vec2 p = map.to_scene(f.position).head<2>();
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    if (!(lo.x() <= hi.x()))
      throw InputError(fmt::format("device '{}' never touched anything: there is no force map to draw", d.name));
    out.cell = std::max((hi - lo).maxCoeff() / 31.0, 1e-6);
  }
  out.origin = lo;
  out.columns = cell_count(lo.x(), hi.x(), out.cell);
  out.rows = cell_count(lo.y(), hi.y(), out.cell);
  const std::size_t cells = static_cast<std::size_t>(out.columns) * static_cast<std::size_t>(out.rows);
  out.peak.assign(cells, 0.0);
  out.mean.assign(cells, 0.0);
  out.samples.assign(cells, 0);
  for (const HapticFrame& f : frames) {
    if (f.device != device) continue;
    const Vec2 p = map.to_scene(f.position).head<2>();
    const long column = std::lround((p.x() - out.origin.x()) / out.cell);
    const long row = std::lround((p.y() - out.origin.y()) / out.cell);
    if (column < 0 || row < 0 || column >= out.columns || row >= out.rows) continue;
    const double normal = f.contact ? std::max(0.0, f.force.dot(up_in_device)) : 0.0;
    const std::size_t i = out.index(static_cast<int>(column), static_cast<int>(row));
    out.peak[i] = std::max(out.peak[i], normal);
    out.mean[i] += normal;
    ++out.samples[i];
  }
  for (std::size_t i = 0; i < cells; ++i)
    if (out.samples[i] > 0) out.mean[i] /= out.samples[i];
  for (const scene::Body& body : model.bodies)
    for (const scene::Nodule& n : body.nodules) out.nodules.emplace_back(n.center.head<2>(), n.radius);
  return out;
}

std::array<std::uint8_t, 3> viridis(double t) {
  // Matplotlib's viridis sampled at nine points, linear in between.
  static constexpr std::array<std::array<double, 3>, 9> anchors{{{68, 1, 84},
                                                                 {71, 44, 122},
                                                                 {59, 81, 139},
                                                                 {44, 113, 142},
                                                                 {33, 144, 141},
                                                                 {39, 173, 129},
                                                                 {92, 200, 99},
                                                                 {170, 220, 50},
                                                                 {253, 231, 37}}};
  t = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.0;
  const double x = t * 8.0;
  const auto i = std::min(static_cast<std::size_t>(x), std::size_t{7});
  const double s = x - static_cast<double>(i);
  std::array<std::uint8_t, 3> rgb{};
  for (std::size_t k = 0; k < 3; ++k)
    rgb[k] = static_cast<std::uint8_t>(std::lround(anchors[i][k] + s * (anchors[i + 1][k] - anchors[i][k])));
  return rgb;
}

namespace {

constexpr raster::Rgb kUnvisited{128, 128, 128};
constexpr double kLabelSize = 13.0;

/// The strongest cell's mean [N] and where it is.
double strongest(const ForceMap& map, int& best_column, int& best_row) {
  double top = 0.0;
  best_column = best_row = 0;
  for (int row = 0; row < map.rows; ++row)
    for (int column = 0; column < map.columns; ++column) {
      const std::size_t i = map.index(column, row);
      if (map.samples[i] > 0 && map.mean[i] > top) {
        top = map.mean[i];
        best_column = column;
        best_row = row;
      }
    }
  return top;
}

}  // namespace

ForceMapLayout force_map_layout(const ForceMap& map) {
  ForceMapLayout l;
  l.cell_pixels = std::max(1, 320 / std::max({map.columns, map.rows, 1}));
  l.plot_left = 64;
  l.plot_top = 30;
  l.plot_width = map.columns * l.cell_pixels;
  l.plot_height = map.rows * l.cell_pixels;
  l.bar_left = l.plot_left + l.plot_width + 18;
  l.bar_top = l.plot_top;
  l.bar_width = 16;
  l.bar_height = l.plot_height;
  l.width = l.bar_left + l.bar_width + 64;
  l.height = l.plot_top + l.plot_height + 46;
  int column = 0, row = 0;
  l.full_scale = strongest(map, column, row);
  return l;
}

raster::Image render_force_map(const ForceMap& map) {
  const ForceMapLayout l = force_map_layout(map);
  raster::Image image(l.width, l.height, kPaper);
  const double top = l.full_scale;
  for (int row = 0; row < map.rows; ++row)
    for (int column = 0; column < map.columns; ++column) {
      const std::size_t i = map.index(column, row);
      const raster::Rgb colour = map.samples[i] == 0 ? kUnvisited : viridis(top > 0.0 ? map.mean[i] / top : 0.0);
      // Image rows run top to bottom: the highest y first.
      const int x = l.plot_left + column * l.cell_pixels, y = l.plot_top + (map.rows - 1 - row) * l.cell_pixels;
      raster::fill_rect(image, x, y, x + l.cell_pixels, y + l.cell_pixels, colour);
    }

  // Axes in mm over the cells' outer edges.
  const double x_lo = 1e3 * (map.origin.x() - 0.5 * map.cell), x_hi = x_lo + 1e3 * map.cell * map.columns;
  const double y_lo = 1e3 * (map.origin.y() - 0.5 * map.cell), y_hi = y_lo + 1e3 * map.cell * map.rows;
  const auto to_px = [&](double x_mm, double y_mm) {
    return Vec2(l.plot_left + (x_mm - x_lo) / (x_hi - x_lo) * l.plot_width,
                l.plot_top + (y_hi - y_mm) / (y_hi - y_lo) * l.plot_height);
  };
  const double step = raster::nice_step(std::max(x_hi - x_lo, y_hi - y_lo), 5.0);
  const int bottom = l.plot_top + l.plot_height;
  for (double v = std::ceil(x_lo / step - 1e-9) * step; v <= x_hi + 1e-9 * step; v += step) {
    const double x = to_px(v, y_lo).x();
    raster::draw_line(image, x, bottom, x, bottom + 5, kInk);
    const std::string label = raster::tick_label(v, step);
    raster::draw_text(image, static_cast<int>(x) - raster::text_width(label, kLabelSize) / 2, bottom + 7, label,
                      kLabelSize, kInk);
  }
  for (double v = std::ceil(y_lo / step - 1e-9) * step; v <= y_hi + 1e-9 * step; v += step) {
    const double y = to_px(x_lo, v).y();
    raster::draw_line(image, l.plot_left - 6, y, l.plot_left - 1, y, kInk);
    const std::string label = raster::tick_label(v, step);
    raster::draw_text(image, l.plot_left - 9 - raster::text_width(label, kLabelSize),
                      static_cast<int>(y) - static_cast<int>(kLabelSize / 2), label, kLabelSize, kInk);
  }
  const std::string x_title = "x [mm]";
  raster::draw_text(image, l.plot_left + l.plot_width / 2 - raster::text_width(x_title, kLabelSize) / 2, bottom + 26,
                    x_title, kLabelSize, kInk);
  raster::draw_text(image, 4, 8, "y [mm]", kLabelSize, kInk);
  raster::draw_text(image, l.plot_left, 8, "mean normal force", kLabelSize, kInk);
  raster::stroke_rect(image, l.plot_left - 1, l.plot_top - 1, l.plot_left + l.plot_width + 1, bottom + 1, kInk);

  // The nodules, dashed, clipped to the plot.
  for (const std::pair<Vec2, double>& nodule : map.nodules) {
    const Vec2 centre = nodule.first;
    const double radius = nodule.second;
    constexpr int kSegments = 72;
    for (int k = 0; k < kSegments; k += 2) {
      const auto at = [&](int s) {
        const double a = 2.0 * 3.14159265358979323846 * s / kSegments;
        return to_px(1e3 * (centre.x() + radius * std::cos(a)), 1e3 * (centre.y() + radius * std::sin(a)));
      };
      const Vec2 p = at(k), q = at(k + 1);
      const auto inside = [&](const Vec2& v) {
        return v.x() >= l.plot_left && v.x() < l.plot_left + l.plot_width && v.y() >= l.plot_top && v.y() < bottom;
      };
      if (inside(p) && inside(q)) raster::draw_line(image, p.x(), p.y(), q.x(), q.y(), kPaper, 1.5);
    }
  }

  // The colour bar: 0 N at the bottom, the strongest cell at the top.
  for (int r = 0; r < l.bar_height; ++r) {
    const double t = 1.0 - (r + 0.5) / l.bar_height;
    raster::fill_rect(image, l.bar_left, l.bar_top + r, l.bar_left + l.bar_width, l.bar_top + r + 1, viridis(t));
  }
  raster::stroke_rect(image, l.bar_left - 1, l.bar_top - 1, l.bar_left + l.bar_width + 1, l.bar_top + l.bar_height + 1,
                      kInk);
  raster::draw_text(image, l.bar_left, 8, "N", kLabelSize, kInk);
  if (top > 0.0) {
    const double bar_step = raster::nice_step(top, 4.0);
    for (double v = 0.0; v <= top * (1.0 + 1e-9); v += bar_step) {
      const double y = l.bar_top + (1.0 - v / top) * l.bar_height;
      const int right = l.bar_left + l.bar_width;
      raster::draw_line(image, right, y, right + 4, y, kInk);
      raster::draw_text(image, right + 7, static_cast<int>(y) - static_cast<int>(kLabelSize / 2),
                        raster::tick_label(v, bar_step), kLabelSize, kInk);
    }
  }
  return image;
}

std::string write_force_map_png(const ForceMap& map, const std::filesystem::path& path) {
  const raster::Image image = render_force_map(map);
  png::write_rgb(path, image.width, image.height, image.rgb);
  int best_column = 0, best_row = 0;
  const double top = strongest(map, best_column, best_row);
  const Vec2 far = map.cell_center(map.columns - 1, map.rows - 1);
  const Vec2 best = map.cell_center(best_column, best_row);
  return fmt::format(
      "force map {} ({}x{} px): {}x{} cells of {:.1f} mm, centres x [{:.4f}, {:.4f}] m, y [{:.4f}, {:.4f}] m, +y up\n"
      "  colour: mean normal force per cell, viridis from 0 N (dark purple) to {:.3f} N (yellow); grey: never "
      "visited; dashed circles: nodules\n  strongest cell {:.3f} N at x {:.4f} m, y {:.4f} m; largest single frame "
      "{:.3f} N\n",
      path.string(), image.width, image.height, map.columns, map.rows, 1e3 * map.cell, map.origin.x(), far.x(),
      map.origin.y(), far.y(), top, top, best.x(), best.y(), map.max_peak());
}

}  // namespace tactus::report
