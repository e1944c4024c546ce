#pragma once
// Tetrahedral volume mesh as plain arrays; adjacency lives in tet_topology.hpp.
#include <vector>

#include "mesh/tri_mesh.hpp"

namespace tactus::mesh {

/// Tets are positively oriented: (v1-v0)·((v2-v0)×(v3-v0)) > 0.
struct TetMesh {
  std::vector<Vec3> vertices;
  std::vector<Tet> tets;
  /// Optional region label per tet (Gmsh physical tag, TetGen region attribute); empty or
  /// one per tet.
  std::vector<int> tet_regions;
  /// Optional labelled triangles the file carried (Gmsh physical surfaces, TetGen .face
  /// markers); empty when the file had none. face_markers is empty or one per face.
  std::vector<Triangle> faces;
  std::vector<int> face_markers;

  [[nodiscard]] Aabb bounds() const;
  [[nodiscard]] double tet_volume(std::size_t t) const;  ///< signed
  [[nodiscard]] double volume() const;                   ///< sum of signed volumes
};

/// Signed volume of the tetrahedron (a, b, c, d).
inline double signed_tet_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

}  // namespace tactus::mesh
