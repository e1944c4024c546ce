// The contact load shared among surface vertices (contact/load_spread.hpp).
#include "contact/load_spread.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

namespace tactus::contact {
namespace {

/// A flat n×n-cell square grid in z = 0 of the given cell size, centred on the origin.
struct Grid {
  std::vector<Vec3> positions;
  std::vector<mesh::Triangle> triangles;
  int n = 0;
  [[nodiscard]] int vertex(int i, int j) const { return j * (n + 1) + i; }
};

Grid grid(int n, double cell) {
  Grid g;
  g.n = n;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) g.positions.emplace_back((i - n / 2.0) * cell, (j - n / 2.0) * cell, 0.0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      g.triangles.push_back({g.vertex(i, j), g.vertex(i + 1, j), g.vertex(i + 1, j + 1)});
      g.triangles.push_back({g.vertex(i, j), g.vertex(i + 1, j + 1), g.vertex(i, j + 1)});
    }
  return g;
}

/// The triangle of the grid that holds (x, y) and the barycentric weights of the point.
std::pair<std::int32_t, Vec3> locate(const Grid& g, double x, double y) {
  for (std::size_t t = 0; t < g.triangles.size(); ++t) {
    const Vec3& a = g.positions[static_cast<std::size_t>(g.triangles[t][0])];
    const Vec3& b = g.positions[static_cast<std::size_t>(g.triangles[t][1])];
    const Vec3& c = g.positions[static_cast<std::size_t>(g.triangles[t][2])];
    const double det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    const double u = ((x - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (y - a.y())) / det;
    const double v = ((b.x() - a.x()) * (y - a.y()) - (x - a.x()) * (b.y() - a.y())) / det;
    if (u >= -1e-12 && v >= -1e-12 && u + v <= 1.0 + 1e-12) return {static_cast<std::int32_t>(t), Vec3(1.0 - u - v, u, v)};
  }
  return {-1, Vec3::Zero()};
}

TEST(LoadSpread, SharesSumToOneAndFollowTheHertzProfileOnAFineMesh) {
  // a = 5 mm over 0.25 mm cells: the shares sample p(ρ) = p0·√(1 − ρ²/a²) finely, so their
  // second moment is the profile's, ∫ρ² p dA / ∫p dA = 0.4·a² (a short derivation in
  // docs/contact-mechanics.md); the grid's sampling error is of order (cell/a) = 5%.
  const Grid g = grid(60, 0.25e-3);
  const auto areas = vertex_areas(g.positions, g.triangles);
  const auto [tri, bary] = locate(g, 0.1e-3, -0.05e-3);
  ASSERT_GE(tri, 0);
  std::array<LoadShare, 2000> out{};
  const double a = 5e-3;
  const int count = spread_load(g.positions, g.triangles, areas, tri, bary, a, out);
  ASSERT_GT(count, 100);
  double total = 0.0, second = 0.0;
  Vec3 centroid = Vec3::Zero();
  const Vec3 point(0.1e-3, -0.05e-3, 0.0);
  for (int i = 0; i < count; ++i) {
    const LoadShare& s = out[static_cast<std::size_t>(i)];
    EXPECT_GE(s.share, 0.0);
    const Vec3& x = g.positions[static_cast<std::size_t>(s.vertex)];
    EXPECT_LE((x - point).norm(), a * (1.0 + 1e-9));
    total += s.share;
    centroid += s.share * x;
    second += s.share * (x - point).squaredNorm();
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
  EXPECT_LT((centroid - point).norm(), 0.02 * a);  // the load acts at the contact point
  EXPECT_NEAR(second, 0.4 * a * a, 0.05 * 0.4 * a * a);
}

TEST(LoadSpread, ALoadAtAVertexIsSharedSymmetricallyOnACoarseMesh) {
  // A 1 mm contact on 10 mm cells: the disc widens to the contact triangle's longest edge.
  const Grid g = grid(10, 10e-3);
  const auto areas = vertex_areas(g.positions, g.triangles);
  const auto [tri, bary] = locate(g, 1e-9, 1e-9);
  std::array<LoadShare, 64> out{};
  const int count = spread_load(g.positions, g.triangles, areas, tri, bary, 1e-3, out);
  ASSERT_GE(count, 5);
  auto share_of = [&](int v) {
    for (int i = 0; i < count; ++i)
      if (out[static_cast<std::size_t>(i)].vertex == v) return out[static_cast<std::size_t>(i)].share;
    return 0.0;
  };
  const int c = g.n / 2;
  const double east = share_of(g.vertex(c + 1, c)), west = share_of(g.vertex(c - 1, c));
  const double north = share_of(g.vertex(c, c + 1)), south = share_of(g.vertex(c, c - 1));
  EXPECT_GT(east, 0.0);
  EXPECT_NEAR(east, west, 1e-6);
  EXPECT_NEAR(east, north, 1e-6);
  EXPECT_NEAR(east, south, 1e-6);
  EXPECT_GT(share_of(g.vertex(c, c)), east);  // the vertex under the contact carries most
}

TEST(LoadSpread, SharesChangeContinuouslyAsTheContactPointCrossesAnEdge) {
  const Grid g = grid(10, 10e-3);
  const auto areas = vertex_areas(g.positions, g.triangles);
  // Either side of the diagonal of one cell: the contact triangle changes, the shares hardly.
  const auto [t1, b1] = locate(g, 3e-3 + 1e-7, 3e-3 - 1e-7);
  const auto [t2, b2] = locate(g, 3e-3 - 1e-7, 3e-3 + 1e-7);
  ASSERT_NE(t1, t2);
  std::array<LoadShare, 64> s1{}, s2{};
  const int n1 = spread_load(g.positions, g.triangles, areas, t1, b1, 2e-3, s1);
  const int n2 = spread_load(g.positions, g.triangles, areas, t2, b2, 2e-3, s2);
  std::vector<double> d(g.positions.size(), 0.0);
  for (int i = 0; i < n1; ++i) d[static_cast<std::size_t>(s1[static_cast<std::size_t>(i)].vertex)] += s1[static_cast<std::size_t>(i)].share;
  for (int i = 0; i < n2; ++i) d[static_cast<std::size_t>(s2[static_cast<std::size_t>(i)].vertex)] -= s2[static_cast<std::size_t>(i)].share;
  for (const double x : d) EXPECT_LT(std::abs(x), 1e-4);
}

TEST(LoadSpread, ANegativeRadiusKeepsTheBarycentricWeights) {
  const Grid g = grid(4, 10e-3);
  const auto areas = vertex_areas(g.positions, g.triangles);
  const Vec3 bary(0.2, 0.3, 0.5);
  std::array<LoadShare, 8> out{};
  ASSERT_EQ(spread_load(g.positions, g.triangles, areas, 5, bary, -1.0, out), 3);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(out[static_cast<std::size_t>(k)].vertex, g.triangles[5][static_cast<std::size_t>(k)]);
    EXPECT_DOUBLE_EQ(out[static_cast<std::size_t>(k)].share, bary[k]);
  }
}

TEST(LoadSpread, AFullBufferKeepsTheNearestVerticesAndRenormalises) {
  const Grid g = grid(40, 1e-3);
  const auto areas = vertex_areas(g.positions, g.triangles);
  const auto [tri, bary] = locate(g, 0.3e-3, 0.2e-3);
  std::array<LoadShare, 6> out{};
  const int count = spread_load(g.positions, g.triangles, areas, tri, bary, 10e-3, out);
  ASSERT_EQ(count, 6);
  double total = 0.0;
  const Vec3 point(0.3e-3, 0.2e-3, 0.0);
  for (int i = 0; i < count; ++i) {
    total += out[static_cast<std::size_t>(i)].share;
    EXPECT_LT((g.positions[static_cast<std::size_t>(out[static_cast<std::size_t>(i)].vertex)] - point).norm(), 1.5e-3);
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
  // Bad input: a triangle that does not exist spreads nothing.
  EXPECT_EQ(spread_load(g.positions, g.triangles, areas, -1, bary, 1e-3, out), 0);
  EXPECT_EQ(spread_load(g.positions, g.triangles, areas, static_cast<std::int32_t>(g.triangles.size()), bary, 1e-3, out), 0);
}

}  // namespace
}  // namespace tactus::contact
