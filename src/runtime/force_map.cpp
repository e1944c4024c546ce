#include "runtime/force_map.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <variant>

#include "core/error.hpp"
#include "core/png.hpp"
#include "runtime/devices.hpp"

namespace tactus::runtime {
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
  const haptics::WorkspaceMap map = workspace_map(d);
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

std::string write_force_map_png(const ForceMap& map, const std::filesystem::path& path) {
  double top = 0.0;
  for (std::size_t i = 0; i < map.mean.size(); ++i)
    if (map.samples[i] > 0) top = std::max(top, map.mean[i]);
  const int scale = std::max(1, 256 / std::max(map.columns, map.rows));
  const int width = map.columns * scale, height = map.rows * scale;
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  int best_column = 0, best_row = 0;
  for (int row = 0; row < map.rows; ++row)
    for (int column = 0; column < map.columns; ++column) {
      const std::size_t i = map.index(column, row);
      if (map.samples[i] > 0 && map.mean[i] > map.mean[map.index(best_column, best_row)]) {
        best_column = column;
        best_row = row;
      }
      const std::array<std::uint8_t, 3> colour =
          map.samples[i] == 0 ? std::array<std::uint8_t, 3>{128, 128, 128} : viridis(top > 0.0 ? map.mean[i] / top : 0.0);
      // Image rows run top to bottom: the highest y first.
      for (int py = 0; py < scale; ++py)
        for (int px = 0; px < scale; ++px) {
          const std::size_t y = static_cast<std::size_t>((map.rows - 1 - row) * scale + py);
          const std::size_t x = static_cast<std::size_t>(column * scale + px);
          std::copy(colour.begin(), colour.end(), rgb.begin() + static_cast<std::ptrdiff_t>(3 * (y * static_cast<std::size_t>(width) + x)));
        }
    }
  png::write_rgb(path, width, height, rgb);
  const Vec2 far = map.cell_center(map.columns - 1, map.rows - 1);
  const Vec2 best = map.cell_center(best_column, best_row);
  return fmt::format(
      "force map {} ({}x{} px): {}x{} cells of {:.1f} mm, centres x [{:.4f}, {:.4f}] m, y [{:.4f}, {:.4f}] m, +y up\n"
      "  colour: mean normal force per cell, viridis from 0 N (dark purple) to {:.3f} N (yellow); grey: never "
      "visited\n  strongest cell {:.3f} N at x {:.4f} m, y {:.4f} m; largest single frame {:.3f} N\n",
      path.string(), width, height, map.columns, map.rows, 1e3 * map.cell, map.origin.x(), far.x(), map.origin.y(),
      far.y(), top, top, best.x(), best.y(), map.max_peak());
}

}  // namespace tactus::runtime
