// Triangle BVH and point tree, checked against brute force over every triangle or point
// (closest_point_on_surface, raycast_surface, a solid-angle winding number), on generated
// surfaces before and after random deformations followed by refits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "contact/bvh.hpp"
#include "core/counting_allocator.hpp"
#include "core/error.hpp"
#include "mesh/generators.hpp"

namespace tactus::contact {
namespace {

#ifdef TACTUS_SANITIZED
constexpr int kQueries = 60;
#else
constexpr int kQueries = 300;
#endif

struct Surface {
  std::string name;
  mesh::TriMesh mesh;
  bool closed = true;
};

std::vector<Surface> surfaces() {
  std::vector<Surface> s;
  for (int sub : {0, 2, 4}) s.push_back({"sphere" + std::to_string(sub), mesh::sphere(0.05, sub)});
  for (int cells : {1, 3, 8}) s.push_back({"box" + std::to_string(cells), mesh::box_surface(Vec3(0.1, 0.06, 0.04), cells)});
  for (int res : {8, 20}) s.push_back({"organ" + std::to_string(res), mesh::organ(0.12, res)});
  s.push_back({"cylinder", mesh::cylinder(0.02, 0.08, 24, 6)});
  s.push_back({"plate", mesh::grid_plate(0.1, 0.08, 9, 7), false});
  // Far from the origin, where single-precision boxes are coarse next to the triangles.
  mesh::TriMesh far = mesh::sphere(0.05, 3);
  for (Vec3& v : far.vertices) v += Vec3(1000.0, -500.0, 250.0);
  s.push_back({"far sphere", far});
  return s;
}

/// Points around the surface: uniform in its box grown by half, and close to vertices.
Vec3 random_point(const std::vector<Vec3>& x, const Aabb& box, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3 size = box.size().cwiseMax(Vec3::Constant(1e-3));
  if (u(rng) < 0.5) {
    const Vec3 r(u(rng), u(rng), u(rng));
    return box.min - 0.25 * size + 1.5 * size.cwiseProduct(r);
  }
  std::uniform_int_distribution<std::size_t> pick(0, x.size() - 1);
  const Vec3 r(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
  return x[pick(rng)] + 0.02 * size.norm() * r;
}

Vec3 random_direction(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Vec3 d(n(rng), n(rng), n(rng));
  while (d.squaredNorm() < 1e-6) d = Vec3(n(rng), n(rng), n(rng));
  return d.normalized();
}

/// A smooth wave of displacement (keeps a closed surface free of self-intersection when
/// the amplitude is small) plus, when `jitter` > 0, independent noise at every vertex.
std::vector<Vec3> deformed(const std::vector<Vec3>& x, double amplitude, double jitter, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Aabb box;
  for (const Vec3& p : x) box.add(p);
  const double size = box.size().norm();
  const Vec3 k = random_direction(rng) * (std::numbers::pi / size);
  const Vec3 along = random_direction(rng);
  const double phase = u(rng) * std::numbers::pi;
  std::vector<Vec3> y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i)
    y[i] = x[i] + amplitude * size * std::sin(k.dot(x[i]) + phase) * along +
           jitter * size * Vec3(u(rng), u(rng), u(rng));
  return y;
}

void expect_same_closest(const SurfacePoint& got, const SurfacePoint& want, const std::string& where) {
  ASSERT_EQ(got.triangle, want.triangle) << where;
  EXPECT_NEAR(got.distance, want.distance, 1e-12) << where;
  EXPECT_LT((got.point - want.point).norm(), 1e-12) << where;
  EXPECT_LT((got.barycentric - want.barycentric).norm(), 1e-12) << where;
  EXPECT_LT((got.normal - want.normal).norm(), 1e-12) << where;
}

void expect_same_hits(const std::vector<RayHit>& got, const std::vector<RayHit>& want, const std::string& where) {
  ASSERT_EQ(got.size(), want.size()) << where;
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].triangle, want[i].triangle) << where << " hit " << i;
    EXPECT_NEAR(got[i].t, want[i].t, 1e-12) << where << " hit " << i;
    EXPECT_LT((got[i].point - want[i].point).norm(), 1e-12) << where << " hit " << i;
    EXPECT_EQ(got[i].entering, want[i].entering) << where << " hit " << i;
  }
}

std::vector<std::int32_t> brute_sphere_overlap(const Vec3& c, double r, const std::vector<Vec3>& x,
                                               const std::vector<mesh::Triangle>& tris) {
  std::vector<std::int32_t> out;
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const auto q = closest_point_on_triangle(c, x[static_cast<std::size_t>(tris[t][0])],
                                             x[static_cast<std::size_t>(tris[t][1])], x[static_cast<std::size_t>(tris[t][2])]);
    if ((c - q.point).squaredNorm() <= r * r) out.push_back(static_cast<std::int32_t>(t));
  }
  return out;
}

/// Generalised winding number by solid angles (Van Oosterom & Strackee 1983).
double winding_number(const Vec3& p, const std::vector<Vec3>& x, const std::vector<mesh::Triangle>& tris) {
  double sum = 0.0;
  for (const auto& t : tris) {
    const Vec3 a = x[static_cast<std::size_t>(t[0])] - p, b = x[static_cast<std::size_t>(t[1])] - p,
               c = x[static_cast<std::size_t>(t[2])] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    sum += 2.0 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb);
  }
  return sum / (4.0 * std::numbers::pi);
}

/// Σ ±1 over the hits (+1 entering): how many times the ray went in, net.
int net_entries(const std::vector<RayHit>& hits) {
  int n = 0;
  for (const RayHit& h : hits) n += h.entering ? 1 : -1;
  return n;
}

/// Compares every query of the tree with brute force over (x, tris).
void check_against_brute_force(const TriangleBvh& bvh, const std::vector<Vec3>& x,
                               const std::vector<mesh::Triangle>& tris, const std::string& name, std::mt19937& rng) {
  Aabb box;
  for (const Vec3& p : x) box.add(p);
  const double size = box.size().norm();
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<RayHit> got, want;
  std::vector<std::int32_t> got_tris;
  for (int q = 0; q < kQueries; ++q) {
    const std::string where = name + " query " + std::to_string(q);
    const Vec3 p = random_point(x, box, rng);
    const SurfacePoint want_cp = closest_point_on_surface(p, x, tris);
    expect_same_closest(bvh.closest_point(p), want_cp, where);
    const double max_distance = 2.0 * u(rng) * want_cp.distance;
    const SurfacePoint limited = bvh.closest_point(p, max_distance);
    EXPECT_EQ(limited.triangle, want_cp.distance <= max_distance ? want_cp.triangle : -1) << where;

    // Rays in random directions, and aimed at a vertex (through shared edges and vertices
    // up to rounding), over a random or unlimited length.
    Vec3 d = random_direction(rng);
    if (q % 3 == 0) {
      std::uniform_int_distribution<std::size_t> pick(0, x.size() - 1);
      const Vec3 to = x[pick(rng)];
      if (to != p) d = to - p;
    }
    const double max_t = q % 2 == 0 ? std::numeric_limits<double>::infinity() : u(rng) * size;
    bvh.raycast(p, d, max_t, got);
    raycast_surface(p, d, max_t, x, tris, want);
    expect_same_hits(got, want, where + " ray");
    EXPECT_TRUE(std::is_sorted(got.begin(), got.end(), [](const RayHit& a, const RayHit& b) { return a.t < b.t; }));

    const Vec3 b = random_point(x, box, rng);
    bvh.segment(p, b, got);
    if (p != b) raycast_surface(p, b - p, 1.0, x, tris, want);
    expect_same_hits(got, want, where + " segment");
    for (const RayHit& h : got) {
      EXPECT_GE(h.t, 0.0);
      EXPECT_LE(h.t, 1.0);
    }

    const double radius = 0.1 * u(rng) * size;
    bvh.sphere_overlap(p, radius, got_tris);
    EXPECT_EQ(got_tris, brute_sphere_overlap(p, radius, x, tris)) << where << " sphere";
  }
}

TEST(TriangleBvh, MatchesBruteForceOnGeneratedSurfaces) {
  std::mt19937 rng(11);
  for (const Surface& s : surfaces()) {
    const TriangleBvh bvh(s.mesh.vertices, s.mesh.triangles);
    EXPECT_EQ(bvh.triangle_count(), s.mesh.triangles.size());
    EXPECT_LE(bvh.depth(), TriangleBvh::kMaxDepth);
    EXPECT_DOUBLE_EQ(bvh.quality(), 1.0);
    check_against_brute_force(bvh, s.mesh.vertices, s.mesh.triangles, s.name, rng);
  }
}

TEST(TriangleBvh, MatchesBruteForceAfterDeformationAndRefit) {
  std::mt19937 rng(12);
  for (const Surface& s : surfaces()) {
    TriangleBvh bvh(s.mesh.vertices, s.mesh.triangles);
    for (int step = 0; step < 3; ++step) {
      // Smooth waves, then independent jitter of a tenth of the size: boxes of the old
      // topology now overlap a lot, answers must still be exact.
      const auto x = deformed(s.mesh.vertices, 0.05 * (step + 1), step == 2 ? 0.1 : 0.0, rng);
      bvh.refit(x);
      const Aabb b = bvh.bounds();
      for (const Vec3& p : x) EXPECT_TRUE(b.contains(p)) << s.name;
      check_against_brute_force(bvh, x, s.mesh.triangles, s.name + " step " + std::to_string(step), rng);
    }
  }
}

TEST(TriangleBvh, AxisRaysThroughGridVerticesAndEdgesCrossOnce) {
  // A unit cube with 4 cells per edge: every coordinate is a multiple of 1/4 and axis rays
  // are not sheared, so rays through vertices and edges meet them exactly.
  const mesh::TriMesh box = mesh::box_surface(Vec3(1, 1, 1), 4);
  const TriangleBvh bvh(box.vertices, box.triangles);
  std::vector<RayHit> hits;
  int exact_cases = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {1.0, -1.0})
      for (int i = -3; i <= 3; ++i)  // eighths: even i, j lie on grid lines (edges, vertices)
        for (int j = -3; j <= 3; ++j) {
          const double u = 0.125 * i, v = 0.125 * j;
          Vec3 d = Vec3::Zero();
          d[axis] = sign;
          Vec3 outside = Vec3::Zero(), inside = Vec3::Zero();
          outside[axis] = -2.0 * sign;
          outside[(axis + 1) % 3] = inside[(axis + 1) % 3] = u;
          outside[(axis + 2) % 3] = inside[(axis + 2) % 3] = v;
          bvh.raycast(outside, d, std::numeric_limits<double>::infinity(), hits);
          ASSERT_EQ(hits.size(), 2u) << "axis " << axis << " at " << u << ", " << v;
          EXPECT_TRUE(hits[0].entering);
          EXPECT_FALSE(hits[1].entering);
          EXPECT_NEAR(hits[0].t, 1.5, 1e-15);
          EXPECT_NEAR(hits[1].t, 2.5, 1e-15);
          bvh.raycast(inside, d, std::numeric_limits<double>::infinity(), hits);
          ASSERT_EQ(hits.size(), 1u) << "axis " << axis << " from inside at " << u << ", " << v;
          EXPECT_FALSE(hits[0].entering);
          EXPECT_TRUE(bvh.inside(inside));
          if (i % 2 == 0 || j % 2 == 0) ++exact_cases;
        }
  EXPECT_GT(exact_cases, 100);
}

TEST(TriangleBvh, OblongRaysThroughExactVerticesKeepParity) {
  // Directions with binary-fraction components through every vertex of the gridded cube:
  // the shear is exact, so these rays meet vertices and edges exactly, some along faces.
  const mesh::TriMesh box = mesh::box_surface(Vec3(1, 1, 1), 4);
  const TriangleBvh bvh(box.vertices, box.triangles);
  const std::vector<Vec3> directions = {{1, 0.5, 0.25}, {-0.5, 1, 0.75}, {1, 1, 1},      {1, 1, 0},
                                        {0.25, -1, 0.5}, {0, 1, -1},     {-1, 0.5, -0.5}};
  std::vector<RayHit> hits, want;
  for (const Vec3& d : directions)
    for (const Vec3& v : box.vertices) {
      // A line through v from far outside: it enters as often as it leaves.
      const Vec3 origin = v - 4.0 * d;
      bvh.raycast(origin, d, std::numeric_limits<double>::infinity(), hits);
      EXPECT_EQ(hits.size() % 2, 0u) << "through " << v.transpose() << " along " << d.transpose();
      EXPECT_EQ(net_entries(hits), 0) << "through " << v.transpose() << " along " << d.transpose();
      raycast_surface(origin, d, std::numeric_limits<double>::infinity(), box.vertices, box.triangles, want);
      expect_same_hits(hits, want, "brute force");
      // From the centre through v: one net exit.
      bvh.raycast(Vec3::Zero(), v, std::numeric_limits<double>::infinity(), hits);
      EXPECT_EQ(hits.size() % 2, 1u) << "from the centre through " << v.transpose();
      EXPECT_EQ(net_entries(hits), -1) << "from the centre through " << v.transpose();
    }
}

TEST(TriangleBvh, RaysThroughSphereVerticesAndEdgesCrossOnce) {
  const mesh::TriMesh s = mesh::sphere(1.0, 2);
  const TriangleBvh bvh(s.vertices, s.triangles);
  std::vector<Vec3> targets = s.vertices;
  for (const auto& t : s.triangles) {
    const Vec3 a = s.vertices[static_cast<std::size_t>(t[0])], b = s.vertices[static_cast<std::size_t>(t[1])];
    targets.push_back(0.5 * (a + b));
  }
  std::vector<RayHit> hits;
  for (const Vec3& target : targets) {
    bvh.raycast(Vec3::Zero(), target, std::numeric_limits<double>::infinity(), hits);
    ASSERT_EQ(hits.size(), 1u) << "from the centre through " << target.transpose();
    EXPECT_FALSE(hits[0].entering);
    EXPECT_NEAR(hits[0].point.norm(), target.norm(), 1e-12);
    // From outside through the target and on through the centre: in once, out once.
    bvh.raycast(2.0 * target, -target, std::numeric_limits<double>::infinity(), hits);
    ASSERT_EQ(hits.size(), 2u) << "from outside through " << target.transpose();
    EXPECT_TRUE(hits[0].entering);
    EXPECT_FALSE(hits[1].entering);
  }
}

TEST(TriangleBvh, RaysFromInsideAnOrganThroughEveryVertexLeaveOnceNet) {
  const mesh::TriMesh organ = mesh::organ(0.12, 12);
  const TriangleBvh bvh(organ.vertices, organ.triangles);
  const Vec3 origin = Vec3::Zero();
  ASSERT_NEAR(winding_number(origin, organ.vertices, organ.triangles), 1.0, 1e-9);
  std::vector<RayHit> hits;
  for (const Vec3& v : organ.vertices) {
    bvh.raycast(origin, v - origin, std::numeric_limits<double>::infinity(), hits);
    EXPECT_EQ(hits.size() % 2, 1u) << "through " << v.transpose();
    EXPECT_EQ(net_entries(hits), -1) << "through " << v.transpose();
  }
}

TEST(TriangleBvh, AllLayersOfNestedSurfacesInOrder) {
  // Two concentric spheres (a capsule wall and a nodule, say): a ray through both meets
  // four layers, entering, entering, leaving, leaving.
  mesh::TriMesh outer = mesh::sphere(0.05, 3), inner = mesh::sphere(0.02, 3);
  const auto offset = static_cast<mesh::Index>(outer.vertices.size());
  const auto first_inner = static_cast<std::int32_t>(outer.triangles.size());
  for (const Vec3& v : inner.vertices) outer.vertices.push_back(v);
  for (const auto& t : inner.triangles) outer.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  const TriangleBvh bvh(outer.vertices, outer.triangles);
  std::vector<RayHit> hits;
  bvh.raycast(Vec3(-0.1, 0.003, 0.001), Vec3(1, 0, 0), 1.0, hits);
  ASSERT_EQ(hits.size(), 4u);
  EXPECT_TRUE(hits[0].entering && hits[1].entering && !hits[2].entering && !hits[3].entering);
  EXPECT_LT(hits[0].triangle, first_inner);
  EXPECT_GE(hits[1].triangle, first_inner);
  EXPECT_GE(hits[2].triangle, first_inner);
  EXPECT_LT(hits[3].triangle, first_inner);
  EXPECT_NEAR(hits[1].point.norm(), 0.02, 1e-3);
  // A segment that stops inside the nodule sees the first two layers only.
  bvh.segment(Vec3(-0.1, 0.003, 0.001), Vec3(0.0, 0.003, 0.001), hits);
  EXPECT_EQ(hits.size(), 2u);
  EXPECT_FALSE(bvh.inside(Vec3(0.0, 0.003, 0.001)));  // inside both: even parity
  EXPECT_TRUE(bvh.inside(Vec3(0.03, 0.0, 0.0)));       // between the layers
}

TEST(TriangleBvh, InsideMatchesWindingNumber) {
  std::mt19937 rng(13);
  int inside_count = 0, outside_count = 0;
  for (const Surface& s : surfaces()) {
    if (!s.closed) continue;
    TriangleBvh bvh(s.mesh.vertices, s.mesh.triangles);
    for (int round = 0; round < 2; ++round) {
      std::vector<Vec3> x = s.mesh.vertices;
      if (round == 1) {
        x = deformed(s.mesh.vertices, 0.03, 0.0, rng);
        bvh.refit(x);
      }
      Aabb box;
      for (const Vec3& p : x) box.add(p);
      for (int q = 0; q < kQueries; ++q) {
        const Vec3 p = random_point(x, box, rng);
        if (closest_point_on_surface(p, x, s.mesh.triangles).distance < 1e-9) continue;
        const double w = winding_number(p, x, s.mesh.triangles);
        ASSERT_LT(std::min(std::abs(w), std::abs(w - 1.0)), 1e-6) << s.name << ": not a clean winding number";
        const bool expected = w > 0.5;
        EXPECT_EQ(bvh.inside(p), expected) << s.name << " round " << round << " at " << p.transpose();
        (expected ? inside_count : outside_count) += 1;
      }
    }
  }
  EXPECT_GT(inside_count, 100);
  EXPECT_GT(outside_count, 100);
}

TEST(TriangleBvh, InsideOnGridPointsOfAGriddedCube) {
  // Points on the planes and lines of the grid; the parity ray of inside() is not an axis,
  // so these check the answers near exact structure.
  const mesh::TriMesh box = mesh::box_surface(Vec3(1, 1, 1), 4);
  const TriangleBvh bvh(box.vertices, box.triangles);
  for (int i = -5; i <= 5; ++i)
    for (int j = -5; j <= 5; ++j)
      for (int k = -5; k <= 5; ++k) {
        const Vec3 p = 0.125 * Vec3(i, j, k);
        const int m = std::max({std::abs(i), std::abs(j), std::abs(k)});
        if (m == 4) continue;  // on the surface
        EXPECT_EQ(bvh.inside(p), m < 4) << p.transpose();
      }
}

TEST(TriangleBvh, TiesGoToTheLowestTriangleIndex) {
  const mesh::TriMesh box = mesh::box_surface(Vec3(1, 1, 1), 2);
  const TriangleBvh bvh(box.vertices, box.triangles);
  // The centre is equally far from all six faces; a vertex of the grid lies on several
  // triangles; a corner is shared by three faces.
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(0.5, 0, 0), Vec3(0.5, 0.5, 0.5), Vec3(0, 0.5, 0.5), Vec3(0.25, 0.25, 0.25)}) {
    const SurfacePoint got = bvh.closest_point(p);
    const SurfacePoint want = closest_point_on_surface(p, box.vertices, box.triangles);
    expect_same_closest(got, want, "tie at " + std::to_string(p.x()));
    std::vector<std::int32_t> tied;
    bvh.sphere_overlap(p, want.distance, tied);
    ASSERT_FALSE(tied.empty());
    EXPECT_EQ(got.triangle, tied.front());
  }
}

TEST(TriangleBvh, QualityTracksHowMuchRefitsLoosenedTheTree) {
  const mesh::TriMesh s = mesh::sphere(0.05, 4);
  TriangleBvh bvh(s.vertices, s.triangles);
  EXPECT_DOUBLE_EQ(bvh.quality(), 1.0);
  EXPECT_FALSE(bvh.needs_rebuild());
  // Translation and uniform scaling leave the normalised cost alone (up to the single
  // precision the boxes are stored in).
  std::vector<Vec3> moved = s.vertices;
  for (Vec3& p : moved) p = 3.0 * p + Vec3(1, -2, 0.5);
  bvh.refit(moved);
  EXPECT_NEAR(bvh.quality(), 1.0, 1e-4);
  // A gentle wave loosens it a little.
  std::mt19937 rng(14);
  bvh.refit(deformed(s.vertices, 0.05, 0.0, rng));
  EXPECT_GT(bvh.quality(), 1.0);
  EXPECT_FALSE(bvh.needs_rebuild());
  // Vertices shuffled across the surface: leaves span the whole sphere.
  std::vector<Vec3> shuffled = s.vertices;
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  bvh.refit(shuffled);
  EXPECT_GT(bvh.quality(), 3.0);
  EXPECT_TRUE(bvh.needs_rebuild());
  bvh.build(shuffled, s.triangles);
  EXPECT_DOUBLE_EQ(bvh.quality(), 1.0);
  EXPECT_FALSE(bvh.needs_rebuild());
}

TEST(TriangleBvh, EmptyMeshAnswersNothing) {
  TriangleBvh bvh;
  EXPECT_TRUE(bvh.empty());
  bvh.build({}, {});
  EXPECT_TRUE(bvh.empty());
  EXPECT_EQ(bvh.closest_point(Vec3(1, 2, 3)).triangle, -1);
  std::vector<RayHit> hits(3);
  bvh.raycast(Vec3::Zero(), Vec3::UnitX(), 1.0, hits);
  EXPECT_TRUE(hits.empty());
  bvh.segment(Vec3::Zero(), Vec3::UnitX(), hits);
  EXPECT_TRUE(hits.empty());
  std::vector<std::int32_t> tris(2);
  bvh.sphere_overlap(Vec3::Zero(), 1.0, tris);
  EXPECT_TRUE(tris.empty());
  EXPECT_FALSE(bvh.inside(Vec3::Zero()));
  bvh.refit({});
  EXPECT_TRUE(bvh.bounds().empty());
  // Vertices without triangles are an empty surface too.
  const std::vector<Vec3> loose = {{0, 0, 0}, {1, 0, 0}};
  bvh.build(loose, {});
  EXPECT_EQ(bvh.closest_point(Vec3(1, 2, 3)).triangle, -1);
  bvh.refit(loose);
}

TEST(TriangleBvh, DegenerateTrianglesAreNeverHitButStillHaveClosestPoints) {
  const std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}};
  const std::vector<mesh::Triangle> t = {{0, 1, 2}, {0, 0, 3}, {0, 1, 3}};
  const TriangleBvh bvh(x, t);
  std::vector<RayHit> hits;
  bvh.raycast(Vec3(1.5, 0, 1), Vec3(0, 0, -1), 5.0, hits);
  EXPECT_TRUE(hits.empty());  // only through the collinear triangle 0
  bvh.raycast(Vec3(0.25, 0.25, 1), Vec3(0, 0, -1), 5.0, hits);
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_EQ(hits[0].triangle, 2);
  const Vec3 p(1.5, -1, 0);
  expect_same_closest(bvh.closest_point(p), closest_point_on_surface(p, x, t), "degenerate");
}

TEST(TriangleBvh, RejectsBadInput) {
  const mesh::TriMesh s = mesh::sphere(0.05, 1);
  EXPECT_THROW(TriangleBvh(s.vertices, std::vector<mesh::Triangle>{{0, 1, 99}}), InputError);
  EXPECT_THROW(TriangleBvh(s.vertices, std::vector<mesh::Triangle>{{0, -1, 2}}), InputError);
  std::vector<Vec3> bad = s.vertices;
  bad[3].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(TriangleBvh(bad, s.triangles), InputError);
  std::vector<Vec3> huge = s.vertices;
  huge[5].x() = 1e31;  // beyond what single-precision boxes hold
  EXPECT_THROW(TriangleBvh(huge, s.triangles), InputError);

  TriangleBvh bvh(s.vertices, s.triangles);
  EXPECT_THROW(bvh.refit(bad), InputError);
  EXPECT_THROW(bvh.refit(std::vector<Vec3>(s.vertices.begin(), s.vertices.end() - 1)), InputError);
  // A failed refit leaves the tree answering for the old positions.
  EXPECT_EQ(bvh.closest_point(Vec3(0.1, 0, 0)).triangle,
            closest_point_on_surface(Vec3(0.1, 0, 0), s.vertices, s.triangles).triangle);

  std::vector<RayHit> hits;
  std::vector<std::int32_t> tris;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(bvh.raycast(Vec3::Zero(), Vec3::Zero(), 1.0, hits), InputError);
  EXPECT_THROW(bvh.raycast(Vec3::Zero(), Vec3(nan, 0, 1), 1.0, hits), InputError);
  EXPECT_THROW(bvh.raycast(Vec3(nan, 0, 0), Vec3::UnitX(), 1.0, hits), InputError);
  EXPECT_THROW(bvh.raycast(Vec3::Zero(), Vec3::UnitX(), -1.0, hits), InputError);
  EXPECT_THROW(bvh.raycast(Vec3::Zero(), Vec3::UnitX(), nan, hits), InputError);
  EXPECT_THROW(bvh.segment(Vec3::Zero(), Vec3(0, nan, 0), hits), InputError);
  EXPECT_THROW((void)bvh.closest_point(Vec3(nan, 0, 0)), InputError);
  EXPECT_THROW((void)bvh.closest_point(Vec3::Zero(), -1.0), InputError);
  EXPECT_THROW(bvh.sphere_overlap(Vec3::Zero(), -0.1, tris), InputError);
  EXPECT_THROW((void)bvh.inside(Vec3(0, 0, std::numeric_limits<double>::infinity())), InputError);
  try {
    bvh.refit(bad);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not finite"), std::string::npos) << e.what();
  }
}

TEST(TriangleBvh, QueriesAndRefitAllocateNothing) {
  const mesh::TriMesh s = mesh::organ(0.12, 16);
  TriangleBvh bvh(s.vertices, s.triangles);
  std::mt19937 rng(15);
  const auto x = deformed(s.vertices, 0.05, 0.0, rng);
  std::vector<RayHit> hits;
  std::vector<std::int32_t> tris;
  hits.reserve(64);
  tris.reserve(s.triangles.size());
  Aabb box = s.bounds();
  std::vector<Vec3> points;
  for (int i = 0; i < 50; ++i) points.push_back(random_point(s.vertices, box, rng));
  const tactus::testing::AllocationCounter counter;
  bvh.refit(x);
  std::size_t sink = 0;
  for (const Vec3& p : points) {
    sink += static_cast<std::size_t>(bvh.closest_point(p).triangle);
    bvh.raycast(p, Vec3(0.3, -0.4, 0.5), 1.0, hits);
    bvh.segment(p, Vec3::Zero(), hits);
    bvh.sphere_overlap(p, 0.01, tris);
    sink += bvh.inside(p) ? 1u : 0u;
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(sink, 0u);
}

// ---- PointTree ----------------------------------------------------------------------------

std::vector<std::int32_t> brute_near_segment(const Vec3& a, const Vec3& b, double r, const std::vector<Vec3>& x) {
  std::vector<std::int32_t> out;
  const Vec3 d = b - a;
  for (std::size_t i = 0; i < x.size(); ++i) {
    // Distance to the segment by projection onto its line, clamped to its ends.
    const double len2 = d.squaredNorm();
    const double u = len2 > 0.0 ? std::clamp((x[i] - a).dot(d) / len2, 0.0, 1.0) : 0.0;
    if ((x[i] - a - u * d).norm() <= r) out.push_back(static_cast<std::int32_t>(i));
  }
  return out;
}

TEST(PointTree, NodesNearSegmentMatchBruteForce) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const mesh::TetMesh volume = mesh::box_volume(Vec3(0.08, 0.06, 0.05), 12, 9, 8);
  std::vector<Vec3> random_cloud(3000);
  for (Vec3& p : random_cloud) p = Vec3(u(rng), u(rng), u(rng)) * 0.1;
  int non_empty = 0;
  for (const std::vector<Vec3>* cloud : std::vector<const std::vector<Vec3>*>{&volume.vertices, &random_cloud}) {
    PointTree tree(*cloud);
    EXPECT_EQ(tree.point_count(), cloud->size());
    std::vector<Vec3> x = *cloud;
    for (int round = 0; round < 3; ++round) {
      if (round > 0) {
        x = deformed(*cloud, 0.05 * round, 0.01 * round, rng);
        tree.refit(x);
      }
      Aabb box;
      for (const Vec3& p : x) box.add(p);
      std::vector<std::int32_t> got;
      for (int q = 0; q < kQueries; ++q) {
        const Vec3 a = random_point(x, box, rng);
        // Needle-like segments of all lengths, and points (a = b).
        const Vec3 b = q % 10 == 0 ? a : Vec3(a + u(rng) * box.size().norm() * random_direction(rng));
        const double r = 0.05 * u(rng) * box.size().norm();
        tree.nodes_near_segment(a, b, r, got);
        const auto want = brute_near_segment(a, b, r, x);
        EXPECT_EQ(got, want) << "round " << round << " query " << q;
        non_empty += want.empty() ? 0 : 1;
      }
    }
  }
  EXPECT_GT(non_empty, kQueries);
}

TEST(PointTree, EmptyAndBadInput) {
  PointTree tree;
  std::vector<std::int32_t> out(4);
  tree.nodes_near_segment(Vec3::Zero(), Vec3::UnitX(), 1.0, out);
  EXPECT_TRUE(out.empty());
  tree.build({});
  tree.refit({});
  tree.nodes_near_segment(Vec3::Zero(), Vec3::UnitX(), 1.0, out);
  EXPECT_TRUE(out.empty());

  const std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  tree.build(x);
  EXPECT_THROW(tree.refit(std::vector<Vec3>(2)), InputError);
  EXPECT_THROW(tree.build(std::vector<Vec3>{{0, 0, std::numeric_limits<double>::quiet_NaN()}}), InputError);
  EXPECT_THROW(tree.build(std::vector<Vec3>{{0, -2e30, 0}}), InputError);
  EXPECT_THROW(tree.nodes_near_segment(Vec3::Zero(), Vec3::UnitX(), -1.0, out), InputError);
  EXPECT_THROW(tree.nodes_near_segment(Vec3::Zero(), Vec3(std::numeric_limits<double>::infinity(), 0, 0), 1.0, out),
               InputError);
  tree.nodes_near_segment(Vec3(0, -0.1, 0), Vec3(1, -0.1, 0), 0.2, out);
  EXPECT_EQ(out, (std::vector<std::int32_t>{0, 1}));

  // Refit and queries allocate nothing once the output has room.
  out.reserve(x.size());
  const tactus::testing::AllocationCounter counter;
  tree.refit(x);
  tree.nodes_near_segment(Vec3(0, 0, 0), Vec3(0, 1, 0), 0.5, out);
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_EQ(out, (std::vector<std::int32_t>{0, 2}));
}

}  // namespace
}  // namespace tactus::contact
