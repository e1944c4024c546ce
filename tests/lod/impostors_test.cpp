#include "lod/impostors.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "lod/remesh.hpp"
#include "mesh/generators.hpp"
#include "mesh/half_edge.hpp"

namespace tactus::lod {
namespace {

constexpr double kRadius = 0.05;

ImpostorParams quick(int coarse, int fine) {
  ImpostorParams p;
  p.coarse_levels = coarse;
  p.subdivision_levels = fine;
  p.error_samples = 1024;
  p.cost_queries = 64;
  return p;
}

void expect_closed_outward(const mesh::TriMesh& m) {
  const mesh::HalfEdgeMesh half_edges(m);
  EXPECT_TRUE(half_edges.closed());
  EXPECT_EQ(half_edges.euler_characteristic(), 2);
  EXPECT_GT(m.signed_volume(), 0.0);
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    // Outward: no face of a convex shape faces its centre.
    const Vec3 centroid = (m.vertices[m.triangles[t][0]] + m.vertices[m.triangles[t][1]] + m.vertices[m.triangles[t][2]]) / 3.0;
    EXPECT_GT(m.face_normal(t).dot(centroid), 0.0) << "triangle " << t;
  }
}

mesh::TriMesh scaled(mesh::TriMesh m, double s) {
  for (Vec3& p : m.vertices) p *= s;
  return m;
}

TEST(Impostors, DecimationKeepsTheRatioClosednessOrientationAndVolume) {
  const mesh::TriMesh input = mesh::sphere(kRadius, 4);  // 5120 triangles
  const ImpostorHierarchy h = build_impostors(input, quick(2, 0));
  ASSERT_EQ(h.levels.size(), 3U);
  EXPECT_EQ(h.input_level, 2U);
  EXPECT_EQ(h.levels[2].mesh.vertices, input.vertices);
  EXPECT_EQ(h.levels[2].mesh.triangles, input.triangles);
  EXPECT_NEAR(static_cast<double>(h.levels[1].mesh.triangles.size()), 1280.0, 4.0);
  EXPECT_NEAR(static_cast<double>(h.levels[0].mesh.triangles.size()), 320.0, 4.0);
  const double volume = input.signed_volume();
  for (const ImpostorLevel& level : h.levels) {
    expect_closed_outward(level.mesh);
    // Stated tolerance: a quarter of the triangles keeps the volume within 1 %, a
    // sixteenth within 3 % (quadric placement keeps vertices on the tangent planes).
    EXPECT_NEAR(level.mesh.signed_volume() / volume, 1.0, 0.03);
    EXPECT_EQ(level.cost.triangles, level.mesh.triangles.size());
  }
  EXPECT_NEAR(h.levels[1].mesh.signed_volume() / volume, 1.0, 0.01);
}

TEST(Impostors, ErrorsFallTowardTheFinestLevelWhichHasNone) {
  const ImpostorHierarchy h = build_impostors(mesh::sphere(kRadius, 3), quick(2, 1));
  ASSERT_EQ(h.levels.size(), 4U);
  EXPECT_EQ(h.levels.back().error, LevelError{});
  for (std::size_t l = 0; l + 1 < h.levels.size(); ++l) {
    EXPECT_GT(h.levels[l].error.hausdorff, h.levels[l + 1].error.hausdorff) << "level " << l;
    EXPECT_GT(h.levels[l].error.hausdorff, 0.0);
    EXPECT_LT(h.levels[l].error.hausdorff, 0.2 * kRadius);
  }
  for (const ImpostorLevel& level : h.levels) {
    EXPECT_GT(level.cost.query_p50, 0.0);
    EXPECT_GE(level.cost.query_p99, level.cost.query_p50);
    EXPECT_GE(level.cost.build_time, 0.0);
  }
}

TEST(Impostors, LoopSubdivisionConvergesTowardTheSphere) {
  const mesh::TriMesh icosahedron = mesh::sphere(1.0, 0);
  const ImpostorHierarchy h = build_impostors(icosahedron, quick(0, 2));
  ASSERT_EQ(h.levels.size(), 3U);
  // The relative spread of the surface's distances from the centre (at its vertices and
  // sampled points) shrinks about threefold per level: 0.205 (the icosahedron's faces sink
  // to 0.795 r), 0.066, 0.021; and so does the step from one level to the next (Loop
  // converges to a smooth, nearly round limit surface, shrunk to about 0.70 r).
  double previous_spread = 1e9;
  for (const ImpostorLevel& level : h.levels) {
    expect_closed_outward(level.mesh);
    double lo = 1e9, hi = 0.0;
    const auto add = [&](const Vec3& p) {
      lo = std::min(lo, p.norm());
      hi = std::max(hi, p.norm());
    };
    for (const Vec3& p : level.mesh.vertices) add(p);
    for (const SurfaceSample& s : sample_surface(level.mesh, 4096, 3)) add(s.point);
    const double spread = (hi - lo) / hi;
    EXPECT_LT(spread, previous_spread / 2.5);
    previous_spread = spread;
  }
  const auto step = [&](std::size_t a, std::size_t b) {
    return hausdorff_distance(h.levels[a].mesh, h.levels[a].bvh, h.levels[b].mesh, h.levels[b].bvh, 2048, 7);
  };
  EXPECT_LT(step(1, 2), 0.5 * step(0, 1));
  EXPECT_EQ(h.levels[1].mesh.triangles.size(), 80U);
  EXPECT_EQ(h.levels[2].mesh.triangles.size(), 320U);
}

TEST(Impostors, HausdorffOfALevelToItselfIsZeroAndToAScaledCopyTheOffset) {
  const mesh::TriMesh a = mesh::sphere(kRadius, 3);
  const contact::TriangleBvh bvh_a(a.vertices, a.triangles);
  EXPECT_LT(hausdorff_distance(a, bvh_a, a, bvh_a, 4096, 3), 1e-15);
  // Every vertex lies on the sphere, so the radial direction is in the normal cone of the
  // convex polyhedron at a vertex: the scaled copy's vertices are (s − 1) r from the
  // original, and no point of either surface is farther from the other.
  const double s = 1.1;
  const mesh::TriMesh b = scaled(a, s);
  const contact::TriangleBvh bvh_b(b.vertices, b.triangles);
  EXPECT_NEAR(hausdorff_distance(a, bvh_a, b, bvh_b, 4096, 3), (s - 1.0) * kRadius, 1e-12);
  // A box scaled about its centre: the corners move farthest, by (s − 1) × half-diagonal.
  const mesh::TriMesh box = mesh::box_surface(Vec3(0.02, 0.03, 0.04), 3);
  const mesh::TriMesh big = scaled(box, 1.5);
  const contact::TriangleBvh bvh_box(box.vertices, box.triangles), bvh_big(big.vertices, big.triangles);
  EXPECT_NEAR(hausdorff_distance(box, bvh_box, big, bvh_big, 1024, 5), 0.5 * Vec3(0.01, 0.015, 0.02).norm(), 1e-12);
}

TEST(Impostors, CurvatureOfASpheresLevelsIsTheInverseRadius) {
  const ImpostorHierarchy h = build_impostors(mesh::sphere(kRadius, 4), quick(2, 1));
  for (std::size_t l = 0; l < h.levels.size(); ++l) {
    const ImpostorLevel& level = h.levels[l];
    double sum = 0.0, worst = 0.0;
    for (const mesh::VertexCurvature& c : level.curvature) {
      ASSERT_TRUE(c.valid);
      sum += c.kmean;
      worst = std::max(worst, std::abs(c.kmean * kRadius - 1.0));
    }
    const double mean = sum / static_cast<double>(level.curvature.size());
    // Stated tolerance: the mean within 3 % of 1/r, every vertex within 6 %, the RMS
    // against the finest level within 4 % of 1/r.
    EXPECT_NEAR(mean * kRadius, 1.0, 0.03) << "level " << l;
    EXPECT_LT(worst, 0.06) << "level " << l;
    EXPECT_LT(h.levels[l].error.curvature_rms * kRadius, 0.04) << "level " << l;
  }
}

TEST(Impostors, RingsKeepTheNeighbourhoodRadiusAndGrowTowardFinerLevels) {
  const ImpostorHierarchy h = build_impostors(mesh::sphere(kRadius, 4), quick(2, 1));
  EXPECT_EQ(h.levels[h.input_level].rings, mesh::CurvatureEstimator::kDefaultRings);
  for (std::size_t l = 0; l + 1 < h.levels.size(); ++l) {
    EXPECT_LE(h.levels[l].rings, h.levels[l + 1].rings);
    EXPECT_GT(h.levels[l].mean_edge, h.levels[l + 1].mean_edge);
  }
  EXPECT_EQ(h.levels.back().rings, 4);
  EXPECT_EQ(rings_for(1.0, 0.1), mesh::CurvatureEstimator::kMaxRings);
  EXPECT_EQ(rings_for(0.01, 1.0), mesh::CurvatureEstimator::kDefaultRings);
  EXPECT_EQ(h.levels[0].rings, mesh::CurvatureEstimator::kDefaultRings);
  EXPECT_EQ(rings_for(0.3, 0.1), 3);
}

TEST(Impostors, RefusesOpenNonManifoldAndInwardMeshesAndBadParameters) {
  const auto expect_error = [](const mesh::TriMesh& m, const std::string& says) {
    try {
      (void)build_impostors(m, quick(1, 0));
      ADD_FAILURE() << "no error, expected one saying " << says;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  };
  expect_error(mesh::grid_plate(1.0, 1.0, 2, 2), "not closed");
  mesh::TriMesh inward = mesh::sphere(1.0, 1);
  for (mesh::Triangle& t : inward.triangles) std::swap(t[1], t[2]);
  expect_error(inward, "oriented inward");
  mesh::TriMesh fin = mesh::sphere(1.0, 1);  // a fourth triangle on one edge
  fin.vertices.emplace_back(3.0, 0.0, 0.0);
  fin.triangles.push_back({fin.triangles[0][0], fin.triangles[0][1], static_cast<mesh::Index>(fin.vertices.size() - 1)});
  fin.triangles.push_back({fin.triangles[0][1], fin.triangles[0][0], static_cast<mesh::Index>(fin.vertices.size() - 1)});
  expect_error(fin, "manifold");
  mesh::TriMesh loose = mesh::sphere(1.0, 1);
  loose.vertices.emplace_back(5.0, 5.0, 5.0);
  expect_error(loose, "in no triangle");
  expect_error(mesh::TriMesh{}, "no triangles");
  ImpostorParams bad = quick(1, 0);
  bad.subdivision_levels = 3;
  EXPECT_THROW((void)build_impostors(mesh::sphere(1.0, 1), bad), InputError);
  bad = quick(1, 0);
  bad.reduction = 1.0;
  EXPECT_THROW((void)build_impostors(mesh::sphere(1.0, 1), bad), InputError);
}

TEST(Impostors, TheHashFollowsEveryByte) {
  const mesh::TriMesh a = mesh::sphere(1.0, 2);
  mesh::TriMesh b = a;
  EXPECT_EQ(a.content_hash(), b.content_hash());
  b.vertices[7].x() = std::nextafter(b.vertices[7].x(), 2.0);
  EXPECT_NE(a.content_hash(), b.content_hash());
  b = a;
  std::swap(b.triangles[3][0], b.triangles[3][1]);
  EXPECT_NE(a.content_hash(), b.content_hash());
}

TEST(Impostors, BuildingTwiceGivesTheSameLevelsAndErrors) {
  const ImpostorHierarchy a = build_impostors(mesh::organ(0.1, 24), quick(2, 1));
  const ImpostorHierarchy b = build_impostors(mesh::organ(0.1, 24), quick(2, 1));
  ASSERT_EQ(a.levels.size(), b.levels.size());
  for (std::size_t l = 0; l < a.levels.size(); ++l) {
    EXPECT_EQ(a.levels[l].mesh.vertices, b.levels[l].mesh.vertices);
    EXPECT_EQ(a.levels[l].mesh.triangles, b.levels[l].mesh.triangles);
    EXPECT_EQ(a.levels[l].error, b.levels[l].error);
    expect_closed_outward(a.levels[l].mesh);
  }
}

}  // namespace
}  // namespace tactus::lod
