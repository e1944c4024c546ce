#include "precompute/grid.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::precompute {

Grid Grid::through(const Vec3& anchor, const Vec3& lo, const Vec3& hi, double spacing, std::size_t max_points) {
  if (!(spacing > 0.0) || !std::isfinite(spacing))
    throw InputError(fmt::format("grid spacing must be > 0 (got {})", spacing));
  for (int a = 0; a < 3; ++a) {
    if (!(lo[a] <= hi[a])) throw InputError(fmt::format("grid box is empty along axis {}", "xyz"[a]));
    if (anchor[a] < lo[a] || anchor[a] > hi[a])
      throw InputError(fmt::format("the contact point ({:.4g}, {:.4g}, {:.4g}) lies outside the grid box",
                                   anchor.x(), anchor.y(), anchor.z()));
  }
  Grid g;
  g.spacing = spacing;
  double total = 1.0;
  for (int a = 0; a < 3; ++a) {
    // Lattice points anchor + n·spacing inside [lo, hi]; a little slack so that a box edge
    // meant to be a lattice point is one despite round-off.
    const double slack = 1e-9 * spacing;
    const double below = std::floor((anchor[a] - lo[a] + slack) / spacing);
    const double above = std::floor((hi[a] - anchor[a] + slack) / spacing);
    total *= below + above + 1.0;
    if (total > static_cast<double>(max_points))
      throw InputError(fmt::format("the grid would have more than {} points; raise the spacing or shrink the box",
                                   max_points));
    g.origin[a] = anchor[a] - below * spacing;
    g.counts[static_cast<std::size_t>(a)] = static_cast<int>(below + above) + 1;
  }
  return g;
}

std::array<int, 3> Grid::cell(std::size_t index) const {
  const auto nx = static_cast<std::size_t>(counts[0]);
  const auto ny = static_cast<std::size_t>(counts[1]);
  return {static_cast<int>(index % nx), static_cast<int>((index / nx) % ny), static_cast<int>(index / (nx * ny))};
}

Vec3 Grid::point(std::size_t index) const {
  const auto c = cell(index);
  return point(c[0], c[1], c[2]);
}

std::size_t Grid::nearest(const Vec3& p) const {
  int c[3];
  for (int a = 0; a < 3; ++a) {
    const double t = std::round((p[a] - origin[a]) / spacing);
    c[a] = static_cast<int>(std::clamp(t, 0.0, static_cast<double>(counts[static_cast<std::size_t>(a)] - 1)));
  }
  return index(c[0], c[1], c[2]);
}

}  // namespace tactus::precompute
