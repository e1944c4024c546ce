#pragma once
// A palpation force map: the normal force the hand felt, binned over the scanned region of
// the scene's x–y plane (the skin patch's plane), from a run's haptic frames.
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/raster.hpp"
#include "runtime/recording.hpp"
#include "scene/model.hpp"

namespace tactus::report {

struct ForceMap {
  Vec2 origin = Vec2::Zero();  ///< centre of cell (0, 0), scene coordinates [m]
  double cell = 0.0;           ///< cell side [m]
  int columns = 0;             ///< along x
  int rows = 0;                ///< along y
  /// Per cell, row-major from the lowest y: the largest and the mean normal force [N] of the
  /// frames whose tool centre lay in it, and how many there were.
  std::vector<double> peak, mean;
  std::vector<std::uint32_t> samples;
  /// The nodules under the scanned skin, as circles in the x–y plane (centre, radius) [m].
  std::vector<std::pair<Vec2, double>> nodules;

  [[nodiscard]] std::size_t index(int column, int row) const {
    return static_cast<std::size_t>(row) * static_cast<std::size_t>(columns) + static_cast<std::size_t>(column);
  }
  [[nodiscard]] Vec2 cell_center(int column, int row) const { return origin + cell * Vec2(column, row); }
  /// The largest peak over the map [N].
  [[nodiscard]] double max_peak() const;
};

/// The force map of `device` from its frames. The normal force is the force sent to the hand
/// along the scene's +z (the sheet pushing the finger up), zero out of contact. Region and
/// cells: for a scripted raster scan, its rectangle in scene coordinates with square cells of
/// the line spacing centred on the scan lines; otherwise the box of the frames in contact in
/// 32 cells along its longer side. InputError when the device has no frame in contact and no
/// raster to take a region from.
ForceMap build_force_map(const scene::Model& model, std::size_t device, const std::vector<runtime::HapticFrame>& frames);

/// The viridis colour map (perceptually uniform, readable in grey and by most colour-blind
/// readers) at t in [0, 1].
std::array<std::uint8_t, 3> viridis(double t);

/// Where the picture of a map puts its parts [px].
struct ForceMapLayout {
  int width = 0, height = 0;  ///< the whole image
  int plot_left = 0, plot_top = 0, plot_width = 0, plot_height = 0;
  int cell_pixels = 0;  ///< a cell's side
  int bar_left = 0, bar_top = 0, bar_width = 0, bar_height = 0;  ///< the colour bar
  double full_scale = 0.0;  ///< [N] at the top of the colour bar: the strongest cell's mean
};
ForceMapLayout force_map_layout(const ForceMap& map);

/// The mean map seen from above (+y up), viridis from 0 N to the strongest cell, cells never
/// visited in grey, at least 256 pixels on the longer side; axes in mm with ticks, the colour
/// bar in N, the nodules' outlines dashed in white. (The mean is the steadier picture: a
/// cell's peak also catches the jolt of touching down.)
raster::Image render_force_map(const ForceMap& map);

/// Writes render_force_map as a PNG. Returns the legend as text lines (scale, region, where
/// the strongest cell is).
std::string write_force_map_png(const ForceMap& map, const std::filesystem::path& path);

}  // namespace tactus::report
