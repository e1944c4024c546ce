#include "mesh/self_intersection.hpp"

#include <gtest/gtest.h>

#include <chrono>

#include "mesh/generators.hpp"
#include "mesh/validate.hpp"

namespace tactus::mesh {
namespace {

SelfIntersections find(const TriMesh& m) { return find_self_intersections(m, {}, 0.0, 10); }

TriMesh merged(const TriMesh& a, const TriMesh& b) {
  TriMesh m = a;
  const auto offset = static_cast<Index>(a.vertices.size());
  m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (auto t : b.triangles) m.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  return m;
}

TriMesh shifted(TriMesh m, const Vec3& by) {
  for (auto& v : m.vertices) v += by;
  return m;
}

TEST(SelfIntersection, CleanClosedSurfacesHaveNone) {
  EXPECT_EQ(find(sphere(1.0, 4)).count, 0u);
  EXPECT_EQ(find(organ(0.22, 12)).count, 0u);
  EXPECT_EQ(find(box_surface(Vec3(1, 2, 3), 5)).count, 0u);
  EXPECT_EQ(find(cylinder(0.1, 0.4, 24, 8)).count, 0u);
  EXPECT_EQ(find(grid_plate(1.0, 1.0, 10, 10)).count, 0u);  // flat, coplanar neighbours
}

TEST(SelfIntersection, OverlappingSpheresCross) {
  const TriMesh m = merged(sphere(1.0, 2), shifted(sphere(1.0, 2), Vec3(1.0, 0.1, 0.05)));
  const auto r = find(m);
  EXPECT_GT(r.count, 10u);
  ASSERT_EQ(r.first.size(), 10u);
  const std::size_t half = sphere(1.0, 2).triangles.size();
  for (const auto& [a, b] : r.first) {
    EXPECT_LT(a, b);
    EXPECT_LT(a, half);  // one from each sphere
    EXPECT_GE(b, half);
  }
  // Apart, they do not meet.
  EXPECT_EQ(find(merged(sphere(1.0, 2), shifted(sphere(1.0, 2), Vec3(2.5, 0, 0)))).count, 0u);
}

TEST(SelfIntersection, AVertexPushedThroughTheOppositeSide) {
  TriMesh m = sphere(1.0, 2);
  std::size_t top = 0;
  for (std::size_t v = 0; v < m.vertices.size(); ++v)
    if (m.vertices[v].z() > m.vertices[top].z()) top = v;
  m.vertices[top].z() = -1.5;  // its fan now pierces the bottom
  EXPECT_GT(find(m).count, 0u);
}

TEST(SelfIntersection, SharedEdgeCountsOnlyWhenFoldedFlat) {
  TriMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 0.5, 0}, {0.3, 0.3, 1}, {0.3, -1, 0}};
  m.triangles = {{0, 1, 2}, {1, 0, 3}};  // 3 lies in 0 1 2's plane on 2's side: folded onto it
  EXPECT_EQ(find(m).count, 1u);
  m.triangles = {{0, 1, 2}, {1, 0, 4}};  // a real dihedral angle
  EXPECT_EQ(find(m).count, 0u);
  m.triangles = {{0, 1, 2}, {1, 0, 5}};  // flat, on the other side: an ordinary flat pair
  EXPECT_EQ(find(m).count, 0u);
}

TEST(SelfIntersection, SharedVertexCountsOnlyBeyondIt) {
  TriMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, -0.5}, {1, 1, 0.5}, {-1, 0, 0.1}, {-1, -1, 0.2}};
  m.triangles = {{0, 1, 2}, {0, 3, 4}};  // the second passes through the first's interior
  EXPECT_EQ(find(m).count, 1u);
  m.triangles = {{0, 1, 2}, {0, 5, 6}};  // only the corner in common
  EXPECT_EQ(find(m).count, 0u);
}

TEST(SelfIntersection, TouchingAndCoplanarOverlap) {
  TriMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, 0}, {0.2, 0.2, 1}, {0.5, 0.2, 1},
                {0.1, 0.1, 0}, {0.3, 0.1, 0}, {0.1, 0.3, 0}};
  m.triangles = {{0, 1, 2}, {3, 4, 5}};  // a corner resting on the face
  EXPECT_EQ(find(m).count, 1u);
  m.triangles = {{0, 1, 2}, {6, 7, 8}};  // a small triangle inside, in the same plane
  EXPECT_EQ(find(m).count, 1u);
}

TEST(SelfIntersection, AnUnweldedSurfaceIsNotSelfIntersecting) {
  const TriMesh s = sphere(1.0, 2);
  TriMesh soup;
  for (const auto& t : s.triangles) {
    const auto base = static_cast<Index>(soup.vertices.size());
    for (const Index v : t) soup.vertices.push_back(s.vertices[v]);
    soup.triangles.push_back({base, base + 1, base + 2});
  }
  EXPECT_EQ(find(soup).count, 0u);
  const auto r = validate(soup);
  EXPECT_EQ(r.count(Severity::warning), 1u + (soup.vertices.size() - s.vertices.size()));  // open + duplicates
}

TEST(SelfIntersection, HundredThousandTrianglesInWellUnderASecond) {
  const TriMesh m = sphere(1.0, 6);  // 81920 triangles
  const TriMesh two = merged(m, shifted(sphere(0.5, 4), Vec3(0.9, 0, 0)));
  ASSERT_GT(two.triangles.size(), 80000u);
  const auto start = std::chrono::steady_clock::now();
  const auto r = find(two);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GT(r.count, 0u);
  std::printf("self-intersection check, %zu triangles: %.3f s\n", two.triangles.size(), seconds);
#ifdef NDEBUG
  EXPECT_LT(seconds, 1.0);
#endif
}

TEST(DuplicateVertices, WithinTheToleranceOnly) {
  std::vector<Vec3> v = {{0, 0, 0}, {1, 0, 0}, {1e-12, 0, 0}, {1, 1e-6, 0}, {1, 0, 1e-13}, {0, 0, 0}};
  const auto d = find_duplicate_vertices(v, 1e-9);
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[0], std::make_pair(std::size_t{2}, std::size_t{0}));
  EXPECT_EQ(d[1], std::make_pair(std::size_t{4}, std::size_t{1}));
  EXPECT_EQ(d[2], std::make_pair(std::size_t{5}, std::size_t{0}));
}

TEST(DuplicateVertices, ReportedByValidateWithTheTolerance) {
  TriMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1e-12, 0, 0}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const auto r = validate(m);
  bool found = false;
  for (const auto& p : r.problems)
    found |= p.what.find("vertex 4: coincides with vertex 0 (within 1.73e-09 m, 1e-09 of the bounding-box diagonal)") !=
             std::string::npos;
  EXPECT_TRUE(found);
}

}  // namespace
}  // namespace tactus::mesh
