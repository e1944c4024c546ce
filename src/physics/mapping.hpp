#pragma once
// Barycentric mapping of points (a visual skin, a collision surface, an embedded vessel or
// fascia sheet; seed 003 §3.1) into a tetrahedral mesh: each point follows the tetrahedron
// that contains it at rest, and forces on the points map back by the transpose.
#include <array>
#include <vector>

#include "core/math.hpp"
#include "mesh/tet_mesh.hpp"

namespace tactus::physics {

class BarycentricMapping {
 public:
  /// Maps `points` (at rest) into `volume`. A point outside every tetrahedron takes the
  /// nearest one (by distance to it) and extrapolated weights; max_outside_distance()
  /// reports how far such a point was.
  BarycentricMapping(const mesh::TetMesh& volume, const std::vector<Vec3>& points);

  [[nodiscard]] std::size_t point_count() const { return tets_.size(); }
  /// Positions of the mapped points for volume node positions x (3N).
  void apply(const VecX& x, std::vector<Vec3>& points) const;
  /// Adds the transpose: forces on the points → forces on volume nodes (3N).
  void apply_transpose(const std::vector<Vec3>& point_forces, VecX& node_forces) const;

  [[nodiscard]] mesh::Index tet_of(std::size_t point) const { return tets_[point]; }
  [[nodiscard]] const Vec4& weights_of(std::size_t point) const { return weights_[point]; }
  [[nodiscard]] double max_outside_distance() const { return max_outside_; }
  /// How far `point` lay outside its tetrahedron at rest (0 inside).
  [[nodiscard]] double outside_distance(std::size_t point) const { return outside_[point]; }

 private:
  std::vector<mesh::Tet> nodes_;  // the four volume nodes of each point's tetrahedron
  std::vector<mesh::Index> tets_;
  std::vector<Vec4> weights_;
  std::vector<double> outside_;
  double max_outside_ = 0.0;
};

/// Barycentric coordinates of p in tetrahedron (a, b, c, d).
Vec4 barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace tactus::physics
