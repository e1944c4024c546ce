#include "mesh/curvature.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/counting_allocator.hpp"
#include "core/error.hpp"
#include "mesh/generators.hpp"

namespace tactus::mesh {
namespace {

TriMesh flipped(TriMesh m) {
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

/// Cylinder whose rings are as far apart as its segments, so triangles are near-isosceles.
TriMesh even_cylinder(double radius, int segments, int rings) {
  const double spacing = 2.0 * std::numbers::pi * radius / segments;
  return cylinder(radius, spacing * rings, segments, rings);
}

// Density: icospheres from 2 subdivisions (162 vertices, edges about 0.3 r) upward. The
// icosphere's uneven triangles keep the error near 1% however fine the mesh gets.
TEST(Curvature, SphereMeanCurvatureMatchesInverseRadius) {
#ifdef TACTUS_SANITIZED
  const int finest = 3;  // the 2562-vertex sphere takes tens of seconds under sanitizers
#else
  const int finest = 4;
#endif
  for (double radius : {0.005, 0.05, 2.0}) {
    for (int subdivisions = 2; subdivisions <= finest; ++subdivisions) {
      const TriMesh m = sphere(radius, subdivisions);
      const CurvatureEstimator estimator{HalfEdgeMesh(m)};
      for (Index v = 0; v < static_cast<Index>(m.vertices.size()); ++v) {
        const VertexCurvature c = estimator.estimate(m.vertices, v);
        SCOPED_TRACE(::testing::Message() << "r " << radius << " subdivisions " << subdivisions << " vertex " << v);
        ASSERT_TRUE(c.valid);
        EXPECT_NEAR(c.kmean * radius, 1.0, 0.05);
        EXPECT_NEAR(c.k1 * radius, c.k2 * radius, 0.05);
        EXPECT_GE(c.k1, c.k2);
        EXPECT_DOUBLE_EQ(c.kmean, 0.5 * (c.k1 + c.k2));
        EXPECT_GT(c.normal.dot(m.vertices[v].normalized()), 0.9999);
        EXPECT_NEAR(c.direction1.norm(), 1.0, 1e-12);
        EXPECT_NEAR(c.direction1.dot(c.normal), 0.0, 1e-12);
        EXPECT_NEAR(c.direction2.dot(c.direction1), 0.0, 1e-12);
      }
    }
  }
}

TEST(Curvature, TaubinFitGivesTheSameMeanOnASphere) {
  const double radius = 0.03;
  const TriMesh m = sphere(radius, 3);
  const HalfEdgeMesh he(m);
  const CurvatureEstimator taubin(he, 2, CurvatureFit::taubin);
  const CurvatureEstimator least_squares(he, 2, CurvatureFit::least_squares);
  for (Index v = 0; v < static_cast<Index>(m.vertices.size()); ++v) {
    const VertexCurvature t = taubin.estimate(m.vertices, v);
    ASSERT_TRUE(t.valid);
    EXPECT_NEAR(t.kmean * radius, 1.0, 0.05);
    EXPECT_NEAR(t.kmean, least_squares.estimate(m.vertices, v).kmean, 0.005 / radius);
  }
}

TEST(Curvature, MoreRingsStillFindTheSphere) {
  const double radius = 0.1;
  const TriMesh m = sphere(radius, 4);
  const HalfEdgeMesh he(m);
  for (int rings = 1; rings <= 4; ++rings) {
    const CurvatureEstimator estimator(he, rings);
    for (Index v = 0; v < static_cast<Index>(m.vertices.size()); v += 7)
      EXPECT_NEAR(estimator.estimate(m.vertices, v).kmean * radius, 1.0, 0.05) << "rings " << rings;
  }
}

// Density: 32 segments round, rings as far apart as segments.
TEST(Curvature, CylinderAwayFromCaps) {
  const double radius = 0.02;
  const int segments = 32, rings = 12;
  const TriMesh m = even_cylinder(radius, segments, rings);
  const CurvatureEstimator estimator{HalfEdgeMesh(m)};
  // Rows within two rings of a cap see the cap's centre vertex; skip them.
  for (int ring = 3; ring <= rings - 3; ++ring)
    for (int s = 0; s < segments; ++s) {
      const Index v = ring * segments + s;
      const VertexCurvature c = estimator.estimate(m.vertices, v);
      SCOPED_TRACE(::testing::Message() << "ring " << ring << " segment " << s);
      ASSERT_TRUE(c.valid);
      EXPECT_NEAR(c.kmean * 2.0 * radius, 1.0, 0.05);
      EXPECT_NEAR(c.k1 * radius, 1.0, 0.05);
      EXPECT_NEAR(c.k2 * radius, 0.0, 0.05);
      const Vec3 radial = Vec3(m.vertices[v].x(), m.vertices[v].y(), 0.0).normalized();
      EXPECT_GT(c.normal.dot(radial), 0.9999);
      EXPECT_GT(std::abs(c.direction2.z()), 0.99);  // straight along the axis
      EXPECT_LT(std::abs(c.direction1.z()), 0.15);  // around it
    }
}

TEST(Curvature, TiltedPlaneIsFlatEverywhereIncludingItsBorder) {
  const double size = 0.1;
  TriMesh m = grid_plate(size, size, 10, 10);
  const Mat3 rotation = (Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized())).toRotationMatrix();
  for (auto& v : m.vertices) v = rotation * v + Vec3(0.3, -0.2, 0.1);
  const Vec3 expected_normal = rotation * Vec3::UnitZ();
  const CurvatureEstimator estimator{HalfEdgeMesh(m)};
  for (Index v = 0; v < static_cast<Index>(m.vertices.size()); ++v) {
    const VertexCurvature c = estimator.estimate(m.vertices, v);
    ASSERT_TRUE(c.valid) << v;
    EXPECT_LT(std::abs(c.kmean) * size, 1e-9) << v;
    EXPECT_LT(std::abs(c.k1) * size, 1e-9) << v;
    EXPECT_LT(std::abs(c.k2) * size, 1e-9) << v;
    EXPECT_GT(c.normal.dot(expected_normal), 1.0 - 1e-12) << v;
  }
}

TEST(Curvature, InsideOfASphereIsConcave) {
  const double radius = 0.04;
  const TriMesh m = flipped(sphere(radius, 3));
  const CurvatureEstimator estimator{HalfEdgeMesh(m)};
  for (Index v = 0; v < static_cast<Index>(m.vertices.size()); ++v) {
    const VertexCurvature c = estimator.estimate(m.vertices, v);
    ASSERT_TRUE(c.valid);
    EXPECT_NEAR(c.kmean * radius, -1.0, 0.05) << v;
    EXPECT_LT(c.k1, 0.0) << v;
    EXPECT_LT(c.normal.dot(m.vertices[v]), 0.0) << v;  // faces the centre
  }
}

TEST(Curvature, InsideOfACylinderIsConcave) {
  const double radius = 0.02;
  const int segments = 32, rings = 12;
  const TriMesh m = flipped(even_cylinder(radius, segments, rings));
  const CurvatureEstimator estimator{HalfEdgeMesh(m)};
  for (int s = 0; s < segments; ++s) {
    const VertexCurvature c = estimator.estimate(m.vertices, 6 * segments + s);
    EXPECT_NEAR(c.kmean * 2.0 * radius, -1.0, 0.05);
    EXPECT_NEAR(c.k2 * radius, -1.0, 0.05);  // the smaller one is now round the axis
    EXPECT_NEAR(c.k1 * radius, 0.0, 0.05);
  }
}

/// Mean curvature of the graph z = f(x, y) for the upward normal, convex (bending away
/// from the normal) positive: −div(∇f / √(1 + |∇f|²)) / 2.
double graph_mean_curvature(double fx, double fy, double fxx, double fxy, double fyy) {
  const double w2 = 1.0 + fx * fx + fy * fy;
  return -((1.0 + fy * fy) * fxx - 2.0 * fx * fy * fxy + (1.0 + fx * fx) * fyy) / (2.0 * std::pow(w2, 1.5));
}

TEST(Curvature, FollowsTheSurfaceAsItDeforms) {
  const double size = 0.1;
  const int cells = 40;
  const TriMesh m = grid_plate(size, size, cells, cells);
  const CurvatureEstimator estimator{HalfEdgeMesh(m)};  // topology only: built once
  std::vector<Vec3> positions = m.vertices;
  const auto id = [&](int i, int j) { return static_cast<Index>(j * (cells + 1) + i); };
  const Index centre = id(cells / 2, cells / 2);
  EXPECT_NEAR(estimator.estimate(positions, centre).kmean, 0.0, 1e-9);

  // Press a dome into the plate: z = −c(x² + y²) has mean curvature 2c at its apex.
  const double c = 8.0;  // 1/m: apex radius 1/(2c) = 62.5 mm
  for (auto& p : positions) p.z() = -c * (p.x() * p.x() + p.y() * p.y());
  for (int j = cells / 2 - 8; j <= cells / 2 + 8; j += 4)
    for (int i = cells / 2 - 8; i <= cells / 2 + 8; i += 4) {
      const Vec3& p = positions[id(i, j)];
      const double expected = graph_mean_curvature(-2 * c * p.x(), -2 * c * p.y(), -2 * c, 0.0, -2 * c);
      const VertexCurvature k = estimator.estimate(positions, id(i, j));
      EXPECT_NEAR(k.kmean / expected, 1.0, 0.05) << i << " " << j;
    }
  EXPECT_NEAR(estimator.estimate(positions, centre).kmean / (2 * c), 1.0, 0.02);

  // Then a trough along x: z = −c·y² bends only across y.
  for (auto& p : positions) p.z() = -c * p.y() * p.y();
  const VertexCurvature trough = estimator.estimate(positions, centre);
  EXPECT_NEAR(trough.k1 / (2 * c), 1.0, 0.03);
  EXPECT_NEAR(trough.k2 / (2 * c), 0.0, 0.03);
  EXPECT_GT(std::abs(trough.direction1.y()), 0.99);

  // A sphere grown to twice its size halves its curvature.
  const TriMesh ball = sphere(0.02, 3);
  const CurvatureEstimator on_ball{HalfEdgeMesh(ball)};
  std::vector<Vec3> grown = ball.vertices;
  for (auto& p : grown) p *= 2.0;
  for (Index v = 0; v < static_cast<Index>(grown.size()); v += 13)
    EXPECT_NEAR(on_ball.estimate(grown, v).kmean, 0.5 * on_ball.estimate(ball.vertices, v).kmean, 1e-9);
}

TEST(Curvature, EstimatesAllocateNothing) {
  const TriMesh m = sphere(0.05, 3);
  const CurvatureEstimator estimator{HalfEdgeMesh(m)};
  std::vector<Vec3> positions = m.vertices;
  double sum = 0.0;
  const tactus::testing::AllocationCounter counter;
  for (int step = 0; step < 20; ++step) {
    positions[step].x() += 1e-4;  // the surface deforms between calls
    sum += estimator.estimate(positions, step).kmean;
    sum += estimator.estimate_at_point(positions, step, Vec3(0.2, 0.3, 0.5)).kmean;
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(sum, 0.0);
}

TEST(Curvature, PointEstimateBlendsItsTriangle) {
  const double radius = 0.05;
  const TriMesh m = sphere(radius, 3);
  const CurvatureEstimator estimator{HalfEdgeMesh(m)};
  for (Index f = 0; f < static_cast<Index>(m.triangles.size()); f += 11) {
    const Triangle& t = m.triangles[f];
    const VertexCurvature at_a = estimator.estimate_at_point(m.vertices, f, Vec3(1, 0, 0));
    const VertexCurvature a = estimator.estimate(m.vertices, t[0]);
    EXPECT_NEAR(at_a.kmean, a.kmean, 1e-12 / radius);
    EXPECT_NEAR(at_a.k1, a.k1, 1e-9 / radius);
    EXPECT_NEAR(at_a.k2, a.k2, 1e-9 / radius);
    EXPECT_GT(at_a.normal.dot(a.normal), 1.0 - 1e-12);

    const VertexCurvature mid = estimator.estimate_at_point(m.vertices, f, Vec3(1, 1, 1) / 3.0);
    double mean_of_three = 0.0;
    for (Index v : t) mean_of_three += estimator.estimate(m.vertices, v).kmean / 3.0;
    EXPECT_NEAR(mid.kmean, mean_of_three, 1e-12 / radius);
    EXPECT_NEAR(mid.kmean * radius, 1.0, 0.05);
    EXPECT_DOUBLE_EQ(mid.kmean, 0.5 * (mid.k1 + mid.k2));
    const Vec3 centroid = (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3.0;
    EXPECT_GT(mid.normal.dot(centroid.normalized()), 0.999);
  }
  // Slightly negative weights from a closest-point query are clamped, not rejected.
  const VertexCurvature clamped = estimator.estimate_at_point(m.vertices, 0, Vec3(1.0 + 1e-12, -1e-12, 0));
  EXPECT_TRUE(clamped.valid);
}

TEST(Curvature, NeighbourhoodsMatchTheHalfEdgeRings) {
  const TriMesh m = sphere(1.0, 2);
  const HalfEdgeMesh he(m);
  const CurvatureEstimator one(he, 1), three(he, 3);
  for (Index v = 0; v < static_cast<Index>(m.vertices.size()); ++v) {
    for (const auto* estimator : {&one, &three}) {
      auto ours = std::vector<Index>(estimator->neighbourhood(v).begin(), estimator->neighbourhood(v).end());
      auto theirs = he.k_ring(v, estimator->rings());
      std::sort(ours.begin(), ours.end());
      std::sort(theirs.begin(), theirs.end());
      EXPECT_EQ(ours, theirs);
    }
    auto faces = std::vector<Index>(one.neighbourhood_faces(v).begin(), one.neighbourhood_faces(v).end());
    auto fan = he.vertex_faces(v);
    std::sort(faces.begin(), faces.end());
    std::sort(fan.begin(), fan.end());
    EXPECT_EQ(faces, fan);
  }
  // Two rings of a valence-6 vertex hold 18 vertices and the 24 faces among them.
  const TriMesh plate = grid_plate(1.0, 1.0, 8, 8);
  const CurvatureEstimator on_plate(HalfEdgeMesh(plate), 2);
  const Index centre = 4 * 9 + 4;
  EXPECT_EQ(on_plate.neighbourhood(centre).size(), 18u);
  EXPECT_EQ(on_plate.neighbourhood_faces(centre).size(), 24u);
}

TEST(Curvature, RejectsBadInput) {
  const TriMesh m = sphere(1.0, 1);
  const HalfEdgeMesh he(m);
  EXPECT_THROW(CurvatureEstimator(he, 0), InputError);
  EXPECT_THROW(CurvatureEstimator(he, CurvatureEstimator::kMaxRings + 1), InputError);
  const CurvatureEstimator estimator(he);
  std::vector<Vec3> short_positions(m.vertices.begin(), m.vertices.end() - 1);
  EXPECT_THROW((void)estimator.estimate(short_positions, 0), InputError);
  EXPECT_THROW((void)estimator.estimate(m.vertices, -1), InputError);
  EXPECT_THROW((void)estimator.estimate(m.vertices, static_cast<Index>(m.vertices.size())), InputError);
  EXPECT_THROW((void)estimator.estimate_at_point(m.vertices, static_cast<Index>(m.triangles.size()), Vec3(1, 0, 0)),
               InputError);
  EXPECT_THROW((void)estimator.estimate_at_point(m.vertices, 0, Vec3(-1, -1, -1)), InputError);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW((void)estimator.estimate_at_point(m.vertices, 0, Vec3(nan, 1, 0)), InputError);
  try {
    (void)estimator.estimate(short_positions, 0);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("positions"), std::string::npos) << e.what();
  }
}

TEST(Curvature, DegenerateGeometryGivesNoAnswerRatherThanNaN) {
  TriMesh m = sphere(0.01, 2);
  m.vertices.push_back(Vec3(5, 5, 5));  // isolated vertex
  const auto isolated = static_cast<Index>(m.vertices.size() - 1);
  const CurvatureEstimator estimator{HalfEdgeMesh(m)};
  const VertexCurvature lone = estimator.estimate(m.vertices, isolated);
  EXPECT_FALSE(lone.valid);
  EXPECT_EQ(lone.kmean, 0.0);

  std::vector<Vec3> broken = m.vertices;
  broken[3] = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  const VertexCurvature c = estimator.estimate(broken, 3);
  EXPECT_FALSE(c.valid);
  EXPECT_TRUE(std::isfinite(c.kmean));
  EXPECT_TRUE(c.normal.allFinite());

  std::vector<Vec3> collapsed(m.vertices.size(), Vec3(1, 2, 3));  // everything at one point
  EXPECT_FALSE(estimator.estimate(collapsed, 0).valid);
  EXPECT_FALSE(estimator.estimate_at_point(collapsed, 0, Vec3(1, 1, 1)).valid);
}

}  // namespace
}  // namespace tactus::mesh
