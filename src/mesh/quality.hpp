#pragma once
// Element quality measures for triangle and tetrahedral meshes.
#include <cstddef>
#include <limits>

#include "mesh/tet_mesh.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::mesh {

/// Running min / max / mean of a measure over elements.
struct Stats {
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();
  double mean = 0.0;
  std::size_t count = 0;

  void add(double x);
};

struct TriQuality {
  Stats min_angle_deg;  ///< smallest angle of each triangle
  Stats aspect_ratio;   ///< longest edge / shortest altitude · √3/2; 1 for equilateral
  Stats edge_length;    ///< every triangle's three edges (shared edges counted twice)
};

/// Radius ratio below which a tet counts as a sliver.
inline constexpr double kSliverRadiusRatio = 0.1;

struct TetQuality {
  Stats radius_ratio;       ///< 3·r_in / r_circ: 1 regular, 0 flat; negative when inverted
  Stats min_dihedral_deg;   ///< each tet's smallest dihedral angle
  Stats max_dihedral_deg;   ///< each tet's largest dihedral angle
  Stats edge_length_ratio;  ///< longest / shortest edge of each tet
  std::size_t inverted = 0;
  std::size_t slivers = 0;  ///< |radius ratio| < kSliverRadiusRatio
};

/// Quality of one triangle: {min angle in degrees, aspect ratio}.
struct TriangleShape {
  double min_angle_deg;
  double aspect_ratio;
};
TriangleShape triangle_shape(const Vec3& a, const Vec3& b, const Vec3& c);

struct TetShape {
  double radius_ratio;
  double min_dihedral_deg;
  double max_dihedral_deg;
  double edge_length_ratio;
};
TetShape tet_shape(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

TriQuality tri_quality(const TriMesh& mesh);
TetQuality tet_quality(const TetMesh& mesh);

}  // namespace tactus::mesh
