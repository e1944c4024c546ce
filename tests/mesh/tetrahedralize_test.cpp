#include "mesh/tetrahedralize.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/error.hpp"
#include "mesh/generators.hpp"
#include "mesh/half_edge.hpp"
#include "mesh/quality.hpp"
#include "mesh/tet_topology.hpp"
#include "mesh/validate.hpp"

namespace tactus::mesh {
namespace {

void expect_all_positive(const TetMesh& m) {
  std::size_t negative = 0;
  for (std::size_t t = 0; t < m.tets.size(); ++t) negative += m.tet_volume(t) <= 0.0;
  EXPECT_EQ(negative, 0u);
  const auto report = validate(m);
  EXPECT_TRUE(report.ok()) << (report.problems.empty() ? "" : report.problems[0].what);
}

TEST(Tetrahedralize, Switches) {
  TetrahedralizeOptions o;
  EXPECT_EQ(tetgen_switches(o), "pzq1.414Q");
  o.max_volume = 1e-7;
  o.min_dihedral_deg = 12;
  o.radius_edge_ratio = 1.2;
  EXPECT_EQ(tetgen_switches(o), "pzq1.2/12a9.9999999999999995e-08Q");
}

TEST(Tetrahedralize, BoxKeepsVolumeAndBoundary) {
  const Vec3 size(0.1, 0.2, 0.3);
  const TriMesh surface = box_surface(size, 2);
  TetrahedralizeOptions o;
  o.max_volume = 1e-4;
  const TetMesh m = tetrahedralize(surface, o);
  ASSERT_GT(m.tets.size(), 10u);
  expect_all_positive(m);
  EXPECT_NEAR(m.volume(), size.prod(), 1e-9 * size.prod());
  // The boundary is the box again: closed, outward, same volume and area, same extent.
  const BoundarySurface b = extract_boundary(m);
  EXPECT_TRUE(HalfEdgeMesh(b.surface).closed());
  EXPECT_NEAR(b.surface.signed_volume(), size.prod(), 1e-9 * size.prod());
  EXPECT_NEAR(b.surface.area(), surface.area(), 1e-9 * surface.area());
  EXPECT_TRUE((b.surface.bounds().min - surface.bounds().min).norm() < 1e-12);
  EXPECT_TRUE((b.surface.bounds().max - surface.bounds().max).norm() < 1e-12);
  // The input vertices come first, unchanged.
  for (std::size_t v = 0; v < surface.vertices.size(); ++v) EXPECT_EQ(m.vertices[v], surface.vertices[v]);
}

TEST(Tetrahedralize, PreserveSurfaceKeepsTriangles) {
  const TriMesh surface = sphere(0.05, 2);
  TetrahedralizeOptions o;
  o.preserve_surface = true;
  o.max_volume = 1e-6;
  const TetMesh m = tetrahedralize(surface, o);
  expect_all_positive(m);
  EXPECT_EQ(extract_boundary(m).surface.triangles.size(), surface.triangles.size());
  EXPECT_NEAR(m.volume(), surface.signed_volume(), 1e-9 * surface.signed_volume());
}

TEST(Tetrahedralize, SphereWithMaxVolume) {
  const double r = 0.05;
  const TriMesh surface = sphere(r, 3);
  const double max_volume = 2e-7;
  TetrahedralizeOptions o;
  o.max_volume = max_volume;
  const TetMesh m = tetrahedralize(surface, o);
  expect_all_positive(m);
  // TetGen leaves a few tets slightly above the bound where splitting them would encroach
  // on the boundary; nearly all obey it.
  std::size_t above = 0;
  double largest = 0.0;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    largest = std::max(largest, m.tet_volume(t));
    above += m.tet_volume(t) > max_volume;
  }
  EXPECT_LE(largest, 1.5 * max_volume);
  EXPECT_LE(above, m.tets.size() / 100);
  EXPECT_GE(m.tets.size(), static_cast<std::size_t>(surface.signed_volume() / max_volume));
  EXPECT_NEAR(m.volume(), surface.signed_volume(), 1e-9 * surface.signed_volume());
  // Finer bound, more tets.
  o.max_volume = max_volume / 4;
  EXPECT_GT(tetrahedralize(surface, o).tets.size(), m.tets.size());
}

TEST(Tetrahedralize, RejectsOpenSurface) {
  TriMesh open = sphere(1.0, 1);
  open.triangles.pop_back();
  try {
    tetrahedralize(open);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("not a closed manifold"), std::string::npos) << what;
    EXPECT_NE(what.find("open boundary"), std::string::npos) << what;
  }
}

TEST(Tetrahedralize, RejectsSelfIntersectingSurface) {
  // Two overlapping closed boxes: each is a valid closed manifold, together they intersect.
  TriMesh a = box_surface(Vec3(1, 1, 1), 1);
  const TriMesh b = box_surface(Vec3(1, 1, 1), 1);
  const auto offset = static_cast<Index>(a.vertices.size());
  for (const auto& v : b.vertices) a.vertices.push_back(v + Vec3(0.5, 0.3, 0.2));
  for (auto t : b.triangles) a.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  try {
    tetrahedralize(a);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("surface intersects itself"), std::string::npos) << e.what();
  }
}

void organ_to_node_count(int resolution, std::size_t target) {
  const TriMesh surface = organ(0.22, resolution);
  const NodeCountResult r = tetrahedralize_to_node_count_detailed(surface, target);
  const TetMesh& m = r.mesh;
  EXPECT_NEAR(static_cast<double>(m.vertices.size()), static_cast<double>(target), 0.1 * target);
  expect_all_positive(m);
  EXPECT_NEAR(m.volume(), surface.signed_volume(), 1e-9 * surface.signed_volume());
  const TetQuality q = tet_quality(m);
  EXPECT_EQ(q.inverted, 0u);
  std::printf("organ res %d, target %zu: %zu nodes, %zu tets, max_volume %.3g m³, surface %zu vertices; "
              "radius ratio min %.3f mean %.3f, dihedral min %.1f° max %.1f°, slivers %zu\n",
              resolution, target, m.vertices.size(), m.tets.size(), r.max_volume, surface.vertices.size(),
              q.radius_ratio.min, q.radius_ratio.mean, q.min_dihedral_deg.min, q.max_dihedral_deg.max, q.slivers);
}

// Surface resolutions chosen so the surface holds about half (500) and 40% (2000) of the nodes.
TEST(Tetrahedralize, OrganAbout500Nodes) { organ_to_node_count(7, 500); }
TEST(Tetrahedralize, OrganAbout2000Nodes) { organ_to_node_count(12, 2000); }

TEST(Tetrahedralize, NodeCountTargetBelowSurfaceIsRejected) {
  try {
    tetrahedralize_to_node_count(organ(0.22, 12), 100);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("use a coarser surface"), std::string::npos) << e.what();
  }
}

/// No child process left behind, exited or not.
void expect_no_children() {
  errno = 0;
  EXPECT_EQ(::waitpid(-1, nullptr, WNOHANG), -1);
  EXPECT_EQ(errno, ECHILD);
}

TEST(TetrahedralizeBudget, ABoundedRunGivesTheSameMesh) {
  const TriMesh s = sphere(0.05, 3);
  TetrahedralizeOptions o;
  o.max_volume = 1e-7;
  const TetMesh in_process = tetrahedralize(s, o);
  o.budget.seconds = 60.0;
#ifndef TACTUS_SANITIZED
  // An address-space cap stops a sanitized child at once: ASan's and TSan's shadow memory
  // alone maps terabytes.
  o.budget.memory_bytes = std::size_t{8} << 30;
#endif
  const TetMesh bounded = tetrahedralize(s, o);
  EXPECT_EQ(bounded.vertices, in_process.vertices);
  EXPECT_EQ(bounded.tets, in_process.tets);
  const TetMesh counted = tetrahedralize_to_node_count(s, 1500, 1.414, 0.1, true, o.budget);
  EXPECT_EQ(counted.tets, tetrahedralize_to_node_count(s, 1500).tets);
  expect_no_children();
}

TEST(TetrahedralizeBudget, AJobPastTheDeadlineIsStoppedAndRefused) {
  // Millions of tetrahedra: many seconds of work, stopped after 0.2 s.
  TetrahedralizeOptions o;
  o.max_volume = 1e-11;
  o.budget.seconds = 0.2;
  const auto start = std::chrono::steady_clock::now();
  try {
    (void)tetrahedralize(sphere(0.05, 3), o);
    ADD_FAILURE() << "expected a timeout";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did not finish within 0.2 s"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--timeout"), std::string::npos) << e.what();
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 3.0);
  // The node-count search shares one deadline across its runs.
  EXPECT_THROW((void)tetrahedralize_to_node_count(organ(0.22, 12), 200000, 1.414, 0.1, true, {0.2, 0}), InputError);
  expect_no_children();
}

TEST(TetrahedralizeBudget, AMemoryCapIsRefusedNamingIt) {
  TetrahedralizeOptions o;
  o.max_volume = 1e-11;
  o.budget.memory_bytes = std::size_t{64} << 20;  // below what the process already maps
  try {
    (void)tetrahedralize(sphere(0.05, 3), o);
    ADD_FAILURE() << "expected running out of memory";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("64 MiB"), std::string::npos) << e.what();
  }
  expect_no_children();
}

}  // namespace
}  // namespace tactus::mesh
