#include "mesh/validate.hpp"

#include <gtest/gtest.h>

#include <limits>

#include <fmt/format.h>

#include "mesh/generators.hpp"
#include "small_meshes.hpp"

namespace tactus::mesh {
namespace {

using test::tetrahedron_surface;

TetMesh two_tets() {
  TetMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}};
  m.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}};
  return m;
}

/// The single problem of the given severity whose text contains `needle`.
::testing::AssertionResult has(const ValidationReport& r, Severity s, const std::string& needle) {
  for (const auto& p : r.problems)
    if (p.severity == s && p.what.find(needle) != std::string::npos) return ::testing::AssertionSuccess();
  std::string all;
  for (const auto& p : r.problems) all += "\n  " + p.what;
  return ::testing::AssertionFailure() << "no problem containing '" << needle << "' in:" << all;
}

TEST(ValidateSurface, CleanMeshesPass) {
  EXPECT_TRUE(validate(tetrahedron_surface(), {.require_closed = true}).problems.empty());
  EXPECT_TRUE(validate(sphere(1.0, 3), {.require_closed = true}).problems.empty());
}

TEST(ValidateSurface, NonFiniteCoordinate) {
  TriMesh m = tetrahedron_surface();
  m.vertices[2].y() = std::numeric_limits<double>::quiet_NaN();
  m.vertices[3].z() = std::numeric_limits<double>::infinity();
  const auto r = validate(m);
  EXPECT_FALSE(r.ok());
  EXPECT_TRUE(has(r, Severity::error, "vertex 2: coordinate is not finite (0 nan 0)"));
  EXPECT_TRUE(has(r, Severity::error, "vertex 3: coordinate is not finite (0 0 inf)"));
}

TEST(ValidateSurface, IndexOutOfRange) {
  TriMesh m = tetrahedron_surface();
  m.triangles[1] = {0, -1, 7};
  const auto r = validate(m);
  EXPECT_TRUE(has(r, Severity::error, "triangle 1 (vertices 0 -1 7): vertex index -1 out of range (mesh has 4 vertices)"));
}

TEST(ValidateSurface, RepeatedIndex) {
  TriMesh m = tetrahedron_surface();
  m.triangles[3] = {1, 2, 1};
  EXPECT_TRUE(has(validate(m), Severity::error, "triangle 3 (vertices 1 2 1): vertex 1 repeated"));
}

TEST(ValidateSurface, DegenerateTriangle) {
  TriMesh m = tetrahedron_surface();
  m.vertices.push_back({0.5, 0.5, 0.0});  // on the segment from 1 to 2
  m.triangles.push_back({1, 2, 4});
  EXPECT_TRUE(has(validate(m), Severity::error, "triangle 4 (vertices 1 2 4): degenerate, area"));
}

TEST(ValidateSurface, NonManifoldEdge) {
  TriMesh m = tetrahedron_surface();
  m.vertices.push_back({1, 1, 1});
  m.triangles.push_back({0, 1, 4});
  EXPECT_TRUE(has(validate(m), Severity::error, "edge (0, 1): non-manifold, shared by 3 triangles (triangle 0, triangle 1, triangle 4)"));
}

TEST(ValidateSurface, InconsistentOrientation) {
  TriMesh m = tetrahedron_surface();
  m.triangles[3] = {1, 3, 2};
  const auto r = validate(m);
  EXPECT_TRUE(has(r, Severity::error, "edge (1, 2): inconsistent orientation, triangle 0 and triangle 3 both traverse it"));
}

TEST(ValidateSurface, OpenBoundary) {
  TriMesh m = tetrahedron_surface();
  m.triangles.pop_back();
  const auto warn = validate(m);
  EXPECT_TRUE(warn.ok());
  EXPECT_TRUE(has(warn, Severity::warning, "surface is open: 3 boundary edges"));
  const auto err = validate(m, {.require_closed = true});
  EXPECT_FALSE(err.ok());
  EXPECT_EQ(err.count(Severity::error), 3u);
  EXPECT_TRUE(has(err, Severity::error, "edge (1, 2): open boundary, used only by triangle 0"));
}

TEST(ValidateSurface, DuplicateTriangle) {
  TriMesh m = tetrahedron_surface();
  m.triangles.push_back({2, 1, 0});
  EXPECT_TRUE(has(validate(m), Severity::error, "triangle 4 (vertices 2 1 0): duplicate of triangle 0"));
}

TEST(ValidateSurface, UnusedVertex) {
  TriMesh m = tetrahedron_surface();
  m.vertices.push_back({5, 5, 5});
  const auto r = validate(m, {.require_closed = true});
  EXPECT_TRUE(r.ok());
  EXPECT_TRUE(has(r, Severity::warning, "vertex 4: unused"));
}

TEST(ValidateSurface, MessagesAreCappedButCountsExact) {
  TriMesh m = grid_plate(1.0, 1.0, 10, 10);
  const std::size_t bad = m.triangles.size();
  for (auto& t : m.triangles) t[0] = 100000;  // every triangle out of range
  const auto r = validate(m);
  EXPECT_EQ(r.count(Severity::error), bad);
  std::size_t lines = 0;
  for (const auto& p : r.problems) lines += p.severity == Severity::error;
  EXPECT_EQ(lines, kMaxMessagesPerKind + 1);
  EXPECT_TRUE(has(r, Severity::error, fmt::format("... and {} more: vertex indices out of range", bad - kMaxMessagesPerKind)));
  // The vertices those triangles no longer reach are unused, not an index problem.
  EXPECT_EQ(r.count(Severity::warning), m.vertices.size());
}

TEST(ValidateTets, CleanMeshPasses) {
  EXPECT_TRUE(validate(two_tets()).problems.empty());
  EXPECT_TRUE(validate(box_volume(Vec3(1, 2, 3), 3, 3, 3)).problems.empty());
}

TEST(ValidateTets, NonFiniteCoordinate) {
  TetMesh m = two_tets();
  m.vertices[4].x() = -std::numeric_limits<double>::infinity();
  EXPECT_TRUE(has(validate(m), Severity::error, "vertex 4: coordinate is not finite (-inf 0 -1)"));
}

TEST(ValidateTets, IndexOutOfRangeAndRepeated) {
  TetMesh m = two_tets();
  m.tets.push_back({0, 1, 2, 5});
  m.tets.push_back({0, 1, 1, 3});
  const auto r = validate(m);
  EXPECT_TRUE(has(r, Severity::error, "tetrahedron 2 (vertices 0 1 2 5): vertex index 5 out of range (mesh has 5 vertices)"));
  EXPECT_TRUE(has(r, Severity::error, "tetrahedron 3 (vertices 0 1 1 3): vertex 1 repeated"));
}

TEST(ValidateTets, Inverted) {
  TetMesh m = two_tets();
  std::swap(m.tets[1][0], m.tets[1][1]);
  const auto r = validate(m);
  EXPECT_EQ(r.count(Severity::error), 1u);
  EXPECT_TRUE(has(r, Severity::error, "tetrahedron 1 (vertices 2 0 1 4): inverted, volume -0.167 m³"));
}

TEST(ValidateTets, ZeroVolume) {
  TetMesh m = two_tets();
  m.vertices.push_back({0.5, 0.5, 0.0});
  m.tets.push_back({0, 1, 2, 5});  // flat: vertex 5 lies in the plane of 0 1 2
  EXPECT_TRUE(has(validate(m), Severity::error, "tetrahedron 2 (vertices 0 1 2 5): zero volume"));
}

TEST(ValidateTets, Duplicate) {
  TetMesh m = two_tets();
  m.tets.push_back({1, 2, 0, 3});  // the same tet, rotated (still positive)
  EXPECT_TRUE(has(validate(m), Severity::error, "tetrahedron 2 (vertices 1 2 0 3): duplicate of tetrahedron 0"));
}

TEST(ValidateTets, NonManifoldFace) {
  TetMesh m = two_tets();
  m.vertices.push_back({0.2, 0.2, 2.0});
  m.tets.push_back({0, 1, 2, 5});
  EXPECT_TRUE(has(validate(m), Severity::error, "face (0 1 2): non-manifold, shared by 3 tetrahedra (tetrahedron 0, tetrahedron 1, tetrahedron 2)"));
}

TEST(ValidateTets, UnusedVertexAndLabels) {
  TetMesh m = two_tets();
  m.vertices.push_back({3, 3, 3});
  m.tet_regions = {1};
  m.faces = {{0, 1, 9}};
  const auto r = validate(m);
  EXPECT_TRUE(has(r, Severity::warning, "vertex 5: unused"));
  EXPECT_TRUE(has(r, Severity::error, "tet_regions has 1 entries for 2 tetrahedra"));
  EXPECT_TRUE(has(r, Severity::error, "face 0 (vertices 0 1 9): vertex index 9 out of range"));
}

TEST(ValidateTets, CappedInvertedCount) {
  TetMesh m = box_volume(Vec3(1, 1, 1), 4, 4, 4);
  for (auto& t : m.tets) std::swap(t[0], t[1]);
  const auto r = validate(m);
  EXPECT_EQ(r.count(Severity::error), m.tets.size());
  EXPECT_TRUE(has(r, Severity::error, fmt::format("... and {} more: inverted tetrahedra", m.tets.size() - kMaxMessagesPerKind)));
}

}  // namespace
}  // namespace tactus::mesh
