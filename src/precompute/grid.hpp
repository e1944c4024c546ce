#pragma once
// The regular grid G of interaction-point positions: a lattice through the undeformed
// contact point, clipped to the box the scene gives.
#include <array>
#include <cstddef>
#include <cstdint>

#include "core/math.hpp"

namespace tactus::precompute {

struct Grid {
  Vec3 origin = Vec3::Zero();       ///< position of point (0, 0, 0) [m]
  double spacing = 1.0;             ///< d_G [m]
  std::array<int, 3> counts{1, 1, 1};  ///< points per axis

  /// The lattice of the given spacing through `anchor`, with every lattice point inside
  /// [lo, hi] (anchor must lie inside). Throws InputError for a non-positive spacing, an
  /// empty box or more than max_points points.
  static Grid through(const Vec3& anchor, const Vec3& lo, const Vec3& hi, double spacing,
                      std::size_t max_points = 2'000'000);

  [[nodiscard]] std::size_t size() const {
    return static_cast<std::size_t>(counts[0]) * static_cast<std::size_t>(counts[1]) *
           static_cast<std::size_t>(counts[2]);
  }
  [[nodiscard]] bool contains(int i, int j, int k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < counts[0] && j < counts[1] && k < counts[2];
  }
  [[nodiscard]] std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * static_cast<std::size_t>(counts[1]) + static_cast<std::size_t>(j)) *
               static_cast<std::size_t>(counts[0]) +
           static_cast<std::size_t>(i);
  }
  [[nodiscard]] std::array<int, 3> cell(std::size_t index) const;
  [[nodiscard]] Vec3 point(std::size_t index) const;
  [[nodiscard]] Vec3 point(int i, int j, int k) const {
    return origin + spacing * Vec3(i, j, k);
  }
  /// The grid point nearest to p (p clamped to the grid's box first).
  [[nodiscard]] std::size_t nearest(const Vec3& p) const;
  [[nodiscard]] Vec3 lower() const { return origin; }
  [[nodiscard]] Vec3 upper() const { return point(counts[0] - 1, counts[1] - 1, counts[2] - 1); }
};

}  // namespace tactus::precompute
