// BvhSurfaceQuery against BruteForceSurfaceQuery over the same positions: random sphere
// sweeps (faces, edges, vertices, starts in overlap) and closest points with the side, on
// several surfaces before and after deformations followed by refits; sweeps onto the exact
// vertices and edges of a grid, where several triangles tie; no allocation per query.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "contact/bvh_surface_query.hpp"
#include "contact/surface_query.hpp"
#include "core/counting_allocator.hpp"
#include "core/error.hpp"
#include "mesh/generators.hpp"

namespace tactus::contact {
namespace {

#ifdef TACTUS_SANITIZED
constexpr int kQueries = 400;
#else
constexpr int kQueries = 3000;
#endif

struct Surface {
  std::string name;
  mesh::TriMesh mesh;
};

void append(mesh::TriMesh& into, const mesh::TriMesh& part, const Vec3& shift = Vec3::Zero()) {
  const auto base = static_cast<mesh::Index>(into.vertices.size());
  for (const Vec3& v : part.vertices) into.vertices.push_back(v + shift);
  for (const auto& t : part.triangles) into.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

std::vector<Surface> surfaces() {
  std::vector<Surface> s;
  s.push_back({"sphere", mesh::sphere(0.05, 3)});
  mesh::TriMesh bumpy = mesh::sphere(0.04, 3);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (Vec3& v : bumpy.vertices) v *= 1.0 + u(rng);
  s.push_back({"bumpy sphere", bumpy});
  s.push_back({"box", mesh::box_surface(Vec3(0.08, 0.05, 0.03), 4)});
  s.push_back({"organ", mesh::organ(0.12, 16)});
  s.push_back({"plate", mesh::grid_plate(0.1, 0.08, 9, 7)});
  mesh::TriMesh skin = mesh::sphere(0.03, 3);
  append(skin, mesh::sphere(0.027, 3));
  append(skin, mesh::sphere(0.003, 1), Vec3(0.01, 0.005, 0.012));
  s.push_back({"two-layer skin over a nodule", skin});
  return s;
}

/// A smooth wave of displacement of a few percent of the size.
std::vector<Vec3> deformed(const std::vector<Vec3>& x, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Aabb box;
  for (const Vec3& p : x) box.add(p);
  const double size = box.size().norm();
  const Vec3 k = Vec3(u(rng), u(rng), u(rng)).normalized() * (std::numbers::pi / size);
  const Vec3 along = Vec3(u(rng), u(rng), u(rng)).normalized();
  const double phase = std::numbers::pi * u(rng);
  std::vector<Vec3> y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) y[i] = x[i] + 0.04 * size * std::sin(k.dot(x[i]) + phase) * along;
  return y;
}

/// Random points around the surface: in its box grown by half, or close to a vertex.
Vec3 point_near(const std::vector<Vec3>& x, const Aabb& box, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3 size = box.size().cwiseMax(Vec3::Constant(1e-3));
  if (u(rng) < 0.4) return box.min - 0.25 * size + 1.5 * size.cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
  std::uniform_int_distribution<std::size_t> pick(0, x.size() - 1);
  return x[pick(rng)] + 0.03 * size.norm() * Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
}

void expect_same_sweep(const SweepHit& bvh, const SweepHit& reference, const std::string& where) {
  ASSERT_EQ(bvh.hit, reference.hit) << where;
  if (!reference.hit) return;
  EXPECT_EQ(bvh.triangle, reference.triangle) << where;
  EXPECT_NEAR(bvh.time, reference.time, 1e-12) << where;
  // The same feature of that triangle: face, edge or vertex, and the same contact.
  EXPECT_EQ((bvh.barycentric.array() == 0.0).count(), (reference.barycentric.array() == 0.0).count()) << where;
  EXPECT_NEAR((bvh.barycentric - reference.barycentric).norm(), 0.0, 1e-12) << where;
  EXPECT_NEAR((bvh.point - reference.point).norm(), 0.0, 1e-12) << where;
  EXPECT_NEAR((bvh.normal - reference.normal).norm(), 0.0, 1e-12) << where;
}

void expect_same_closest(const ClosestSurfacePoint& bvh, const ClosestSurfacePoint& reference,
                         const std::string& where) {
  ASSERT_EQ(bvh.found, reference.found) << where;
  EXPECT_EQ(bvh.triangle, reference.triangle) << where;
  EXPECT_EQ(bvh.point, reference.point) << where;
  EXPECT_EQ(bvh.barycentric, reference.barycentric) << where;
  EXPECT_EQ(bvh.distance, reference.distance) << where;
  EXPECT_NEAR((bvh.normal - reference.normal).norm(), 0.0, 1e-12) << where;
  EXPECT_EQ(bvh.behind, reference.behind) << where;
}

/// Sweeps from points around the surface: toward another such point (half of them aimed
/// through a surface point so that many hit), with radius 0 or up to 5 % of the size, some
/// starting in overlap; every answer compared with the brute-force scan.
void compare_on(const Surface& s, const std::vector<Vec3>& x, const TriangleBvh& tree, std::mt19937& rng,
                const std::string& stage) {
  const BvhSurfaceQuery bvh(tree);
  const BruteForceSurfaceQuery reference(x, s.mesh.triangles);
  Aabb box;
  for (const Vec3& p : x) box.add(p);
  const double size = box.size().norm();
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<std::size_t> pick(0, s.mesh.triangles.size() - 1);
  int hits = 0, overlaps = 0, edge_or_vertex = 0;
  for (int q = 0; q < kQueries; ++q) {
    const std::string where = s.name + ", " + stage + ", query " + std::to_string(q);
    const Vec3 from = point_near(x, box, rng);
    Vec3 to = point_near(x, box, rng);
    if (q % 2 == 0) {
      const auto& t = s.mesh.triangles[pick(rng)];
      const double wa = u(rng), wb = u(rng) * (1.0 - wa);
      const Vec3 on = wa * x[static_cast<std::size_t>(t[0])] + wb * x[static_cast<std::size_t>(t[1])] +
                      (1.0 - wa - wb) * x[static_cast<std::size_t>(t[2])];
      to = from + (1.0 + u(rng)) * (on - from);
    }
    const double radius = q % 3 == 0 ? 0.0 : 0.05 * size * u(rng);
    const SweepHit expected = reference.sweep_sphere(from, to, radius);
    expect_same_sweep(bvh.sweep_sphere(from, to, radius), expected, where);
    hits += expected.hit ? 1 : 0;
    overlaps += expected.hit && expected.time == 0.0 ? 1 : 0;
    edge_or_vertex += expected.hit && (expected.barycentric.array() == 0.0).any() ? 1 : 0;

    const Vec3 p = point_near(x, box, rng);
    expect_same_closest(bvh.closest_point(p), reference.closest_point(p), where);
    const std::int32_t t = static_cast<std::int32_t>(pick(rng));
    EXPECT_EQ(bvh.triangle(t), reference.triangle(t)) << where;
  }
  EXPECT_GT(hits, kQueries / 4) << s.name << ", " << stage;
  EXPECT_GT(overlaps, 0) << s.name << ", " << stage;
  EXPECT_GT(edge_or_vertex, kQueries / 20) << s.name << ", " << stage;
}

TEST(BvhSurfaceQuery, AnswersLikeBruteForceBeforeAndAfterDeformationAndRefit) {
  std::mt19937 rng(17);
  for (const Surface& s : surfaces()) {
    TriangleBvh tree(s.mesh.vertices, s.mesh.triangles);
    compare_on(s, s.mesh.vertices, tree, rng, "as built");
    const std::vector<Vec3> moved = deformed(s.mesh.vertices, rng);
    tree.refit(moved);
    compare_on(s, moved, tree, rng, "deformed and refitted");
  }
}

TEST(BvhSurfaceQuery, TiesOnGridVerticesAndEdgesGoToTheLowestTriangle) {
  // Straight down onto exact vertices and edge midpoints of a plate: two to six triangles are
  // touched at the same time, and the lowest index must win as in the scan.
  const mesh::TriMesh plate = mesh::grid_plate(0.08, 0.08, 8, 8);
  const TriangleBvh tree(plate.vertices, plate.triangles);
  const BvhSurfaceQuery bvh(tree);
  const BruteForceSurfaceQuery reference(plate.vertices, plate.triangles);
  int ties = 0;
  for (std::size_t v = 0; v < plate.vertices.size(); ++v) {
    const Vec3 on = plate.vertices[v];
    const Vec3 next = plate.vertices[(v + 1) % plate.vertices.size()];
    for (const Vec3& target : {on, Vec3(0.5 * (on + next))}) {
      for (const double radius : {0.0, 0.003}) {
        const Vec3 from = target + Vec3(0, 0, 0.02), to = target - Vec3(0, 0, 0.02);
        const SweepHit expected = reference.sweep_sphere(from, to, radius);
        expect_same_sweep(bvh.sweep_sphere(from, to, radius), expected, "vertex " + std::to_string(v));
        // Count the triangles touched at the same time as the winner.
        int same_time = 0;
        for (const auto& t : plate.triangles) {
          const SweepHit h = sweep_sphere_triangle(from, to, radius, plate.vertices[static_cast<std::size_t>(t[0])],
                                                   plate.vertices[static_cast<std::size_t>(t[1])],
                                                   plate.vertices[static_cast<std::size_t>(t[2])]);
          same_time += h.hit && h.time == expected.time ? 1 : 0;
        }
        ties += same_time > 1 ? 1 : 0;
        // Along the plate through the vertices: axis-aligned motion with zero components.
        const Vec3 side_from = target + Vec3(-0.1, 0, 0.001), side_to = target + Vec3(0.1, 0, 0.001);
        expect_same_sweep(bvh.sweep_sphere(side_from, side_to, radius),
                          reference.sweep_sphere(side_from, side_to, radius), "along, vertex " + std::to_string(v));
      }
    }
  }
  EXPECT_GT(ties, static_cast<int>(plate.vertices.size()));
}

TEST(BvhSurfaceQuery, QueriesAllocateNothing) {
  const mesh::TriMesh organ = mesh::organ(0.12, 16);
  TriangleBvh tree(organ.vertices, organ.triangles);
  std::mt19937 rng(8);
  const std::vector<Vec3> moved = deformed(organ.vertices, rng);
  const Aabb box = organ.bounds();
  std::vector<Vec3> points(400);
  for (Vec3& p : points) p = point_near(organ.vertices, box, rng);
  const BvhSurfaceQuery bvh(tree);
  int hits = 0, found = 0;
  const tactus::testing::AllocationCounter counter;
  tree.refit(moved);
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    hits += bvh.sweep_sphere(points[i], points[i + 1], 0.002).hit ? 1 : 0;
    found += bvh.closest_point(points[i]).found ? 1 : 0;
    found += bvh.triangle(static_cast<std::int32_t>(i)).has_value() ? 1 : 0;
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(hits, 50);
  EXPECT_EQ(found, 2 * static_cast<int>(points.size() - 1));
}

TEST(BvhSurfaceQuery, EmptyTreesAndBadInputFindNothing) {
  const TriangleBvh empty;
  const BvhSurfaceQuery none(empty);
  EXPECT_FALSE(none.closest_point(Vec3::Zero()).found);
  EXPECT_FALSE(none.sweep_sphere(Vec3::Zero(), Vec3::Ones(), 0.1).hit);
  EXPECT_FALSE(none.triangle(0).has_value());

  const mesh::TriMesh ball = mesh::sphere(0.05, 2);
  const TriangleBvh tree(ball.vertices, ball.triangles);
  const BvhSurfaceQuery bvh(tree);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(bvh.closest_point(Vec3(nan, 0, 0)).found);
  EXPECT_FALSE(bvh.sweep_sphere(Vec3(0, 0, 1), Vec3(0, 0, -inf), 0.0).hit);
  EXPECT_FALSE(bvh.sweep_sphere(Vec3(0, 0, 1), Vec3::Zero(), nan).hit);
  EXPECT_FALSE(bvh.sweep_sphere(Vec3(0, 0, 1), Vec3::Zero(), -0.1).hit);
  EXPECT_FALSE(bvh.triangle(-1).has_value());
  EXPECT_FALSE(bvh.triangle(static_cast<std::int32_t>(ball.triangles.size())).has_value());
  // The tree itself reports bad input.
  EXPECT_THROW((void)tree.sweep_sphere(Vec3(0, 0, 1), Vec3(0, 0, nan), 0.0), InputError);
  EXPECT_THROW((void)tree.sweep_sphere(Vec3(0, 0, 1), Vec3::Zero(), -1.0), InputError);
  EXPECT_THROW((void)tree.closest_point_with_side(Vec3(inf, 0, 0)), InputError);
  // A sphere that does not move touches nothing; one that starts clear and stops short neither.
  EXPECT_FALSE(bvh.sweep_sphere(Vec3(0, 0, 0.06), Vec3(0, 0, 0.06), 0.02).hit);
  EXPECT_FALSE(bvh.sweep_sphere(Vec3(0, 0, 0.2), Vec3(0, 0, 0.08), 0.02).hit);
  const SweepHit down = bvh.sweep_sphere(Vec3(0, 0, 0.2), Vec3(0, 0, 0.0), 0.01);
  ASSERT_TRUE(down.hit);
  EXPECT_NEAR(down.center.z(), 0.05 + 0.01, 2e-3);  // the icosphere's top, within a facet's sag
}

}  // namespace
}  // namespace tactus::contact
