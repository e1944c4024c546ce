#pragma once
// A palpation force map: the normal force the hand felt, binned over the scanned region of
// the scene's x–y plane (the skin patch's plane), from a run's haptic frames.
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "runtime/recording.hpp"
#include "scene/model.hpp"

namespace tactus::runtime {

struct ForceMap {
  Vec2 origin = Vec2::Zero();  ///< centre of cell (0, 0), scene coordinates [m]
  double cell = 0.0;           ///< cell side [m]
  int columns = 0;             ///< along x
  int rows = 0;                ///< along y
  /// Per cell, row-major from the lowest y: the largest and the mean normal force [N] of the
  /// frames whose tool centre lay in it, and how many there were.
  std::vector<double> peak, mean;
  std::vector<std::uint32_t> samples;

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
ForceMap build_force_map(const scene::Model& model, std::size_t device, const std::vector<HapticFrame>& frames);

/// The viridis colour map (perceptually uniform, readable in grey and by most colour-blind
/// readers) at t in [0, 1].
std::array<std::uint8_t, 3> viridis(double t);

/// Writes the mean map as a PNG, seen from above (+y up), viridis from 0 N to the strongest
/// cell, cells never visited in grey; at least 256 pixels on the longer side. (The mean is
/// the steadier picture: a cell's peak also catches the jolt of touching down.) Returns the
/// legend as text lines (scale, region, where the strongest cell is).
std::string write_force_map_png(const ForceMap& map, const std::filesystem::path& path);

}  // namespace tactus::runtime
