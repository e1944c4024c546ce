#include "physics/mapping.hpp"

#include <gtest/gtest.h>

#include <random>

namespace tactus::physics {
namespace {

/// Unit cube split into the six Kuhn tetrahedra around the diagonal 0–7.
mesh::TetMesh kuhn_cube() {
  mesh::TetMesh m;
  for (int v = 0; v < 8; ++v) m.vertices.emplace_back(v & 1, (v >> 1) & 1, (v >> 2) & 1);
  m.tets = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
  return m;
}

VecX flatten(const std::vector<Vec3>& v) {
  VecX x(3 * static_cast<Eigen::Index>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) x.segment<3>(3 * static_cast<Eigen::Index>(i)) = v[i];
  return x;
}

std::vector<Vec3> sample_points() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.02, 0.98);
  std::vector<Vec3> p;
  for (int i = 0; i < 50; ++i) p.emplace_back(u(rng), u(rng), u(rng));
  p.emplace_back(1.05, 0.5, 0.5);  // slightly outside: extrapolated
  return p;
}

TEST(BarycentricMapping, ReproducesPointsAtRestAndLocatesThemInside) {
  const auto cube = kuhn_cube();
  const auto pts = sample_points();
  const BarycentricMapping map(cube, pts);
  std::vector<Vec3> out;
  map.apply(flatten(cube.vertices), out);
  for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_LT((out[i] - pts[i]).norm(), 1e-12) << i;
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    EXPECT_GE(map.weights_of(i).minCoeff(), -1e-12) << i;
    EXPECT_NEAR(map.weights_of(i).sum(), 1.0, 1e-12);
  }
  EXPECT_NEAR(map.max_outside_distance(), 0.05, 1e-9);
}

TEST(BarycentricMapping, FollowsAffineMotionExactly) {
  const auto cube = kuhn_cube();
  const auto pts = sample_points();
  const BarycentricMapping map(cube, pts);
  Mat3 a;
  a << 1.2, 0.1, 0.0, -0.3, 0.9, 0.2, 0.05, 0.0, 1.1;
  const Vec3 b(0.3, -0.2, 0.5);
  std::vector<Vec3> moved;
  for (const auto& v : cube.vertices) moved.push_back(a * v + b);
  std::vector<Vec3> out;
  map.apply(flatten(moved), out);
  for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_LT((out[i] - (a * pts[i] + b)).norm(), 1e-12) << i;
}

TEST(BarycentricMapping, TransposeIsTheAdjointAndConservesForce) {
  const auto cube = kuhn_cube();
  const auto pts = sample_points();
  const BarycentricMapping map(cube, pts);
  std::mt19937 rng(3);
  std::normal_distribution<double> n;
  std::vector<Vec3> f(pts.size());
  Vec3 total = Vec3::Zero();
  for (auto& v : f) {
    v = Vec3(n(rng), n(rng), n(rng));
    total += v;
  }
  VecX u(24);
  for (Eigen::Index i = 0; i < u.size(); ++i) u[i] = n(rng);
  VecX node_f = VecX::Zero(24);
  map.apply_transpose(f, node_f);
  // Virtual work: f · (J u) = (Jᵀ f) · u.
  std::vector<Vec3> mapped_u;
  map.apply(u, mapped_u);
  double lhs = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i) lhs += f[i].dot(mapped_u[i]);
  EXPECT_NEAR(lhs, node_f.dot(u), 1e-10);
  Vec3 node_total = Vec3::Zero();
  for (int i = 0; i < 8; ++i) node_total += node_f.segment<3>(3 * i);
  EXPECT_LT((node_total - total).norm(), 1e-12);
}

TEST(BarycentricMapping, RejectsAnEmptyVolume) {
  EXPECT_THROW(BarycentricMapping(mesh::TetMesh{}, {Vec3::Zero()}), std::invalid_argument);
}

}  // namespace
}  // namespace tactus::physics
