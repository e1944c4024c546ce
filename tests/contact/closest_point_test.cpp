// Closest points on triangles, checked against dense sampling of the triangle (a reference
// that shares no code with the Voronoi-region algorithm).
#include <gtest/gtest.h>

#include <random>

#include "contact/closest_point.hpp"

namespace tactus::contact {
namespace {

/// The closest of ~20,000 barycentric samples: within a few 1e-3 of the edge length.
Vec3 sampled_closest(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  constexpr int n = 200;
  Vec3 best = a;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const double u = static_cast<double>(i) / n, v = static_cast<double>(j) / n;
      const Vec3 q = (1 - u - v) * a + u * b + v * c;
      if ((p - q).squaredNorm() < (p - best).squaredNorm()) best = q;
    }
  return best;
}

TEST(ClosestPoint, MatchesDenseSamplingInEveryRegion) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    const Vec3 p = 2.0 * Vec3(u(rng), u(rng), u(rng));
    const TrianglePoint q = closest_point_on_triangle(p, a, b, c);
    const Vec3 ref = sampled_closest(p, a, b, c);
    // The exact answer is never farther than the best sample, and at most one sample
    // spacing closer.
    EXPECT_LE((p - q.point).norm(), (p - ref).norm() + 1e-12);
    EXPECT_GE((p - q.point).norm(), (p - ref).norm() - 0.02);
    EXPECT_NEAR(q.barycentric.sum(), 1.0, 1e-12);
    EXPECT_GE(q.barycentric.minCoeff(), -1e-12);
    EXPECT_LT((q.barycentric[0] * a + q.barycentric[1] * b + q.barycentric[2] * c - q.point).norm(), 1e-12);
  }
}

TEST(ClosestPoint, DegenerateTriangleGivesAPointOnItsLongestEdge) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(2, 0, 0);  // collinear
  const TrianglePoint q = closest_point_on_triangle(Vec3(1.5, 1, 0), a, b, c);
  EXPECT_NEAR((q.point - Vec3(1.5, 0, 0)).norm(), 0.0, 1e-12);
}

TEST(ClosestPoint, OnASurfaceGivesTheOutwardFaceNormalAndDistance) {
  // Two triangles of the square [0,1]² at z = 0, counter-clockwise seen from +z.
  const std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<mesh::Triangle> t = {{0, 1, 2}, {0, 2, 3}};
  const SurfacePoint s = closest_point_on_surface(Vec3(0.25, 0.75, 0.3), x, t);
  EXPECT_EQ(s.triangle, 1);
  EXPECT_NEAR(s.distance, 0.3, 1e-12);
  EXPECT_NEAR((s.normal - Vec3::UnitZ()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((s.point - Vec3(0.25, 0.75, 0)).norm(), 0.0, 1e-12);
  EXPECT_EQ(closest_point_on_surface(Vec3::Zero(), x, {}).triangle, -1);
}

}  // namespace
}  // namespace tactus::contact
