#include "physics/mapping.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace tactus::physics {

Vec4 barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  Mat3 m;
  m << b - a, c - a, d - a;
  const Vec3 l = m.partialPivLu().solve(p - a);
  return {1.0 - l.sum(), l[0], l[1], l[2]};
}

namespace {

/// Closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision Detection §5.1.5).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

/// Distance from p to the solid tetrahedron (0 inside).
double distance_to_tet(const Vec3& p, const std::array<Vec3, 4>& v, const Vec4& w) {
  if (w.minCoeff() >= 0.0) return 0.0;
  double best = std::numeric_limits<double>::infinity();
  constexpr int faces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (const auto& f : faces)
    best = std::min(best, (closest_on_triangle(p, v[f[0]], v[f[1]], v[f[2]]) - p).norm());
  return best;
}

/// How far the weights leave [0, 1]: ranks candidate elements for points just outside.
double outside_measure(const Vec4& w) {
  double m = 0.0;
  for (int i = 0; i < 4; ++i) m = std::max(m, -w[i]);
  return m;
}

/// A uniform grid over tetrahedron bounding boxes, for point location.
class TetGrid {
 public:
  explicit TetGrid(const mesh::TetMesh& mesh) : mesh_(mesh) {
    box_ = mesh.bounds();
    const double cells = std::max(1.0, std::cbrt(static_cast<double>(mesh.tets.size())));
    const Vec3 size = box_.size();
    const double h = std::max(size.maxCoeff() / cells, 1e-12);
    for (int k = 0; k < 3; ++k) dims_[k] = std::max(1, static_cast<int>(std::ceil(size[k] / h)));
    cell_ = h;
    buckets_.resize(static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2]);
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
      Aabb b;
      for (auto v : mesh.tets[t]) b.add(mesh.vertices[static_cast<std::size_t>(v)]);
      const auto lo = cell_of(b.min), hi = cell_of(b.max);
      for (int i = lo[0]; i <= hi[0]; ++i)
        for (int j = lo[1]; j <= hi[1]; ++j)
          for (int k = lo[2]; k <= hi[2]; ++k) buckets_[index(i, j, k)].push_back(static_cast<mesh::Index>(t));
    }
  }

  /// The containing tetrahedron (or the least-outside candidate in the point's cell and its
  /// neighbours; -1 if the grid holds none nearby).
  std::pair<mesh::Index, Vec4> locate(const Vec3& p) const {
    mesh::Index best = -1;
    Vec4 best_w = Vec4::Zero();
    double best_m = std::numeric_limits<double>::infinity();
    const auto c = cell_of(p);
    for (int ring = 0; ring <= 2 && best_m > 0.0; ++ring) {
      for (int i = c[0] - ring; i <= c[0] + ring; ++i)
        for (int j = c[1] - ring; j <= c[1] + ring; ++j)
          for (int k = c[2] - ring; k <= c[2] + ring; ++k) {
            if (i < 0 || j < 0 || k < 0 || i >= dims_[0] || j >= dims_[1] || k >= dims_[2]) continue;
            for (auto t : buckets_[index(i, j, k)]) {
              const auto& e = mesh_.tets[static_cast<std::size_t>(t)];
              const Vec4 w = barycentric(p, mesh_.vertices[static_cast<std::size_t>(e[0])],
                                         mesh_.vertices[static_cast<std::size_t>(e[1])],
                                         mesh_.vertices[static_cast<std::size_t>(e[2])],
                                         mesh_.vertices[static_cast<std::size_t>(e[3])]);
              const double m = outside_measure(w);
              if (m < best_m) {
                best_m = m;
                best = t;
                best_w = w;
              }
            }
          }
      if (best >= 0 && best_m <= 1e-9) break;
    }
    return {best, best_w};
  }

 private:
  std::array<int, 3> cell_of(const Vec3& p) const {
    std::array<int, 3> c{};
    for (int k = 0; k < 3; ++k)
      c[k] = std::clamp(static_cast<int>(std::floor((p[k] - box_.min[k]) / cell_)), 0, dims_[k] - 1);
    return c;
  }
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * dims_[1] + j) * dims_[0] + i;
  }

  const mesh::TetMesh& mesh_;
  Aabb box_;
  double cell_ = 1.0;
  std::array<int, 3> dims_{1, 1, 1};
  std::vector<std::vector<mesh::Index>> buckets_;
};

}  // namespace

BarycentricMapping::BarycentricMapping(const mesh::TetMesh& volume, const std::vector<Vec3>& points) {
  if (volume.tets.empty()) throw std::invalid_argument("barycentric mapping: the volume mesh has no tetrahedra");
  const TetGrid grid(volume);
  nodes_.reserve(points.size());
  tets_.reserve(points.size());
  weights_.reserve(points.size());
  for (const auto& p : points) {
    auto [t, w] = grid.locate(p);
    if (t < 0) {
      // Far outside the grid's reach: fall back to the nearest tetrahedron centroid.
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < volume.tets.size(); ++i) {
        Vec3 c = Vec3::Zero();
        for (auto v : volume.tets[i]) c += volume.vertices[static_cast<std::size_t>(v)] / 4.0;
        if ((c - p).squaredNorm() < best) {
          best = (c - p).squaredNorm();
          t = static_cast<mesh::Index>(i);
        }
      }
      const auto& e = volume.tets[static_cast<std::size_t>(t)];
      w = barycentric(p, volume.vertices[static_cast<std::size_t>(e[0])], volume.vertices[static_cast<std::size_t>(e[1])],
                      volume.vertices[static_cast<std::size_t>(e[2])], volume.vertices[static_cast<std::size_t>(e[3])]);
    }
    const auto& e = volume.tets[static_cast<std::size_t>(t)];
    std::array<Vec3, 4> corners;
    for (std::size_t k = 0; k < 4; ++k) corners[k] = volume.vertices[static_cast<std::size_t>(e[k])];
    outside_.push_back(distance_to_tet(p, corners, w));
    max_outside_ = std::max(max_outside_, outside_.back());
    nodes_.push_back(e);
    tets_.push_back(t);
    weights_.push_back(w);
  }
}

void BarycentricMapping::apply(const VecX& x, std::vector<Vec3>& points) const {
  points.resize(tets_.size());
  for (std::size_t i = 0; i < tets_.size(); ++i) {
    Vec3 p = Vec3::Zero();
    for (int k = 0; k < 4; ++k) p += weights_[i][k] * x.segment<3>(3 * nodes_[i][static_cast<std::size_t>(k)]);
    points[i] = p;
  }
}

void BarycentricMapping::apply_transpose(const std::vector<Vec3>& point_forces, VecX& node_forces) const {
  const std::size_t n = std::min(point_forces.size(), tets_.size());
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 4; ++k)
      node_forces.segment<3>(3 * nodes_[i][static_cast<std::size_t>(k)]) += weights_[i][k] * point_forces[i];
}

}  // namespace tactus::physics
