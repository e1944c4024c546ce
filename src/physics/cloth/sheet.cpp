#include "physics/cloth/sheet.hpp"

#include <cmath>

#include "core/error.hpp"

namespace tactus::physics {

SheetGrid rectangular_sheet(double width, double height, double spacing, const Vec3& origin, const Vec3& warp_axis,
                            const Vec3& weft_axis, SheetBending bending) {
  if (!(width > 0.0 && height > 0.0 && spacing > 0.0 && std::isfinite(width) && std::isfinite(height)))
    throw InputError("sheet: width, height and spacing must be positive and finite");
  if (std::abs(warp_axis.norm() - 1.0) > 1e-9 || std::abs(weft_axis.norm() - 1.0) > 1e-9 ||
      std::abs(warp_axis.dot(weft_axis)) > 1e-9)
    throw InputError("sheet: the warp and weft axes must be orthonormal");
  const double cells_u = std::ceil(width / spacing - 1e-9), cells_v = std::ceil(height / spacing - 1e-9);
  if ((cells_u + 1) * (cells_v + 1) > 4e6) throw InputError("sheet: more than 4 million nodes; use a larger spacing");
  SheetGrid g;
  g.nodes_u = static_cast<int>(cells_u) + 1;
  g.nodes_v = static_cast<int>(cells_v) + 1;
  const double du = width / cells_u, dv = height / cells_v;
  for (int j = 0; j < g.nodes_v; ++j)
    for (int i = 0; i < g.nodes_u; ++i) {
      const Vec2 uv(i * du, j * dv);
      g.cloth.uv.push_back(uv);
      g.cloth.mesh.vertices.push_back(origin + uv.x() * warp_axis + uv.y() * weft_axis);
    }
  for (int j = 0; j + 1 < g.nodes_v; ++j)
    for (int i = 0; i + 1 < g.nodes_u; ++i) {
      const auto a = g.at(i, j), b = g.at(i + 1, j), c = g.at(i + 1, j + 1), d = g.at(i, j + 1);
      if ((i + j) % 2 == 0) {
        g.cloth.mesh.triangles.push_back({a, b, c});
        g.cloth.mesh.triangles.push_back({a, c, d});
      } else {
        g.cloth.mesh.triangles.push_back({a, b, d});
        g.cloth.mesh.triangles.push_back({b, c, d});
      }
    }
  if (bending == SheetBending::yarns) {
    // Each bend stands for the strip of fabric its middle node owns: a half strip on the border.
    auto share = [](int k, int count) { return (k == 0 || k == count - 1) ? 0.5 : 1.0; };
    for (int j = 0; j < g.nodes_v; ++j)
      for (int i = 1; i + 1 < g.nodes_u; ++i)
        g.cloth.yarns.push_back({g.at(i - 1, j), g.at(i, j), g.at(i + 1, j), true, du * dv * share(j, g.nodes_v)});
    for (int i = 0; i < g.nodes_u; ++i)
      for (int j = 1; j + 1 < g.nodes_v; ++j)
        g.cloth.yarns.push_back({g.at(i, j - 1), g.at(i, j), g.at(i, j + 1), false, du * dv * share(i, g.nodes_u)});
  }
  return g;
}

std::vector<std::int32_t> clamp_warp_start(SheetGrid& grid, int columns) {
  if (columns < 2 || columns >= grid.nodes_u) throw InputError("sheet: a clamp holds 2 to all but one warp columns");
  std::vector<std::int32_t> held;
  for (int j = 0; j < grid.nodes_v; ++j)
    for (int i = 0; i < columns; ++i) held.push_back(grid.at(i, j));
  for (auto& y : grid.cloth.yarns)
    if (y.warp && y.b % grid.nodes_u == columns - 1) {
      y.curvature_scale = 2.0;
      y.area *= 0.5;
    }
  return held;
}

}  // namespace tactus::physics
