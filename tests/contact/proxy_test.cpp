// God-object / proxy rendering: the swept-sphere query against a reference that uses only
// closest points, the side test against a winding number, sliding on planes and corners,
// the friction cone, deforming surfaces, plane blending, and the proxy never ending inside a
// closed surface over many fast random trajectories.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "contact/bvh_surface_query.hpp"
#include "contact/proxy.hpp"
#include "contact/surface_query.hpp"
#include "core/counting_allocator.hpp"
#include "core/error.hpp"
#include "mesh/generators.hpp"

namespace tactus::contact {
namespace {

constexpr double kPi = std::numbers::pi;

// --- references ------------------------------------------------------------------------------

/// Generalised winding number of a closed triangle surface around p: the sum of the solid
/// angles of its triangles over 4π (Van Oosterom & Strackee). 1 inside, 0 outside.
double winding_number(const Vec3& p, const mesh::TriMesh& m) {
  double sum = 0.0;
  for (const auto& t : m.triangles) {
    const Vec3 a = m.vertices[static_cast<std::size_t>(t[0])] - p;
    const Vec3 b = m.vertices[static_cast<std::size_t>(t[1])] - p;
    const Vec3 c = m.vertices[static_cast<std::size_t>(t[2])] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    sum += 2.0 * std::atan2(num, den);
  }
  return sum / (4.0 * kPi);
}

double distance_to(const Vec3& p, const mesh::TriMesh& m) {
  return closest_point_on_surface(p, m.vertices, m.triangles).distance;
}

/// Appends `part` to `into`, moved by `shift`.
void append(mesh::TriMesh& into, const mesh::TriMesh& part, const Vec3& shift = Vec3::Zero()) {
  const auto base = static_cast<mesh::Index>(into.vertices.size());
  for (const Vec3& v : part.vertices) into.vertices.push_back(v + shift);
  for (const auto& t : part.triangles) into.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

mesh::TriMesh transformed(mesh::TriMesh m, const Mat3& rotation, const Vec3& shift = Vec3::Zero()) {
  for (Vec3& v : m.vertices) v = rotation * v + shift;
  return m;
}

/// An icosphere with every vertex moved along its ray by up to ±35 %: closed, outward, and full
/// of concave valleys, sharp ridges and pits (where one face normal gives the wrong side).
mesh::TriMesh bumpy_sphere(double radius, int subdivisions, unsigned seed) {
  mesh::TriMesh m = mesh::sphere(radius, subdivisions);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.35, 0.35);
  for (Vec3& v : m.vertices) v *= 1.0 + u(rng);  // along the ray: every triangle keeps its orientation
  return m;
}

ProxyParams params_with(double radius, double mu_s = 0.0, double mu_k = 0.0) {
  ProxyParams p;
  p.radius = radius;
  p.stiffness = 1000.0;
  p.static_friction = mu_s;
  p.kinetic_friction = mu_k;
  validate_proxy_params(p);
  return p;
}

constexpr double kDt = 1e-3;

// Sample counts, smaller under sanitizers (ten to fifty times slower) so that the suite stays
// within a minute there.
#ifdef TACTUS_SANITIZED
constexpr int kSweepTrials = 600;
constexpr int kSidePoints = 800;
#else
constexpr int kSweepTrials = 3000;
constexpr int kSidePoints = 4000;
#endif

// --- swept sphere against one triangle -------------------------------------------------------

/// Distance from a + t·(b − a) to the triangle: convex in t.
struct SegmentDistance {
  Vec3 from, d, a, b, c;
  double operator()(double t) const {
    const Vec3 x = from + t * d;
    return (x - closest_point_on_triangle(x, a, b, c).point).norm();
  }
};

TEST(SweepSphereTriangle, MatchesAReferenceBuiltOnClosestPointsOnly) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int hits = 0, misses = 0;
  for (int trial = 0; trial < kSweepTrials; ++trial) {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    const Vec3 from = 2.0 * Vec3(u(rng), u(rng), u(rng));
    // Aim half of the segments at a point of the triangle so that many of them hit.
    const Vec3 aim = trial % 2 == 0 ? 2.0 * Vec3(u(rng), u(rng), u(rng))
                                    : Vec3(0.2 * a + 0.3 * b + 0.5 * c + 0.3 * Vec3(u(rng), u(rng), u(rng)));
    const Vec3 to = from + (1.0 + 0.5 * u(rng)) * (aim - from);
    const double radius = trial % 5 == 0 ? 0.0 : 0.25 * (1.0 + u(rng));
    const SegmentDistance dist{from, to - from, a, b, c};
    if (dist(0.0) <= radius + 1e-9) continue;  // overlap at the start: covered below

    // Minimum of the convex distance by golden-section search, then the first crossing by bisection.
    double lo = 0.0, hi = 1.0;
    for (int i = 0; i < 200; ++i) {
      const double m1 = lo + (hi - lo) * 0.381966, m2 = hi - (hi - lo) * 0.381966;
      (dist(m1) < dist(m2) ? hi : lo) = dist(m1) < dist(m2) ? m2 : m1;
    }
    const double t_min = 0.5 * (lo + hi);
    const SweepHit hit = sweep_sphere_triangle(from, to, radius, a, b, c);
    if (dist(t_min) > radius + 1e-9) {
      EXPECT_FALSE(hit.hit) << "trial " << trial;
      ++misses;
      continue;
    }
    if (dist(t_min) > radius - 1e-9) continue;  // a grazing touch: either answer is right
    double before = 0.0, after = t_min;
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (before + after);
      (dist(mid) > radius ? before : after) = mid;
    }
    ASSERT_TRUE(hit.hit) << "trial " << trial;
    ++hits;
    EXPECT_NEAR(hit.time, after, 1e-9) << "trial " << trial;
    EXPECT_NEAR((hit.center - hit.point).norm(), radius, 1e-9);
    EXPECT_NEAR((hit.point - closest_point_on_triangle(hit.center, a, b, c).point).norm(), 0.0, 1e-12);
    if (radius > 0.0) {
      EXPECT_NEAR((hit.normal - (hit.center - hit.point) / radius).norm(), 0.0, 1e-6);
    }
  }
  EXPECT_GT(hits, kSweepTrials / 6);
  EXPECT_GT(misses, kSweepTrials / 6);
}

TEST(SweepSphereTriangle, FaceEdgeVertexAndBackFace) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);  // normal +z
  const double r = 0.1;
  // Straight down onto the face: contact when the centre is r above it.
  SweepHit h = sweep_sphere_triangle(Vec3(0.2, 0.2, 1.0), Vec3(0.2, 0.2, -1.0), r, a, b, c);
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.time, 0.9 / 2.0, 1e-12);
  EXPECT_NEAR((h.normal - Vec3::UnitZ()).norm(), 0.0, 1e-12);
  // From below: the back face, normal reversed.
  h = sweep_sphere_triangle(Vec3(0.2, 0.2, -1.0), Vec3(0.2, 0.2, 1.0), r, a, b, c);
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.time, 0.45, 1e-12);
  EXPECT_NEAR((h.normal + Vec3::UnitZ()).norm(), 0.0, 1e-12);
  // Horizontally into the edge x + y = 1 (hypotenuse) at height 0: the cylinder around it.
  const Vec3 edge_mid(0.5, 0.5, 0.0), out = Vec3(1, 1, 0).normalized();
  h = sweep_sphere_triangle(edge_mid + out, edge_mid - out, r, a, b, c);
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.time, 0.9 / 2.0, 1e-12);
  EXPECT_NEAR((h.point - edge_mid).norm(), 0.0, 1e-12);
  // Past vertex b along +x at a height below r: touches the vertex sphere.
  const double z = 0.06, x_contact = 1.0 + std::sqrt(r * r - z * z);
  h = sweep_sphere_triangle(Vec3(3.0, 0.0, z), Vec3(1.0, 0.0, z), r, a, b, c);
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.time, (3.0 - x_contact) / 2.0, 1e-12);
  EXPECT_NEAR((h.point - b).norm(), 0.0, 1e-12);
  // Misses: passing beside, stopping short.
  EXPECT_FALSE(sweep_sphere_triangle(Vec3(2, 2, 1), Vec3(2, 2, -1), r, a, b, c).hit);
  EXPECT_FALSE(sweep_sphere_triangle(Vec3(0.2, 0.2, 1.0), Vec3(0.2, 0.2, 0.2), r, a, b, c).hit);
  // Overlapping at the start: stopped at once when approaching, free when leaving or sliding.
  h = sweep_sphere_triangle(Vec3(0.2, 0.2, 0.05), Vec3(0.2, 0.2, -1.0), r, a, b, c);
  EXPECT_TRUE(h.hit);
  EXPECT_EQ(h.time, 0.0);
  EXPECT_FALSE(sweep_sphere_triangle(Vec3(0.2, 0.2, 0.05), Vec3(0.2, 0.2, 1.0), r, a, b, c).hit);
  EXPECT_FALSE(sweep_sphere_triangle(Vec3(0.2, 0.2, 0.05), Vec3(0.3, 0.2, 0.05), r, a, b, c).hit);
  // Radius zero: the segment through the face.
  h = sweep_sphere_triangle(Vec3(0.2, 0.2, 1.0), Vec3(0.2, 0.2, -1.0), 0.0, a, b, c);
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.time, 0.5, 1e-12);
  EXPECT_NEAR((h.normal - Vec3::UnitZ()).norm(), 0.0, 1e-12);
}

// --- closest point with side --------------------------------------------------------------

TEST(BruteForceSurfaceQuery, InsideFlagAgreesWithTheWindingNumberNearEdgesAndCorners) {
  mesh::TriMesh shapes[] = {mesh::box_surface(Vec3(0.1, 0.06, 0.04), 2), mesh::sphere(0.05, 1),
                            bumpy_sphere(0.05, 2, 9)};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const auto& m : shapes) {
    const BruteForceSurfaceQuery query(m.vertices, m.triangles);
    int inside = 0;
    for (int i = 0; i < kSidePoints; ++i) {
      // Points near a vertex or an edge midpoint, where a single face normal gives the wrong side.
      const auto& t = m.triangles[static_cast<std::size_t>(i) % m.triangles.size()];
      const Vec3 v0 = m.vertices[static_cast<std::size_t>(t[0])], v1 = m.vertices[static_cast<std::size_t>(t[1])];
      const Vec3 base = i % 2 == 0 ? v0 : Vec3(0.5 * (v0 + v1));
      const Vec3 p = base + 0.004 * Vec3(u(rng), u(rng), u(rng));
      const ClosestSurfacePoint cp = query.closest_point(p);
      ASSERT_TRUE(cp.found);
      const bool reference_inside = winding_number(p, m) > 0.5;
      EXPECT_EQ(cp.behind, reference_inside) << "point " << p.transpose();
      EXPECT_NEAR(cp.distance, distance_to(p, m), 1e-15);
      EXPECT_NEAR(cp.normal.norm(), 1.0, 1e-12);
      inside += reference_inside ? 1 : 0;
    }
    EXPECT_GT(inside, kSidePoints / 4);
    EXPECT_LT(inside, kSidePoints * 3 / 4);
  }
}

TEST(BruteForceSurfaceQuery, RejectsTrianglesThatReferToMissingVertices) {
  const std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<mesh::Triangle> bad = {{0, 1, 3}};
  EXPECT_THROW(BruteForceSurfaceQuery(x, bad), InputError);
  const std::vector<mesh::Triangle> negative = {{0, -1, 2}};
  EXPECT_THROW(BruteForceSurfaceQuery(x, negative), InputError);
  const BruteForceSurfaceQuery empty(x, {});
  EXPECT_FALSE(empty.closest_point(Vec3::Zero()).found);
  EXPECT_FALSE(empty.sweep_sphere(Vec3::Zero(), Vec3::Ones(), 0.1).hit);
  EXPECT_FALSE(empty.triangle(0).has_value());
}

// --- the plane solve ------------------------------------------------------------------------

TEST(ClosestPointOnPlanes, KeepsOnlyTheActivePlanesAndDetectsAnEmptyRegion) {
  // The positive octant: x ≥ 0, y ≥ 0, z ≥ 0.
  const ConstraintPlane planes[] = {{Vec3::UnitX(), 0.0}, {Vec3::UnitY(), 0.0}, {Vec3::UnitZ(), 0.0}};
  Vec3 x;
  ASSERT_TRUE(closest_point_on_planes(Vec3(1, 2, 3), planes, 3, 1e-12, x));
  EXPECT_NEAR((x - Vec3(1, 2, 3)).norm(), 0.0, 1e-15);  // feasible goal: itself
  ASSERT_TRUE(closest_point_on_planes(Vec3(-1, 2, 3), planes, 3, 1e-12, x));
  EXPECT_NEAR((x - Vec3(0, 2, 3)).norm(), 0.0, 1e-15);
  ASSERT_TRUE(closest_point_on_planes(Vec3(-1, -2, 3), planes, 3, 1e-12, x));
  EXPECT_NEAR((x - Vec3(0, 0, 3)).norm(), 0.0, 1e-15);
  ASSERT_TRUE(closest_point_on_planes(Vec3(-1, -2, -3), planes, 3, 1e-12, x));
  EXPECT_NEAR(x.norm(), 0.0, 1e-15);
  // A wedge of two planes at 45°: the goal below both projects onto their common line.
  const ConstraintPlane wedge[] = {{Vec3::UnitZ(), 0.0}, {Vec3(-1, 0, 1).normalized(), 0.0}};
  ASSERT_TRUE(closest_point_on_planes(Vec3(0.5, 0.3, -2.0), wedge, 2, 1e-12, x));
  EXPECT_NEAR((x - Vec3(0, 0.3, 0)).norm(), 0.0, 1e-12);
  // Facing parallel planes with nothing between them.
  const ConstraintPlane slab[] = {{Vec3::UnitZ(), 1.0}, {-Vec3::UnitZ(), 0.0}};  // z ≥ 1 and z ≤ 0
  EXPECT_FALSE(closest_point_on_planes(Vec3::Zero(), slab, 2, 1e-12, x));
}

// --- sliding ---------------------------------------------------------------------------------

/// A large square floor at z = 0, facing +z (an open sheet of triangles).
mesh::TriMesh floor_plate() { return mesh::grid_plate(1.0, 1.0, 4, 4); }

TEST(Proxy, OnAPlaneSitsAboveTheGoalWithTheSpringForceAlongTheNormal) {
  const mesh::TriMesh floor = floor_plate();
  const BruteForceSurfaceQuery surface(floor.vertices, floor.triangles);
  for (const double radius : {0.0, 0.004}) {
    ProxyParams params = params_with(radius);
    params.closed_surfaces = false;
    ProxyState state = make_proxy_state(Vec3(0.01, 0.02, 0.05));
    ProxyResult res = update_proxy(params, state, Vec3(0.03, -0.02, 0.04), Vec3::Zero(), kDt, surface);
    EXPECT_FALSE(res.in_contact);
    EXPECT_EQ(res.force, Vec3::Zero());
    EXPECT_EQ(res.position, Vec3(0.03, -0.02, 0.04));
    // One fast jump to 7 mm below the floor.
    const Vec3 goal(0.123, 0.0456, -0.007);
    res = update_proxy(params, state, goal, Vec3::Zero(), kDt, surface);
    ASSERT_TRUE(res.in_contact);
    EXPECT_NEAR(res.position.x(), goal.x(), 1e-12);
    EXPECT_NEAR(res.position.y(), goal.y(), 1e-12);
    EXPECT_GE(res.position.z(), radius + 0.5 * params.skin);
    EXPECT_LE(res.position.z(), radius + 3.0 * params.skin);
    // k times the depth of the goal below the plane (plus r: the spring ends at the centre).
    EXPECT_NEAR(res.force.z(), params.stiffness * (0.007 + radius), params.stiffness * 3.0 * params.skin);
    EXPECT_NEAR(res.force.head<2>().norm(), 0.0, 1e-9);
    EXPECT_NEAR((res.contact_normal - Vec3::UnitZ()).norm(), 0.0, 1e-9);
    EXPECT_NEAR((res.contact_point - Vec3(goal.x(), goal.y(), 0.0)).norm(), 0.0, 1e-12);
    EXPECT_EQ(res.friction, FrictionState::slip);  // frictionless: free to slide
    EXPECT_GE(res.triangle, 0);
    ASSERT_EQ(state.plane_count, 1);
    EXPECT_NEAR((state.planes[0].normal - Vec3::UnitZ()).norm(), 0.0, 1e-12);
    // Sliding while pressed: the proxy follows the goal's projection.
    res = update_proxy(params, state, goal + Vec3(0.05, -0.1, -0.002), Vec3::Zero(), kDt, surface);
    EXPECT_NEAR(res.position.x(), goal.x() + 0.05, 1e-12);
    EXPECT_NEAR(res.position.y(), goal.y() - 0.1, 1e-12);
    EXPECT_NEAR(res.depth, 0.009 + radius, 3.0 * params.skin);
  }
}

/// Floor z = 0 and walls x = 0 and y = 0 over the unit box corner, facing into the positive
/// octant: a concave corner of three planes.
mesh::TriMesh corner_soup() {
  mesh::TriMesh m;
  const Mat3 to_wall_x = Eigen::AngleAxisd(kPi / 2, Vec3::UnitY()).toRotationMatrix();   // +z → +x
  const Mat3 to_wall_y = Eigen::AngleAxisd(-kPi / 2, Vec3::UnitX()).toRotationMatrix();  // +z → +y
  const mesh::TriMesh plate = mesh::grid_plate(1.0, 1.0, 3, 3);  // [−½, ½]², normal +z
  append(m, transformed(plate, Mat3::Identity(), Vec3(0.5, 0.5, 0.0)));
  append(m, transformed(plate, to_wall_x, Vec3(0.0, 0.5, 0.5)));
  append(m, transformed(plate, to_wall_y, Vec3(0.5, 0.0, 0.5)));
  return m;
}

TEST(Proxy, InAConcaveCornerSitsAtTheCornerPointClosestToTheGoal) {
  const mesh::TriMesh corner = corner_soup();
  // The soup's faces point into the positive octant.
  for (std::size_t t = 0; t < corner.triangles.size(); ++t) {
    const Vec3 n = corner.face_normal(t);
    EXPECT_NEAR(n.maxCoeff(), 1.0, 1e-12);
  }
  const BruteForceSurfaceQuery surface(corner.vertices, corner.triangles);
  for (const double radius : {0.0, 0.01}) {
    ProxyParams params = params_with(radius);
    params.closed_surfaces = false;
    const double c = radius + 2.0 * params.skin;  // where the configuration-space planes are
    const double tol = 2.0 * params.skin;
    struct Case {
      Vec3 goal, expected;
    };
    const Case cases[] = {
        {Vec3(0.4, 0.3, -0.2), Vec3(0.4, 0.3, c)},    // floor only
        {Vec3(-0.1, 0.3, -0.2), Vec3(c, 0.3, c)},     // floor and wall x: their common line
        {Vec3(-0.1, -0.2, -0.3), Vec3(c, c, c)},      // all three: the corner point
        {Vec3(-0.3, -0.05, 0.4), Vec3(c, c, 0.4)},    // two walls, above the floor
    };
    for (const Case& k : cases) {
      // From well inside the free octant, in a single update.
      ProxyState state = make_proxy_state(Vec3(0.5, 0.5, 0.5));
      const ProxyResult res = update_proxy(params, state, k.goal, Vec3::Zero(), kDt, surface);
      ASSERT_TRUE(res.in_contact);
      EXPECT_NEAR((res.position - k.expected).norm(), 0.0, tol) << "goal " << k.goal.transpose();
      EXPECT_NEAR((res.force - params.stiffness * (res.position - k.goal)).norm(), 0.0, 1e-12);
    }
  }
}

TEST(Proxy, DraggedInsideAFacetedSphereItFollowsTheClosestSurfacePointAcrossFacets) {
  const mesh::TriMesh ball = mesh::sphere(0.05, 3);
  const BruteForceSurfaceQuery surface(ball.vertices, ball.triangles);
  for (const double radius : {0.0, 0.003}) {
    const ProxyParams params = params_with(radius);
    ProxyState state = make_proxy_state(Vec3(0.0, 0.0, 0.08));
    double worst_offset = 0.0, mean_offset = 0.0, worst_height = 0.0, worst_angle = 0.0;
    const Vec3 axis = Vec3(1, 2, 0.5).normalized();
    for (int k = 0; k <= 500; ++k) {
      // 5 mm deep, along a great circle at 0.5 mm per update (four radians in all).
      const Vec3 goal = Eigen::AngleAxisd(0.01 * k, axis) * Vec3(0.0, 0.0, 0.045);
      const ProxyResult res = update_proxy(params, state, goal, Vec3::Zero(), kDt, surface);
      ASSERT_TRUE(res.in_contact) << k;
      if (k < 10) continue;  // arriving from above
      // The spring reaches from the goal to the closest point of the surface grown by r (for
      // a convex solid and a goal inside, a point of one of the faces pushed out by r).
      Vec3 expected = Vec3::Constant(1.0);
      for (std::size_t t = 0; t < ball.triangles.size(); ++t) {
        const Vec3 shift = radius * ball.face_normal(t);
        const auto& tri = ball.triangles[t];
        const Vec3 q = closest_point_on_triangle(goal, ball.vertices[static_cast<std::size_t>(tri[0])] + shift,
                                                 ball.vertices[static_cast<std::size_t>(tri[1])] + shift,
                                                 ball.vertices[static_cast<std::size_t>(tri[2])] + shift)
                           .point;
        if ((q - goal).norm() < (expected - goal).norm()) expected = q;
      }
      const double offset = (res.position - expected).norm();
      worst_offset = std::max(worst_offset, offset);
      mean_offset += offset / 490.0;
      worst_height = std::max(worst_height, distance_to(res.position, ball) - radius);
      // Frictionless: the force is normal to the surface where the proxy touches it (within
      // the normal cone of an edge or a vertex: up to about 0.2 rad between facets around a vertex).
      worst_angle = std::max(worst_angle, std::acos(std::min(1.0, res.force.normalized().dot(res.contact_normal))));
    }
    // The proxy is a local minimum: it stays on a facet while the goal's projection is on it,
    // so it trails the global closest point by a fraction of a facet (6.6 mm) at transitions.
    EXPECT_LT(worst_offset, 2e-3) << "radius " << radius;
    EXPECT_LT(mean_offset, 3e-4) << "radius " << radius;
    EXPECT_LT(worst_height, 1e-4) << "radius " << radius;
    EXPECT_LT(worst_angle, 0.25) << "radius " << radius;
  }
}

// --- friction --------------------------------------------------------------------------------

/// Presses the goal straight down (−z, like gravity) into a plane tilted by theta about y,
/// then holds it; returns the last result.
struct PressOutcome {
  ProxyResult last;
  bool touched = false;
  Vec3 first_touch = Vec3::Zero();
  int slips = 0;
};

PressOutcome press_into_tilted_plane(double theta, const ProxyParams& params) {
  const Mat3 tilt = Eigen::AngleAxisd(theta, Vec3::UnitY()).toRotationMatrix();
  const mesh::TriMesh plane = transformed(floor_plate(), tilt);
  const BruteForceSurfaceQuery surface(plane.vertices, plane.triangles);
  PressOutcome out;
  ProxyState state = make_proxy_state(Vec3(0.0, 0.0, 0.01));
  const double step = 1e-4;
  for (int i = 0; i <= 150; ++i) {  // down to 5 mm below the plane's surface at the axis
    const Vec3 goal(0.0, 0.0, 0.01 - step * std::min(i, 150));
    out.last = update_proxy(params, state, goal, Vec3(0, 0, i < 150 ? -step / kDt : 0.0), kDt, surface);
    if (out.last.in_contact && !out.touched) {
      out.touched = true;
      out.first_touch = out.last.position;
    }
    if (out.last.friction == FrictionState::slip) ++out.slips;
  }
  for (int i = 0; i < 50; ++i)
    out.last = update_proxy(params, state, Vec3(0, 0, -0.005), Vec3::Zero(), kDt, surface);
  return out;
}

TEST(ProxyFriction, StaticConeHoldsOnAGentleSlopeAndSlipsToTheKineticConeOnASteepOne) {
  const ProxyParams params = params_with(0.0, 0.5, 0.3);
  for (const double theta_deg : {10.0, 20.0, 25.0, 30.0, 35.0, 45.0}) {
    const double theta = theta_deg * kPi / 180.0;
    const Vec3 normal(std::sin(theta), 0.0, std::cos(theta));
    const PressOutcome o = press_into_tilted_plane(theta, params);
    ASSERT_TRUE(o.last.in_contact);
    const Vec3 f = o.last.force;
    const double angle_to_normal = std::acos(std::clamp(f.normalized().dot(normal), -1.0, 1.0));
    EXPECT_EQ(o.last.friction, FrictionState::stick) << theta_deg << "°: at rest it sticks";
    if (std::tan(theta) < params.static_friction) {
      // Held where it landed: the spring pulls (nearly) straight up, at θ from the normal.
      // The landing point is off the vertical by at most one 0.1 mm step's projection, which
      // tilts the force by up to 0.01 rad at the final 5 mm depth.
      EXPECT_EQ(o.slips, 0) << theta_deg;
      EXPECT_LT((o.last.position - o.first_touch).norm(), 1e-9) << theta_deg;
      EXPECT_NEAR(angle_to_normal, theta, 0.012) << theta_deg;
    } else {
      // Slid downhill (+x, −z along the plane) until the force sits on the kinetic cone.
      EXPECT_GT(o.slips, 10) << theta_deg;
      EXPECT_GT(o.last.position.x() - o.first_touch.x(), 1e-4) << theta_deg;
      EXPECT_NEAR(angle_to_normal, std::atan(params.kinetic_friction), 1e-6) << theta_deg;
    }
  }
}

TEST(ProxyFriction, StickThenSlipThenStickWhileDraggingAlongAPlane) {
  const mesh::TriMesh floor = floor_plate();
  const BruteForceSurfaceQuery surface(floor.vertices, floor.triangles);
  ProxyParams params = params_with(0.0, 0.5, 0.3);
  params.closed_surfaces = false;
  ProxyState state = make_proxy_state(Vec3(0, 0, 0.01));
  const double depth = 0.002;
  ProxyResult res = update_proxy(params, state, Vec3(0, 0, -depth), Vec3::Zero(), kDt, surface);
  ASSERT_TRUE(res.in_contact);
  const Vec3 anchor = res.position;
  const double step = 4.7e-5;  // 4.7 cm/s at 1 kHz; the static cone μs·depth = 1 mm falls between steps
  int first_slip = -1;
  for (int i = 1; i <= 100; ++i) {
    const double dx = step * i;
    res = update_proxy(params, state, Vec3(dx, 0, -depth), Vec3(step / kDt, 0, 0), kDt, surface);
    if (dx < params.static_friction * depth) {
      EXPECT_EQ(res.friction, FrictionState::stick) << i;
      EXPECT_LT((res.position - anchor).norm(), 1e-9) << i;
      // The tangential force is the spring's: k·dx backward.
      EXPECT_NEAR(res.force.x(), -params.stiffness * dx, 1e-9);
    } else {
      if (first_slip < 0) first_slip = i;
      EXPECT_EQ(res.friction, FrictionState::slip) << i;
      // Dragged behind the goal on the kinetic cone: |Ft| = μk·Fn.
      EXPECT_NEAR(dx - res.position.x(), params.kinetic_friction * res.depth, 1e-9) << i;
      EXPECT_NEAR(-res.force.x() / res.force.z(), params.kinetic_friction, 1e-6) << i;
    }
  }
  EXPECT_EQ(first_slip, 22);  // 21 steps = 0.987 mm < 1 mm < 22 steps
  // The goal stops: the proxy sticks where it is, and stays.
  const Vec3 held = res.position;
  for (int i = 0; i < 20; ++i) {
    res = update_proxy(params, state, Vec3(step * 100, 0, -depth), Vec3::Zero(), kDt, surface);
    EXPECT_EQ(res.friction, FrictionState::stick);
    EXPECT_LT((res.position - held).norm(), 1e-9);
  }
  // Moving the goal back past the proxy: held while within the static cone on the other
  // side (proxy 0.6 mm behind the goal → 0.1 mm ahead), slipping beyond it (2.4 mm ahead).
  res = update_proxy(params, state, Vec3(step * 100 - 0.0005, 0, -depth), Vec3::Zero(), kDt, surface);
  EXPECT_EQ(res.friction, FrictionState::stick);
  EXPECT_LT((res.position - held).norm(), 1e-9);
  res = update_proxy(params, state, Vec3(step * 100 - 0.003, 0, -depth), Vec3::Zero(), kDt, surface);
  EXPECT_EQ(res.friction, FrictionState::slip);
  EXPECT_NEAR(res.position.x() - (step * 100 - 0.003), params.kinetic_friction * res.depth, 1e-9);
  // Lifting off ends the contact and the friction with it.
  res = update_proxy(params, state, Vec3(0, 0, 0.01), Vec3::Zero(), kDt, surface);
  EXPECT_FALSE(res.in_contact);
  EXPECT_EQ(res.friction, FrictionState::none);
  EXPECT_EQ(res.force, Vec3::Zero());
}

TEST(ProxyFriction, SlipDampingApproachesTheKineticConeAtTheSpeedOfTheMotionEquation) {
  const mesh::TriMesh floor = floor_plate();
  const BruteForceSurfaceQuery surface(floor.vertices, floor.triangles);
  ProxyParams params = params_with(0.0, 0.5, 0.3);
  params.closed_surfaces = false;
  params.slip_damping = 4.0;  // k·dt/b_p = 1000·0.001/4 = ¼ of the way per update
  ProxyState state = make_proxy_state(Vec3(0, 0, 0.01));
  const double depth = 0.002;
  ProxyResult res = update_proxy(params, state, Vec3(0, 0, -depth), Vec3::Zero(), kDt, surface);
  const double start_x = res.position.x();
  const double dx = 0.005;  // well outside the static cone
  res = update_proxy(params, state, Vec3(dx, 0, -depth), Vec3::Zero(), kDt, surface);
  ASSERT_EQ(res.friction, FrictionState::slip);
  const double cone_x = dx - params.kinetic_friction * res.depth;
  // b_p·ẋ = |Ft| − μk·Fn with |Ft| = k·lag: one explicit step covers k·dt/b_p of the gap.
  EXPECT_NEAR(res.position.x() - start_x, 0.25 * (cone_x - start_x), 1e-9);
  // It keeps slipping, closer each update, and sticks once it reaches the cone.
  double gap = cone_x - res.position.x();
  for (int i = 0; i < 200 && res.friction == FrictionState::slip; ++i) {
    res = update_proxy(params, state, Vec3(dx, 0, -depth), Vec3::Zero(), kDt, surface);
    const double new_gap = cone_x - res.position.x();
    EXPECT_LE(new_gap, gap + 1e-12);
    gap = new_gap;
  }
  EXPECT_EQ(res.friction, FrictionState::stick);
  EXPECT_NEAR(dx - res.position.x(), params.kinetic_friction * res.depth, 1e-5);
}

// --- deforming surfaces ----------------------------------------------------------------------

TEST(ProxyDeforming, APlaneMovingUpThroughTheProxyPushesItOutNeverInside) {
  for (const bool closed_slab : {false, true}) {
    // An open sheet, or a closed slab 0.1 mm thick rising 1 mm per update (ten thicknesses).
    const mesh::TriMesh rest = closed_slab ? mesh::box_surface(Vec3(0.2, 0.2, 1e-4), 1) : floor_plate();
    const double top = closed_slab ? 0.5e-4 : 0.0;
    mesh::TriMesh moving = rest;
    const BruteForceSurfaceQuery surface(moving.vertices, moving.triangles);
    for (const double radius : {0.0, 0.003}) {
      ProxyParams params = params_with(radius, 0.4, 0.3);
      params.closed_surfaces = closed_slab;
      ProxyState state = make_proxy_state(Vec3(0.01, 0.02, 0.0));
      int pushes = 0;
      for (int i = 0; i <= 60; ++i) {
        const double lift = -0.02 + 0.001 * i;  // the surface rises from 2 cm below the goal
        for (std::size_t v = 0; v < rest.vertices.size(); ++v) moving.vertices[v] = rest.vertices[v] + Vec3(0, 0, lift);
        const ProxyResult res = update_proxy(params, state, Vec3(0.01, 0.02, 0.0), Vec3::Zero(), kDt, surface);
        pushes += res.pushed_out ? 1 : 0;
        EXPECT_GE(res.position.z() - (top + lift), radius + 0.5 * params.skin) << "update " << i;
        if (closed_slab) {
          EXPECT_LT(winding_number(res.position, moving), 0.5);
        }
        if (res.in_contact) {
          EXPECT_GT(res.force.z(), 0.0);
        }
        // Carried up with the surface, never left behind it.
        EXPECT_NEAR(res.position.x(), 0.01, 1e-9);
        EXPECT_NEAR(res.position.y(), 0.02, 1e-9);
      }
      EXPECT_GT(pushes, 30);
    }
  }
}

TEST(ProxyDeforming, AStickingProxyIsCarriedByTheSurfaceUnderIt) {
  const mesh::TriMesh rest = floor_plate();
  mesh::TriMesh moving = rest;
  const BruteForceSurfaceQuery surface(moving.vertices, moving.triangles);
  ProxyParams params = params_with(0.0, 0.8, 0.6);
  params.closed_surfaces = false;
  ProxyState state = make_proxy_state(Vec3(0, 0, 0.01));
  const double depth = 0.003;
  ProxyResult res = update_proxy(params, state, Vec3(0, 0, -depth), Vec3::Zero(), kDt, surface);
  const Vec3 touch = res.position;
  // The sheet slides sideways by 1 mm (inside the static cone μs·depth = 2.4 mm): the proxy
  // goes with it and the device feels the drag.
  for (int i = 1; i <= 10; ++i) {
    for (std::size_t v = 0; v < rest.vertices.size(); ++v) moving.vertices[v] = rest.vertices[v] + Vec3(1e-4 * i, 0, 0);
    res = update_proxy(params, state, Vec3(0, 0, -depth), Vec3::Zero(), kDt, surface);
    EXPECT_EQ(res.friction, FrictionState::stick);
    EXPECT_NEAR(res.position.x() - touch.x(), 1e-4 * i, 1e-9);
    EXPECT_NEAR(res.force.x(), params.stiffness * 1e-4 * i, 1e-6);
  }
}

TEST(ProxyDeforming, AReplacedSurfaceIsNoMotionForTheDamping) {
  // A proxy resting on a sheet 3 mm above the goal, which a newer model puts 2 mm lower: the
  // proxy falls with it in one update. As motion at 2 m/s, a 0.2 N·s/m damper takes 0.4 N off
  // the 0.2 N spring and pulls the hand into the tissue; as a replaced model the spring alone
  // is rendered.
  for (const bool replaced : {false, true}) {
    const mesh::TriMesh rest = floor_plate();
    mesh::TriMesh moving = rest;
    const BruteForceSurfaceQuery surface(moving.vertices, moving.triangles);
    ProxyParams params = params_with(0.0, 0.0, 0.0);
    params.closed_surfaces = false;
    params.stiffness = 200.0;
    params.damping = 0.2;
    ProxyState state = make_proxy_state(Vec3(0, 0, 0.01));
    const Vec3 goal(0, 0, -0.003);
    for (int i = 0; i < 3; ++i) (void)update_proxy(params, state, goal, Vec3::Zero(), kDt, surface);
    const double before = state.position.z();
    for (std::size_t v = 0; v < rest.vertices.size(); ++v) moving.vertices[v] = rest.vertices[v] + Vec3(0, 0, -0.002);
    state.surface_replaced = replaced;
    const ProxyResult res = update_proxy(params, state, goal, Vec3::Zero(), kDt, surface);
    EXPECT_NEAR(res.position.z(), -0.002, 1e-5);  // on the sheet (within the proxy's skin)
    const double spring = 200.0 * (res.position.z() - goal.z());
    if (replaced) {
      EXPECT_NEAR(res.force.z(), spring, 1e-9);
      EXPECT_GT(res.force.z(), 0.19);
      EXPECT_FALSE(state.surface_replaced);  // one update only
    } else {
      EXPECT_NEAR(res.force.z(), spring + 0.2 * (res.position.z() - before) / kDt, 1e-9);
      EXPECT_LT(res.force.z(), -0.19);
    }
  }
}

// --- blending planes between surface updates ------------------------------------------------

TEST(PlaneBlending, TurnsAboutTheCommonLineAndTranslatesParallelPlanes) {
  const ConstraintPlane floor{Vec3::UnitZ(), 0.0};
  const ConstraintPlane tilted{Vec3(1, 0, 1).normalized(), 0.0};
  const ConstraintPlane raised{Vec3::UnitZ(), 0.002};
  EXPECT_EQ(blend_planes(floor, tilted, 0.0).normal, floor.normal);
  EXPECT_EQ(blend_planes(floor, tilted, 1.0).normal, tilted.normal);
  const ConstraintPlane half = blend_planes(floor, tilted, 0.5);
  EXPECT_NEAR(half.normal.norm(), 1.0, 1e-12);
  EXPECT_NEAR(std::acos(half.normal.dot(Vec3::UnitZ())), kPi / 8, 1e-12);
  EXPECT_NEAR(half.signed_distance(Vec3(0, 0.3, 0)), 0.0, 1e-15);  // the y axis lies on both
  EXPECT_NEAR(blend_planes(floor, raised, 0.25).offset, 0.0005, 1e-15);
  // Opposite planes hand over instead of vanishing.
  const ConstraintPlane ceiling{-Vec3::UnitZ(), 0.0};
  EXPECT_EQ(blend_planes(floor, ceiling, 0.5).normal, ceiling.normal);
  EXPECT_THROW(PlaneInterpolator(-1.0), InputError);
}

TEST(PlaneBlending, APlaneJumpAtTheSimulationRateGivesNoForceStep) {
  const ProxyParams params = params_with(0.0);  // a half-space is a closed solid
  const double blend_time = 0.04;  // one 25 Hz simulation period
  PlaneInterpolator smooth(blend_time);
  EXPECT_FALSE(smooth.has_plane());
  smooth.set_target({Vec3::UnitZ(), 0.0}, 0.0);
  EXPECT_EQ(smooth.at(0.0).offset, 0.0);  // the first plane is shown at once
  ProxyState state = make_proxy_state(Vec3(0, 0, 0.01));
  const Vec3 goal(0, 0, -0.003);
  double last_force = 0.0, largest_step = 0.0;
  for (int k = 0; k <= 200; ++k) {
    const double t = k * kDt;
    if (k == 50) smooth.set_target({Vec3::UnitZ(), 0.002}, t);      // the surface rose 2 mm
    if (k == 70) smooth.set_target({Vec3(0.1, 0, 1).normalized(), 0.001}, t);  // and again, mid-blend
    const ConstraintPlane plane = smooth.at(t);
    const HalfSpaceQuery surface(plane.normal, plane.offset);
    const ProxyResult res = update_proxy(params, state, goal, Vec3::Zero(), kDt, surface);
    ASSERT_TRUE(res.in_contact);
    if (k > 0) largest_step = std::max(largest_step, std::abs(res.force.norm() - last_force));
    last_force = res.force.norm();
    if (k == 69) {
      // Continuity across a new target that arrives mid-blend.
      const ConstraintPlane before = smooth.at(0.07);
      PlaneInterpolator copy = smooth;
      copy.set_target({Vec3(0.1, 0, 1).normalized(), 0.001}, 0.07);
      EXPECT_NEAR((copy.at(0.07).normal - before.normal).norm(), 0.0, 1e-15);
      EXPECT_NEAR(copy.at(0.07).offset, before.offset, 1e-15);
    }
  }
  // A 2 mm step at k = 1000 N/m would be 2 N in one update; blended over 40 updates it is ≤ 2/40 N
  // per update (plus the second retarget's share).
  EXPECT_GT(largest_step, 0.0);
  EXPECT_LT(largest_step, 0.1);
  EXPECT_NEAR(smooth.at(1.0).offset, 0.001, 1e-15);
}

// --- robustness: never inside ---------------------------------------------------------------

struct Shape {
  const char* name;
  mesh::TriMesh surface;   ///< everything the proxy touches
  mesh::TriMesh boundary;  ///< the closed surface it must stay outside of
  double size;             ///< extent of the object [m]
};

std::vector<Shape> shapes() {
  std::vector<Shape> out;
  out.push_back({"sphere", mesh::sphere(0.05, 2), {}, 0.1});
  out.push_back({"box", mesh::box_surface(Vec3(0.08, 0.05, 0.03), 2), {}, 0.08});
  out.push_back({"thin slab", mesh::box_surface(Vec3(0.06, 0.06, 1e-4), 1), {}, 0.06});
  out.push_back({"bumpy sphere", bumpy_sphere(0.04, 2, 4), {}, 0.1});
  // Two-layer skin over a nodule: outer skin surface, the layer below it 3 mm deeper, and a
  // nodule 6 mm across inside, all closed and outward.
  Shape skin{"two-layer skin over a nodule", mesh::sphere(0.03, 2), mesh::sphere(0.03, 2), 0.06};
  append(skin.surface, mesh::sphere(0.027, 2));
  append(skin.surface, mesh::sphere(0.003, 1), Vec3(0.01, 0.005, 0.012));
  out.push_back(std::move(skin));
  for (Shape& s : out)
    if (s.boundary.triangles.empty()) s.boundary = s.surface;
  return out;
}

TEST(ProxyRobustness, NeverEndsInsideOverFastRandomTrajectories) {
#ifdef TACTUS_SANITIZED
  constexpr int kUpdatesPerShape = 2000;  // 10,000 updates: shrunk under sanitizers
#else
  constexpr int kUpdatesPerShape = 20000;  // 100,000 updates over the five shapes
#endif
  constexpr int kUpdatesPerTrajectory = 50;
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  for (const Shape& shape : shapes()) {
    const BruteForceSurfaceQuery surface(shape.surface.vertices, shape.surface.triangles);
    const Aabb box = shape.boundary.bounds();
    int contacts = 0, inside_goals = 0, trajectory = 0;
    for (int done = 0; done < kUpdatesPerShape; done += kUpdatesPerTrajectory, ++trajectory) {
      // Vary the proxy: point or sphere, with or without friction.
      const double radius = trajectory % 2 == 0 ? 0.0 : 0.02 * shape.size;
      const ProxyParams params = trajectory % 4 < 2 ? params_with(radius) : params_with(radius, 0.6, 0.4);
      Vec3 start;
      do start = 2.0 * shape.size * Vec3(u(rng), u(rng), u(rng));
      while (distance_to(start, shape.surface) < radius + params.skin || winding_number(start, shape.boundary) > 0.5);
      ProxyState state = make_proxy_state(start);
      Vec3 goal = start;
      for (int k = 0; k < kUpdatesPerTrajectory; ++k) {
        const double pick = unit(rng);
        if (pick < 0.4) {
          goal = 2.0 * shape.size * Vec3(u(rng), u(rng), u(rng));  // a jump of up to several sizes
        } else if (pick < 0.6) {
          // Into the object's bounding box: mostly inside it (inside the slab, between the layers).
          goal = box.center() + 0.5 * box.size().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
        } else {
          goal += 0.05 * shape.size * Vec3(u(rng), u(rng), u(rng));  // dragging along
        }
        inside_goals += winding_number(goal, shape.boundary) > 0.5 ? 1 : 0;
        const ProxyResult res = update_proxy(params, state, goal, Vec3::Zero(), kDt, surface);
        contacts += res.in_contact ? 1 : 0;
        // The reference: outside the closed boundary, and the sphere clear of every triangle.
        ASSERT_LT(winding_number(res.position, shape.boundary), 0.5)
            << shape.name << ", trajectory " << trajectory << ", update " << k;
        ASSERT_GE(distance_to(res.position, shape.surface), radius + 0.5 * params.skin)
            << shape.name << ", trajectory " << trajectory << ", update " << k;
        // A static surface never needs the push-out: the sweeps alone kept the proxy clear.
        ASSERT_FALSE(res.pushed_out) << shape.name << ", trajectory " << trajectory << ", update " << k;
        ASSERT_TRUE(res.force.allFinite());
      }
    }
    EXPECT_GT(contacts, kUpdatesPerShape / 5) << shape.name;
    EXPECT_GT(inside_goals, kUpdatesPerShape / 20) << shape.name;
  }
}

// --- robustness on deforming closed meshes ----------------------------------------------------

/// A closed surface whose vertices move smoothly between proxy updates; the proxy queries it
/// through a BVH refitted after every move.
struct DeformingShape {
  const char* name;
  mesh::TriMesh rest;                 ///< everything the proxy touches, at rest
  std::size_t boundary_triangles;     ///< the first ones: the closed surface to stay outside of
  double size;                        ///< extent of the object [m]
  std::function<Vec3(const Vec3&, int)> at;  ///< where a rest vertex is at update `step`
};

std::vector<DeformingShape> deforming_shapes() {
  std::vector<DeformingShape> out;
  // A sphere breathing anisotropically by ±15 % of its 5 cm radius every 50 updates: the
  // surface moves up to about 1 mm per update (1 m/s).
  out.push_back({"breathing sphere", mesh::sphere(0.05, 2), 0, 0.1, [](const Vec3& x, int step) {
                   const double phase = 2.0 * kPi * step / 50.0;
                   const Vec3 scale(1.0 + 0.15 * std::sin(phase), 1.0 + 0.15 * std::sin(phase + 2.0),
                                    1.0 + 0.15 * std::sin(phase + 4.0));
                   return Vec3(scale.cwiseProduct(x));
                 }});
  // The two-layer skin over a nodule, dented: a Gaussian dent up to 4 mm deep and 12 mm wide
  // presses in and releases every 40 updates while its centre wanders over the skin, and the
  // whole swells by ±3 % every 30 updates. Every layer moves with the same smooth field
  // (gradient below 0.4), so the layers never cross.
  DeformingShape skin{"dented two-layer skin over a nodule", mesh::sphere(0.03, 2), 0, 0.06,
                      [](const Vec3& x, int step) {
                        const double phase = 2.0 * kPi * step / 40.0;
                        const double depth = 0.004 * 0.5 * (1.0 - std::cos(phase));
                        const double turn = 0.01 * step;
                        const Vec3 axis =
                            Vec3(std::cos(turn), std::sin(turn), 0.4 * std::sin(0.7 * turn)).normalized();
                        const double w = 0.012;
                        const double swell = 1.0 + 0.03 * std::sin(2.0 * kPi * step / 30.0);
                        return Vec3(swell * x - depth * std::exp(-(x - 0.03 * axis).squaredNorm() / (w * w)) * axis);
                      }};
  skin.boundary_triangles = skin.rest.triangles.size();
  append(skin.rest, mesh::sphere(0.027, 2));
  append(skin.rest, mesh::sphere(0.003, 1), Vec3(0.01, 0.005, 0.012));
  out.push_back(std::move(skin));
  for (DeformingShape& s : out)
    if (s.boundary_triangles == 0) s.boundary_triangles = s.rest.triangles.size();
  return out;
}

TEST(ProxyRobustness, NeverEndsInsideAClosedMeshThatDeformsBetweenUpdates) {
#ifdef TACTUS_SANITIZED
  constexpr int kUpdatesPerShape = 5000;  // 10,000 updates: shrunk under sanitizers
#else
  constexpr int kUpdatesPerShape = 50000;  // 100,000 updates over the two shapes
#endif
  constexpr int kUpdatesPerTrajectory = 50;
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  for (const DeformingShape& shape : deforming_shapes()) {
    mesh::TriMesh moving = shape.rest;
    mesh::TriMesh boundary = shape.rest;
    boundary.triangles.resize(shape.boundary_triangles);
    int step = 0;
    const auto deform = [&] {
      for (std::size_t v = 0; v < shape.rest.vertices.size(); ++v)
        moving.vertices[v] = shape.at(shape.rest.vertices[v], step);
      boundary.vertices = moving.vertices;
      ++step;
    };
    deform();
    TriangleBvh tree(moving.vertices, moving.triangles);
    const BvhSurfaceQuery surface(tree);
    const Aabb box = boundary.bounds();
    int contacts = 0, pushes = 0, trajectory = 0;
    for (int done = 0; done < kUpdatesPerShape; done += kUpdatesPerTrajectory, ++trajectory) {
      const double radius = trajectory % 2 == 0 ? 0.0 : 0.02 * shape.size;
      const ProxyParams params = trajectory % 4 < 2 ? params_with(radius) : params_with(radius, 0.6, 0.4);
      Vec3 start;
      do start = 2.0 * shape.size * Vec3(u(rng), u(rng), u(rng));
      while (distance_to(start, moving) < radius + params.skin || winding_number(start, boundary) > 0.5);
      ProxyState state = make_proxy_state(start);
      Vec3 goal = start;
      for (int k = 0; k < kUpdatesPerTrajectory; ++k) {
        // Jumps, goals inside the object, holds (the surface moves under a still hand) and drags.
        const double pick = unit(rng);
        if (pick < 0.2) {
          goal = 2.0 * shape.size * Vec3(u(rng), u(rng), u(rng));
        } else if (pick < 0.5) {
          goal = box.center() + 0.5 * box.size().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
        } else if (pick < 0.8) {
          goal += 0.05 * shape.size * Vec3(u(rng), u(rng), u(rng));
        }
        // The simulation moved the surface since the last update; the tree follows it.
        deform();
        tree.refit(moving.vertices);
        const ProxyResult res = update_proxy(params, state, goal, Vec3::Zero(), kDt, surface);
        contacts += res.in_contact ? 1 : 0;
        pushes += res.pushed_out ? 1 : 0;
        ASSERT_LT(winding_number(res.position, boundary), 0.5)
            << shape.name << ", trajectory " << trajectory << ", update " << k << ", step " << step;
        ASSERT_GE(distance_to(res.position, moving), radius + 0.5 * params.skin)
            << shape.name << ", trajectory " << trajectory << ", update " << k << ", step " << step;
        ASSERT_TRUE(res.force.allFinite());
      }
    }
    EXPECT_GT(contacts, kUpdatesPerShape / 5) << shape.name;
    // The surface came to the proxy often: the push-out, not the sweep, kept it outside.
    EXPECT_GT(pushes, kUpdatesPerShape / 25) << shape.name;
  }
}

// --- contract ------------------------------------------------------------------------------

TEST(Proxy, UpdateAllocatesNothing) {
  const mesh::TriMesh ball = mesh::sphere(0.05, 2);
  const BruteForceSurfaceQuery surface(ball.vertices, ball.triangles);
  const ProxyParams params = params_with(0.002, 0.5, 0.3);
  ProxyState state = make_proxy_state(Vec3(0, 0, 0.1));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.08, 0.08);
  std::vector<Vec3> goals(200);
  for (Vec3& g : goals) g = Vec3(u(rng), u(rng), u(rng));
  int contacts = 0;
  const tactus::testing::AllocationCounter counter;
  for (const Vec3& g : goals) contacts += update_proxy(params, state, g, Vec3::Zero(), kDt, surface).in_contact ? 1 : 0;
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(contacts, 20);
}

TEST(Proxy, RejectsBadParametersAndHoldsOnNonFiniteInput) {
  const auto invalid = [](auto change) {
    ProxyParams p;
    change(p);
    EXPECT_THROW(validate_proxy_params(p), InputError);
  };
  invalid([](ProxyParams& p) { p.radius = -1e-3; });
  invalid([](ProxyParams& p) { p.skin = 0.0; });
  invalid([](ProxyParams& p) { p.stiffness = std::nan(""); });
  invalid([](ProxyParams& p) { p.damping = -1.0; });
  invalid([](ProxyParams& p) {
    p.static_friction = 0.2;
    p.kinetic_friction = 0.3;
  });
  invalid([](ProxyParams& p) { p.slip_damping = -1.0; });
  invalid([](ProxyParams& p) { p.max_iterations = 0; });
  EXPECT_NO_THROW(validate_proxy_params(ProxyParams{}));
  try {
    ProxyParams p;
    p.static_friction = 0.2;
    p.kinetic_friction = 0.3;
    validate_proxy_params(p);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("kinetic_friction"), std::string::npos) << e.what();
  }

  const mesh::TriMesh floor = floor_plate();
  const BruteForceSurfaceQuery surface(floor.vertices, floor.triangles);
  ProxyState state = make_proxy_state(Vec3(0, 0, 0.01));
  const ProxyParams params = params_with(0.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const auto& [goal, dt] : {std::pair{Vec3(nan, 0, 0), kDt}, std::pair{Vec3(0, 0, -0.01), nan},
                                 std::pair{Vec3(0, 0, -0.01), -kDt}}) {
    const ProxyResult res = update_proxy(params, state, goal, Vec3::Zero(), dt, surface);
    EXPECT_TRUE(res.input_rejected);
    EXPECT_EQ(res.force, Vec3::Zero());
    EXPECT_EQ(state.position, Vec3(0, 0, 0.01));
  }
}

TEST(Proxy, AProxyStartedInsideAClosedSurfaceIsPushedOut) {
  const mesh::TriMesh box = mesh::box_surface(Vec3(0.1, 0.1, 0.1), 2);
  const BruteForceSurfaceQuery surface(box.vertices, box.triangles);
  const ProxyParams params = params_with(0.0);
  ProxyState state = make_proxy_state(Vec3(0.01, 0.02, 0.04));  // 1 cm under the top face
  const ProxyResult res = update_proxy(params, state, Vec3(0.01, 0.02, 0.04), Vec3::Zero(), kDt, surface);
  EXPECT_TRUE(res.pushed_out);
  EXPECT_LT(winding_number(res.position, box), 0.5);
  EXPECT_NEAR((res.position - Vec3(0.01, 0.02, 0.05)).norm(), 0.0, 3.0 * params.skin);
  EXPECT_NEAR(res.force.z(), params.stiffness * 0.01, params.stiffness * 3.0 * params.skin);
}

}  // namespace
}  // namespace tactus::contact
