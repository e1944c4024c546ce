#include "mesh/generators.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <unordered_map>

#include <fmt/format.h>

#include "core/error.hpp"
#include "mesh/implicit_surface.hpp"

namespace tactus::mesh {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw InputError(what);
}

void require_size(const Vec3& size, const char* who) {
  require(size.allFinite() && (size.array() > 0.0).all(),
          fmt::format("{}: size must be positive, got ({} {} {})", who, size.x(), size.y(), size.z()));
}

}  // namespace

TriMesh QuadMesh::triangulated() const {
  TriMesh out;
  out.vertices = vertices;
  out.triangles.reserve(2 * quads.size());
  for (const auto& q : quads) {
    out.triangles.push_back({q[0], q[1], q[2]});
    out.triangles.push_back({q[0], q[2], q[3]});
  }
  return out;
}

QuadMesh grid_plate_quads(double size_x, double size_y, int cells_x, int cells_y) {
  require_size(Vec3(size_x, size_y, 1.0), "grid plate");
  require(cells_x >= 1 && cells_y >= 1, fmt::format("grid plate: cells must be >= 1, got {} x {}", cells_x, cells_y));
  QuadMesh out;
  for (int j = 0; j <= cells_y; ++j)
    for (int i = 0; i <= cells_x; ++i)
      out.vertices.emplace_back(size_x * (static_cast<double>(i) / cells_x - 0.5),
                                size_y * (static_cast<double>(j) / cells_y - 0.5), 0.0);
  const auto id = [&](int i, int j) { return static_cast<Index>(j * (cells_x + 1) + i); };
  for (int j = 0; j < cells_y; ++j)
    for (int i = 0; i < cells_x; ++i) out.quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return out;
}

TriMesh grid_plate(double size_x, double size_y, int cells_x, int cells_y) {
  return grid_plate_quads(size_x, size_y, cells_x, cells_y).triangulated();
}

TriMesh box_surface(const Vec3& size, int cells) {
  require_size(size, "box surface");
  require(cells >= 1, fmt::format("box surface: cells must be >= 1, got {}", cells));
  const int n = cells + 1;
  TriMesh out;
  // Lattice points on the surface get vertices; faces share them along the box edges.
  std::vector<Index> id(static_cast<std::size_t>(n) * n * n, -1);
  const auto vertex = [&](std::array<int, 3> g) {
    Index& v = id[(static_cast<std::size_t>(g[2]) * n + g[1]) * n + g[0]];
    if (v < 0) {
      v = static_cast<Index>(out.vertices.size());
      out.vertices.push_back(
          Vec3(size.x() * (static_cast<double>(g[0]) / cells - 0.5), size.y() * (static_cast<double>(g[1]) / cells - 0.5),
               size.z() * (static_cast<double>(g[2]) / cells - 0.5)));
    }
    return v;
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;  // e_b × e_c = e_axis
    for (int side = 0; side < 2; ++side)
      for (int u = 0; u < cells; ++u)
        for (int w = 0; w < cells; ++w) {
          std::array<std::array<int, 3>, 4> g{};
          const int du[4] = {0, 1, 1, 0}, dw[4] = {0, 0, 1, 1};
          for (int k = 0; k < 4; ++k) {
            g[k][axis] = side * cells;
            g[k][b] = u + du[k];
            g[k][c] = w + dw[k];
          }
          Index q[4];
          for (int k = 0; k < 4; ++k) q[k] = vertex(g[k]);
          if (side == 1) {
            out.triangles.push_back({q[0], q[1], q[2]});
            out.triangles.push_back({q[0], q[2], q[3]});
          } else {
            out.triangles.push_back({q[0], q[2], q[1]});
            out.triangles.push_back({q[0], q[3], q[2]});
          }
        }
  }
  return out;
}

TetMesh box_volume(const Vec3& size, int cells_x, int cells_y, int cells_z) {
  require_size(size, "box volume");
  require(cells_x >= 1 && cells_y >= 1 && cells_z >= 1,
          fmt::format("box volume: cells must be >= 1, got {} x {} x {}", cells_x, cells_y, cells_z));
  TetMesh out;
  const auto id = [&](int i, int j, int k) { return static_cast<Index>((k * (cells_y + 1) + j) * (cells_x + 1) + i); };
  for (int k = 0; k <= cells_z; ++k)
    for (int j = 0; j <= cells_y; ++j)
      for (int i = 0; i <= cells_x; ++i)
        out.vertices.push_back(Vec3(size.x() * (static_cast<double>(i) / cells_x - 0.5),
                                    size.y() * (static_cast<double>(j) / cells_y - 0.5),
                                    size.z() * (static_cast<double>(k) / cells_z - 0.5)));
  // Six tets per cube around the main diagonal, one per axis order (Kuhn): every cube
  // splits its faces the same way, so neighbouring cubes match.
  std::array<int, 3> perm{0, 1, 2};
  std::vector<std::array<int, 3>> orders;
  do orders.push_back(perm);
  while (std::next_permutation(perm.begin(), perm.end()));
  for (int k = 0; k < cells_z; ++k)
    for (int j = 0; j < cells_y; ++j)
      for (int i = 0; i < cells_x; ++i)
        for (const auto& order : orders) {
          std::array<int, 3> g{i, j, k};
          Tet t{};
          t[0] = id(g[0], g[1], g[2]);
          for (int s = 0; s < 3; ++s) {
            ++g[order[s]];
            t[s + 1] = id(g[0], g[1], g[2]);
          }
          if (signed_tet_volume(out.vertices[t[0]], out.vertices[t[1]], out.vertices[t[2]], out.vertices[t[3]]) < 0)
            std::swap(t[1], t[2]);
          out.tets.push_back(t);
        }
  return out;
}

TriMesh sphere(double radius, int subdivisions) {
  require(std::isfinite(radius) && radius > 0.0, fmt::format("sphere: radius must be positive, got {}", radius));
  require(subdivisions >= 0 && subdivisions <= 10,
          fmt::format("sphere: subdivisions must be in [0, 10], got {}", subdivisions));
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  TriMesh m;
  m.vertices = {{-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0}, {0, -1, phi}, {0, 1, phi},
                {0, -1, -phi}, {0, 1, -phi}, {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}};
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (auto& v : m.vertices) v.normalize();
  // Outward: the icosahedron is convex and centred, so a face's normal must face its centroid.
  for (auto& t : m.triangles) {
    const Vec3 n = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
    if (n.dot(m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) < 0.0) std::swap(t[1], t[2]);
  }
  for (int s = 0; s < subdivisions; ++s) {
    std::unordered_map<std::uint64_t, Index> midpoint;
    const auto mid = [&](Index a, Index b) {
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint64_t>(std::max(a, b));
      auto [it, inserted] = midpoint.try_emplace(key, static_cast<Index>(m.vertices.size()));
      if (inserted) m.vertices.push_back((m.vertices[a] + m.vertices[b]).normalized());
      return it->second;
    };
    std::vector<Triangle> finer;
    finer.reserve(4 * m.triangles.size());
    for (const auto& t : m.triangles) {
      const Index ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
      finer.push_back({t[0], ab, ca});
      finer.push_back({t[1], bc, ab});
      finer.push_back({t[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    m.triangles = std::move(finer);
  }
  for (auto& v : m.vertices) v *= radius;
  return m;
}

TriMesh cylinder(double radius, double height, int segments, int rings) {
  require(std::isfinite(radius) && radius > 0.0 && std::isfinite(height) && height > 0.0,
          fmt::format("cylinder: radius and height must be positive, got {} and {}", radius, height));
  require(segments >= 3 && rings >= 1,
          fmt::format("cylinder: needs segments >= 3 and rings >= 1, got {} and {}", segments, rings));
  TriMesh m;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double theta = 2.0 * std::numbers::pi * s / segments;
      m.vertices.emplace_back(radius * std::cos(theta), radius * std::sin(theta), height * r / rings);
    }
  const auto id = [&](int r, int s) { return static_cast<Index>(r * segments + (s % segments)); };
  // Side quads: tangent × axis points outward.
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      m.triangles.push_back({id(r, s), id(r, s + 1), id(r + 1, s + 1)});
      m.triangles.push_back({id(r, s), id(r + 1, s + 1), id(r + 1, s)});
    }
  const auto bottom = static_cast<Index>(m.vertices.size());
  m.vertices.emplace_back(0.0, 0.0, 0.0);
  const auto top = static_cast<Index>(m.vertices.size());
  m.vertices.emplace_back(0.0, 0.0, height);
  for (int s = 0; s < segments; ++s) {
    m.triangles.push_back({bottom, id(0, s + 1), id(0, s)});
    m.triangles.push_back({top, id(rings, s), id(rings, s + 1)});
  }
  return m;
}

TriMesh organ(double length, int resolution) {
  require(std::isfinite(length) && length > 0.0, fmt::format("organ: length must be positive, got {}", length));
  require(resolution >= 4 && resolution <= 1000,
          fmt::format("organ: resolution must be in [4, 1000], got {}", resolution));
  // A liver-like blend laid out for a 0.22 m organ (0.15 m wide, 0.08 m thick), then scaled:
  // a large right lobe, a thinner left lobe, a posterior bulge and a small caudate lobe.
  const std::vector<Ellipsoid> lobes{
      {Vec3(-0.030, 0.000, 0.000), Vec3(0.080, 0.070, 0.040)},
      {Vec3(0.050, 0.015, -0.004), Vec3(0.066, 0.046, 0.021)},
      {Vec3(-0.055, -0.022, 0.004), Vec3(0.050, 0.048, 0.034)},
      {Vec3(0.005, -0.025, 0.012), Vec3(0.040, 0.030, 0.022)},
  };
  const double blend = 0.02;
  const auto field = [&](const Vec3& p) { return smooth_union_field(lobes, blend, p); };
  Aabb box;
  for (const auto& e : lobes) {
    box.add(e.center - e.radii);
    box.add(e.center + e.radii);
  }
  const double cell = box.size().x() / resolution;
  TriMesh m = marching_tetrahedra(field, box, cell);
  taubin_smooth(m, 5);

  // Centre on the bounding box and scale to the requested length.
  const Aabb b = m.bounds();
  const double scale = length / b.size().x();
  const Vec3 c = b.center();
  for (auto& v : m.vertices) v = (v - c) * scale;
  return m;
}

}  // namespace tactus::mesh
