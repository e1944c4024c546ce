#pragma once
// Synthetic label images with known volumes and interface areas, and the measures the
// validation compares with them.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include "imaging/label_image.hpp"
#include "mesh/tet_mesh.hpp"

namespace tactus::imaging::test {

/// Label 2: a sphere of radius r_inner; label 1: the shell out to r_outer; centred in a
/// cube of n voxels of edge h with a margin of background.
inline LabelImage nested_spheres(std::size_t n, double h, double r_outer, double r_inner) {
  LabelImage image;
  image.size = {n, n, n};
  image.spacing = Vec3::Constant(h);
  image.origin = Vec3(0.01, -0.02, 0.03);  // anywhere: the measures do not depend on it
  image.labels.resize(n * n * n);
  // The centre off the voxel grid, so that no plane of voxels is special.
  const Vec3 centre = Vec3::Constant(0.5 * static_cast<double>(n - 1) * h) + Vec3(0.31, 0.17, 0.23) * h;
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t j = 0; j < n; ++j)
      for (std::size_t i = 0; i < n; ++i) {
        const double r = (Vec3(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)) * h - centre).norm();
        image.labels[image.index(i, j, k)] = r < r_inner ? 2 : r < r_outer ? 1 : 0;
      }
  return image;
}

/// Label 1: a slab [lo, hi] (faces halfway between voxel centres); label 2: a cylinder
/// "vessel" of radius r along i through the whole slab, its axis at (y, z) = axis_yz.
struct Vessel {
  LabelImage image;
  Vec3 lo, hi;  ///< slab corners, in image coordinates [m] (voxel (0,0,0) at 0)
  double radius = 0.0;
};
inline Vessel vessel_in_slab(const std::array<std::size_t, 3>& size, double h, double radius) {
  Vessel v;
  v.image.size = size;
  v.image.spacing = Vec3::Constant(h);
  v.radius = radius;
  for (int a = 0; a < 3; ++a) {
    v.lo[a] = 3.5 * h;
    v.hi[a] = (static_cast<double>(size[a]) - 4.5) * h;
  }
  const double cy = 0.5 * (v.lo[1] + v.hi[1]) + 0.27 * h, cz = 0.5 * (v.lo[2] + v.hi[2]) + 0.41 * h;
  v.image.labels.resize(size[0] * size[1] * size[2]);
  for (std::size_t k = 0; k < size[2]; ++k)
    for (std::size_t j = 0; j < size[1]; ++j)
      for (std::size_t i = 0; i < size[0]; ++i) {
        const Vec3 p = Vec3(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k)) * h;
        const bool in_slab = (p.array() > v.lo.array()).all() && (p.array() < v.hi.array()).all();
        const bool in_vessel = std::hypot(p.y() - cy, p.z() - cz) < radius;
        v.image.labels[v.image.index(i, j, k)] = in_slab ? (in_vessel ? 2 : 1) : 0;
      }
  return v;
}

inline std::map<int, double> region_volumes(const mesh::TetMesh& m) {
  std::map<int, double> volume;
  for (std::size_t t = 0; t < m.tets.size(); ++t) volume[m.tet_regions[t]] += m.tet_volume(t);
  return volume;
}

/// Area of the faces shared by a tet of region a and one of region b (a < b); a == 0 is
/// the outer boundary of region b.
inline std::map<std::pair<int, int>, double> interface_areas(const mesh::TetMesh& m) {
  std::map<std::array<int, 3>, std::pair<int, int>> faces;  // sorted corners → (first region, count)
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const auto& tet = m.tets[t];
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> key{tet[(f + 1) % 4], tet[(f + 2) % 4], tet[(f + 3) % 4]};
      std::sort(key.begin(), key.end());
      auto [it, inserted] = faces.emplace(key, std::pair<int, int>{m.tet_regions[t], 0});
      if (!inserted) it->second.second = m.tet_regions[t];
      else it->second.second = -1;  // unpaired so far
    }
  }
  std::map<std::pair<int, int>, double> area;
  for (const auto& [key, regions] : faces) {
    const int a = regions.first, b = regions.second < 0 ? 0 : regions.second;
    if (a == b) continue;
    const double s = 0.5 * (m.vertices[static_cast<std::size_t>(key[1])] - m.vertices[static_cast<std::size_t>(key[0])])
                               .cross(m.vertices[static_cast<std::size_t>(key[2])] - m.vertices[static_cast<std::size_t>(key[0])])
                               .norm();
    area[{std::min(a, b), std::max(a, b)}] += s;
  }
  return area;
}

}  // namespace tactus::imaging::test
