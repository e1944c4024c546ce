#include "mesh/generators.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "mesh/half_edge.hpp"
#include "mesh/quality.hpp"
#include "mesh/validate.hpp"

namespace tactus::mesh {
namespace {

/// Closed (no boundary), manifold (the half-edge build accepts it), sphere-like,
/// outward, free of every validation error.
void expect_closed_outward(const TriMesh& m) {
  const auto report = validate(m, {.require_closed = true});
  EXPECT_TRUE(report.problems.empty()) << (report.problems.empty() ? "" : report.problems[0].what);
  const HalfEdgeMesh he(m);
  EXPECT_TRUE(he.closed());
  EXPECT_EQ(he.euler_characteristic(), 2);
  EXPECT_GT(m.signed_volume(), 0.0);
}

TEST(Generators, GridPlate) {
  const QuadMesh q = grid_plate_quads(2.0, 1.0, 4, 2);
  EXPECT_EQ(q.vertices.size(), 15u);
  EXPECT_EQ(q.quads.size(), 8u);
  const TriMesh t = q.triangulated();
  EXPECT_EQ(t.triangles.size(), 16u);
  EXPECT_NEAR(t.area(), 2.0, 1e-12);
  for (std::size_t f = 0; f < t.triangles.size(); ++f) EXPECT_NEAR(t.face_normal(f).z(), 1.0, 1e-12);
  const Aabb b = t.bounds();
  EXPECT_NEAR(b.min.x(), -1.0, 1e-12);
  EXPECT_NEAR(b.max.y(), 0.5, 1e-12);
  EXPECT_TRUE(validate(t).ok());
}

TEST(Generators, BoxSurface) {
  for (int cells : {1, 3}) {
    const TriMesh m = box_surface(Vec3(0.1, 0.2, 0.3), cells);
    expect_closed_outward(m);
    EXPECT_NEAR(m.signed_volume(), 0.1 * 0.2 * 0.3, 1e-15);
    EXPECT_EQ(m.triangles.size(), static_cast<std::size_t>(12 * cells * cells));
    EXPECT_EQ(m.vertices.size(), static_cast<std::size_t>(6 * cells * cells + 2));
  }
}

TEST(Generators, BoxVolume) {
  const Vec3 size(0.4, 0.3, 0.2);
  const TetMesh m = box_volume(size, 4, 3, 2);
  EXPECT_EQ(m.tets.size(), 6u * 24u);
  EXPECT_NEAR(m.volume(), size.prod(), 1e-14);
  for (std::size_t t = 0; t < m.tets.size(); ++t) EXPECT_NEAR(m.tet_volume(t), size.prod() / 144.0, 1e-15);
  EXPECT_TRUE(validate(m).problems.empty());
}

TEST(Generators, SphereVolumeWithinPolygonError) {
  // An inscribed icosphere lies inside the sphere, so it underestimates; at 4 subdivisions
  // (5120 triangles, edge ≈ 0.06 r) the deficit is about 0.5%: allow 1%.
  const double r = 0.05;
  const TriMesh m = sphere(r, 4);
  expect_closed_outward(m);
  EXPECT_EQ(m.triangles.size(), 5120u);
  const double exact = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  EXPECT_LT(m.signed_volume(), exact);
  EXPECT_GT(m.signed_volume(), 0.99 * exact);
  for (const auto& v : m.vertices) EXPECT_NEAR(v.norm(), r, 1e-15);
  EXPECT_NEAR(sphere(1.0, 0).signed_volume(), 2.5362, 1e-4);  // icosahedron inscribed in the unit sphere
}

TEST(Generators, CylinderVolumeIsThePrismVolume) {
  // The inscribed polygon has area (n/2)·r²·sin(2π/n): exact for the mesh, and within
  // 1 - sin(2π/n)/(2π/n) ≈ 0.16% of πr²h at 64 segments.
  const double r = 0.02, h = 0.1;
  const int n = 64;
  const TriMesh m = cylinder(r, h, n, 5);
  expect_closed_outward(m);
  EXPECT_NEAR(m.signed_volume(), 0.5 * n * r * r * std::sin(2.0 * std::numbers::pi / n) * h, 1e-15);
  EXPECT_NEAR(m.signed_volume(), std::numbers::pi * r * r * h, 0.002 * std::numbers::pi * r * r * h);
  EXPECT_NEAR(m.bounds().min.z(), 0.0, 1e-15);
  EXPECT_NEAR(m.bounds().max.z(), h, 1e-15);
}

TEST(Generators, OrganIsClosedLiverSized) {
  const double length = 0.22;
  const int resolution = 30;
  const TriMesh m = organ(length, resolution);
  expect_closed_outward(m);
  const Vec3 extent = m.bounds().size();
  EXPECT_NEAR(extent.x(), length, length / resolution);
  // Liver proportions: about 15 cm wide and 8 cm thick for 22 cm long.
  EXPECT_GT(extent.y(), 0.11);
  EXPECT_LT(extent.y(), 0.17);
  EXPECT_GT(extent.z(), 0.06);
  EXPECT_LT(extent.z(), 0.10);
  EXPECT_NEAR(m.bounds().center().norm(), 0.0, 1e-12);
  // Between half and all of the bounding box: a rounded, blob-like shape (a liver is ~1.5 L).
  const double volume = m.signed_volume();
  EXPECT_GT(volume, 0.3 * extent.prod());
  EXPECT_LT(volume, 0.7 * extent.prod());
  EXPECT_GT(volume, 0.8e-3);
  EXPECT_LT(volume, 2.0e-3);
  const TriQuality q = tri_quality(m);
  EXPECT_GT(q.min_angle_deg.min, 1.0);
}

TEST(Generators, OrganScalesAndStaysClosedAtCoarseResolution) {
  for (int resolution : {8, 12, 50}) {
    const TriMesh m = organ(0.1, resolution);
    expect_closed_outward(m);
    EXPECT_NEAR(m.bounds().size().x(), 0.1, 1e-12);
  }
}

TEST(Generators, RejectBadParameters) {
  EXPECT_THROW(sphere(-1.0, 2), InputError);
  EXPECT_THROW(box_volume(Vec3(1, 0, 1), 1, 1, 1), InputError);
  EXPECT_THROW(cylinder(1.0, 1.0, 2, 1), InputError);
  EXPECT_THROW(organ(0.2, 1), InputError);
}

}  // namespace
}  // namespace tactus::mesh
