#include "mesh/quality.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mesh/generators.hpp"

namespace tactus::mesh {
namespace {

const double kRegularDihedral = std::acos(1.0 / 3.0) * 180.0 / std::numbers::pi;  // 70.5288°

TetMesh regular_tet() {
  TetMesh m;
  m.vertices = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  m.tets = {{0, 1, 2, 3}};
  if (m.tet_volume(0) < 0) std::swap(m.tets[0][0], m.tets[0][1]);
  return m;
}

TEST(Quality, RegularTet) {
  const TetQuality q = tet_quality(regular_tet());
  EXPECT_NEAR(q.radius_ratio.min, 1.0, 1e-12);
  EXPECT_NEAR(q.min_dihedral_deg.min, kRegularDihedral, 1e-9);
  EXPECT_NEAR(q.max_dihedral_deg.max, kRegularDihedral, 1e-9);
  EXPECT_NEAR(kRegularDihedral, 70.53, 0.01);
  EXPECT_NEAR(q.edge_length_ratio.max, 1.0, 1e-12);
  EXPECT_EQ(q.inverted, 0u);
  EXPECT_EQ(q.slivers, 0u);
}

TEST(Quality, InvertedAndSliverCounted) {
  TetMesh m = regular_tet();
  std::swap(m.tets[0][0], m.tets[0][1]);
  // A sliver: four nearly coplanar points of a square.
  m.vertices.insert(m.vertices.end(), {{0, 0, 0}, {1, 0, 0}, {1, 1, 1e-3}, {0, 1, 0}});
  m.tets.push_back({4, 5, 6, 7});
  if (m.tet_volume(1) < 0) std::swap(m.tets[1][0], m.tets[1][1]);
  const TetQuality q = tet_quality(m);
  EXPECT_EQ(q.inverted, 1u);
  EXPECT_NEAR(q.radius_ratio.min, -1.0, 1e-12);
  EXPECT_EQ(q.slivers, 1u);
  EXPECT_GT(q.max_dihedral_deg.max, 179.0);  // a flat tet has dihedral angles near 180°
  EXPECT_EQ(q.radius_ratio.count, 2u);
}

TEST(Quality, RightTetKnownAngles) {
  // Corner of a cube: three right dihedral angles at the origin edges.
  const TetShape s = tet_shape({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  EXPECT_NEAR(s.max_dihedral_deg, 90.0, 1e-9);
  EXPECT_NEAR(s.min_dihedral_deg, std::acos(1.0 / std::sqrt(3.0)) * 180.0 / std::numbers::pi, 1e-9);
  EXPECT_NEAR(s.edge_length_ratio, std::sqrt(2.0), 1e-12);
  // r_in = 1/(3+√3), r_circ = √3/2.
  EXPECT_NEAR(s.radius_ratio, 3.0 / (3.0 + std::sqrt(3.0)) / (std::sqrt(3.0) / 2.0), 1e-12);
}

TEST(Quality, TriangleMeasures) {
  TriMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0.5, std::sqrt(3.0) / 2.0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}};
  TriQuality q = tri_quality(m);
  EXPECT_NEAR(q.min_angle_deg.min, 60.0, 1e-9);
  EXPECT_NEAR(q.aspect_ratio.max, 1.0, 1e-12);
  EXPECT_NEAR(q.edge_length.mean, 1.0, 1e-12);

  m.triangles = {{0, 1, 3}};  // right isosceles: 45°, longest √2, shortest altitude √2/2
  q = tri_quality(m);
  EXPECT_NEAR(q.min_angle_deg.min, 45.0, 1e-9);
  EXPECT_NEAR(q.aspect_ratio.max, std::sqrt(2.0) / (std::sqrt(2.0) / 2.0) * std::sqrt(3.0) / 2.0, 1e-12);
  EXPECT_NEAR(q.edge_length.max, std::sqrt(2.0), 1e-12);
}

TEST(Quality, StatsMeanAndCount) {
  Stats s;
  for (double x : {1.0, 2.0, 6.0}) s.add(x);
  EXPECT_EQ(s.count, 3u);
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 6.0);
  EXPECT_DOUBLE_EQ(s.mean, 3.0);
}

TEST(Quality, BoxVolumeKuhnTets) {
  const TetQuality q = tet_quality(box_volume(Vec3(1, 1, 1), 2, 2, 2));
  EXPECT_EQ(q.inverted, 0u);
  EXPECT_EQ(q.slivers, 0u);
  EXPECT_NEAR(q.max_dihedral_deg.max, 90.0, 1e-9);  // Kuhn tets: dihedrals are 45°, 60°, 90°
  EXPECT_NEAR(q.min_dihedral_deg.min, 45.0, 1e-9);
}

}  // namespace
}  // namespace tactus::mesh
