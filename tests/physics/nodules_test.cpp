// Nodules under a sheet (seed 004 §5.4) and the fingertip that pushes but never drags.
#include <gtest/gtest.h>

#include <cmath>

#include "mesh/generators.hpp"
#include "physics/body.hpp"
#include "physics/mass_spring/surface_builder.hpp"
#include "physics/nodules.hpp"

namespace tactus::physics {
namespace {

TEST(Nodules, ProjectionGeneralizesThePapersEquations) {
  // Seed 004's nodule: centre (0, −2, 0), r_n = 1 (the line of its eq. 8 passes through
  // (0, −2, 0)); its t1 = 1/√(Px² + (Py + 2)² + Pz²) and t2 = t1 + r_p/√(...).
  const Vec3 c(0.0, -2.0, 0.0);
  const Vec3 p(0.3, -1.6, 0.2);
  const double dist = std::sqrt(p.x() * p.x() + (p.y() + 2.0) * (p.y() + 2.0) + p.z() * p.z());
  const double t1 = 1.0 / dist, rp = 0.25, t2 = rp / dist + t1;
  const Vec3 paper_s(p.x() * t1, -2.0 + (p.y() + 2.0) * t1, p.z() * t1);
  const Vec3 paper_proxy(p.x() * t2, -2.0 + (p.y() + 2.0) * t2, p.z() * t2);
  EXPECT_LT((project_onto_sphere(p, c, 1.0) - paper_s).norm(), 1e-14);
  EXPECT_LT((project_onto_sphere(p, c, 1.0 + rp) - paper_proxy).norm(), 1e-14);

  // Any centre and radius: on the sphere, on the ray from the centre through the point.
  const Vec3 c2(0.01, -0.02, -0.005);
  const Vec3 q(0.012, -0.018, -0.003);
  const Vec3 s = project_onto_sphere(q, c2, 0.004);
  EXPECT_NEAR((s - c2).norm(), 0.004, 1e-15);
  EXPECT_LT((s - c2).normalized().cross((q - c2).normalized()).norm(), 1e-12);
  EXPECT_GT((s - c2).dot(q - c2), 0.0);
}

TEST(Nodules, HertzPressureSumsToHertzForce) {
  // A flat sheet lowered by d onto an elastic sphere: the local law summed over a fine grid
  // gives Hertz's F = (4/3) E* √R d^(3/2).
  const double e = 3e4, nu = 0.45, radius = 0.005, d = 2e-4;
  const double beta = hertz_pressure_coefficient(e, nu, radius);
  const double h = 2e-5;
  double force = 0.0;
  for (int i = -200; i <= 200; ++i)
    for (int j = -200; j <= 200; ++j) {
      const double r2 = (i * h) * (i * h) + (j * h) * (j * h);
      const double overlap = d - (radius - std::sqrt(std::max(radius * radius - r2, 0.0)));
      if (r2 < radius * radius && overlap > 0.0) force += h * h * beta * std::sqrt(overlap);
    }
  const double hertz = 4.0 / 3.0 * e / (1.0 - nu * nu) * std::sqrt(radius) * std::pow(d, 1.5);
  EXPECT_NEAR(force, hertz, 0.02 * hertz);
}

/// One free node (mass m, area A) pushed by a constant force F onto a soft nodule, stepped
/// by symplectic Euler with the nodule enforced after each step.
double settled_overlap(const Nodule& nodule, double force, double mass, double area, double dt, int steps) {
  NoduleSet set;
  set.nodules.push_back(nodule);
  set.node_area = {area};
  VecX x(3), v = VecX::Zero(3), m = VecX::Constant(3, mass);
  x = nodule.center + Vec3(0.0, 0.0, nodule.radius);  // resting on its top
  const std::vector<std::uint8_t> fixed;
  for (int k = 0; k < steps; ++k) {
    v[2] += -dt * force / mass - dt * 50.0 * v[2];  // weight and some damping
    x += dt * v;
    enforce_nodules(set, fixed, m, dt, x, v);
  }
  return nodule.radius - (Vec3(x) - nodule.center).norm();
}

TEST(Nodules, SoftNoduleHoldsTheLoadWithItsHertzPressure) {
  Nodule soft;
  soft.rigid = false;
  soft.radius = 0.005;
  soft.pressure_coefficient = hertz_pressure_coefficient(3e4, 0.45, soft.radius);
  const double force = 0.01, area = 6e-6, mass = 1e-3;
  const double expected = std::pow(force / (area * soft.pressure_coefficient), 2.0);
  for (const double dt : {1e-4, 1e-3, 1e-2}) {  // stable whatever the step
    const double overlap = settled_overlap(soft, force, mass, area, dt, static_cast<int>(3.0 / dt));
    EXPECT_NEAR(overlap, expected, 0.02 * expected) << "dt " << dt;
  }
  // Stiffer nodules yield less and tend to the rigid one.
  Nodule stiff = soft;
  stiff.pressure_coefficient = hertz_pressure_coefficient(3e7, 0.45, soft.radius);
  EXPECT_LT(settled_overlap(stiff, force, mass, area, 1e-3, 3000), 1e-4 * expected);
  Nodule rigid = soft;
  rigid.rigid = true;
  EXPECT_NEAR(settled_overlap(rigid, force, mass, area, 1e-3, 3000), 0.0, 1e-15);
}

/// A 20x20 sheet of the paper's skin at z = 0, border held; `center` is its middle node.
struct Sheet {
  Body body;
  std::int32_t center = -1;
};

Sheet make_sheet() {
  Sheet s;
  const mesh::QuadMesh q = mesh::grid_plate_quads(0.04, 0.04, 20, 20);
  SurfaceSpringParams p;
  p.longitudinal_stiffness = 200.0;
  p.areal_density = 1.5;
  p.nodal_damping = 1e-3;
  s.body.model = surface_mass_spring(q, p);
  s.body.settings.integrator = Integrator::implicit_euler;
  std::vector<std::int32_t> border;
  for (std::size_t i = 0; i < q.vertices.size(); ++i) {
    const Vec3& v = q.vertices[i];
    if (std::abs(std::abs(v.x()) - 0.02) < 1e-9 || std::abs(std::abs(v.y()) - 0.02) < 1e-9)
      border.push_back(static_cast<std::int32_t>(i));
    if (v.head<2>().norm() < 1e-9) s.center = static_cast<std::int32_t>(i);
  }
  s.body.fixed_dofs.assign(3 * s.body.model->node_count(), 0);
  s.body.fix_nodes(border);
  return s;
}

/// Presses the whole sheet down with `force` shared by its nodes (a uniform pressure, so it
/// drapes over what lies under it), ramped in over 0.4 s and held to 1.5 s; returns the
/// height of its middle node.
double pressed_depth(Sheet& s, double force, VecX* positions = nullptr) {
  BodyState state = make_state(s.body);
  const Eigen::Index nodes = state.x.size() / 3;
  VecX f = VecX::Zero(state.x.size());
  for (int k = 0; k < 300; ++k) {
    const double ramp = std::min(1.0, (k + 1) * 0.005 / 0.4);
    for (Eigen::Index n = 0; n < nodes; ++n) f[3 * n + 2] = -ramp * force / static_cast<double>(nodes);
    step(s.body, state, 0.005, f);
  }
  if (positions) *positions = state.x;
  return state.x[3 * s.center + 2];
}

TEST(Nodules, RigidNoduleStopsTheSheetAndIsNeverEntered) {
  Sheet free_sheet = make_sheet();
  const double free_depth = pressed_depth(free_sheet, 2.0);
  ASSERT_LT(free_depth, -0.004) << "the load must push the free sheet past the nodule's top";

  Sheet s = make_sheet();
  Nodule n;
  n.center = Vec3(0.0, 0.0, -0.008);
  n.radius = 0.006;  // top at z = −2 mm
  s.body.nodules.nodules.push_back(n);
  VecX x;
  const double depth = pressed_depth(s, 2.0, &x);
  // Resting on the nodule near its top (the frictionless cap lets it settle slightly aside).
  EXPECT_LT(depth, -0.002 + 1e-9);
  EXPECT_GT(depth, -0.0021);
  for (Eigen::Index i = 0; i < x.size(); i += 3)
    EXPECT_GE((Vec3(x.segment<3>(i)) - n.center).norm(), n.radius - 1e-12);
}

TEST(Nodules, SoftNoduleYieldsMoreThanRigidLessThanNone) {
  Sheet rigid_sheet = make_sheet(), soft_sheet = make_sheet(), free_sheet = make_sheet();
  Nodule n;
  n.center = Vec3(0.0, 0.0, -0.008);
  n.radius = 0.006;
  rigid_sheet.body.nodules.nodules.push_back(n);
  n.rigid = false;
  n.pressure_coefficient = hertz_pressure_coefficient(2e4, 0.45, n.radius);
  soft_sheet.body.nodules.nodules.push_back(n);
  const mesh::QuadMesh q = mesh::grid_plate_quads(0.04, 0.04, 20, 20);
  soft_sheet.body.nodules.node_area.assign(q.vertices.size(), 0.002 * 0.002);
  VecX x_rigid, x_soft;
  pressed_depth(rigid_sheet, 2.0, &x_rigid);
  const double soft = pressed_depth(soft_sheet, 2.0, &x_soft);
  const double none = pressed_depth(free_sheet, 2.0);
  auto penetration = [&](const VecX& x) {
    double deepest = 0.0;
    for (Eigen::Index i = 0; i < x.size(); i += 3)
      deepest = std::max(deepest, n.radius - (Vec3(x.segment<3>(i)) - n.center).norm());
    return deepest;
  };
  EXPECT_LT(penetration(x_rigid), 1e-12);
  // The soft one yields a little under the nodes it carries, and still holds the sheet up.
  EXPECT_GT(penetration(x_soft), 1e-6);
  EXPECT_LT(penetration(x_soft), 1e-3);
  EXPECT_GT(soft, none + 1e-3);
}

TEST(Nodules, FixedNodesNeverMove) {
  NoduleSet set;
  set.nodules.push_back({Vec3::Zero(), 1.0, true, 0.0});
  VecX x(6), v = VecX::Zero(6), m = VecX::Ones(6);
  x << 0.1, 0.0, 0.0, 0.2, 0.0, 0.0;
  const std::vector<std::uint8_t> fixed{1, 1, 1, 0, 0, 0};
  enforce_nodules(set, fixed, m, 1e-3, x, v);
  EXPECT_EQ(x[0], 0.1);
  EXPECT_NEAR(Vec3(x.segment<3>(3)).norm(), 1.0, 1e-15);
}

TEST(Fingertip, PushesButNeverPullsOrDrags) {
  const Vec3 center(0.0, 0.0, 0.01);
  const double radius = 0.006;
  const Vec3 finger_velocity(0.02, 0.0, -0.01);
  VecX x(9), v(9);
  x << 0.001, 0.0, 0.005,   // inside, below the centre
      0.0, 0.0, 0.0,        // outside: untouched
      0.0, 0.001, 0.007;    // inside
  v << 0.0, 0.03, 0.0,      // tangential motion kept
      0.0, 0.0, 0.5,        // outside and moving towards the finger: left alone
      0.0, 0.0, -1.0;       // already leaving faster than the finger pushes: kept
  const VecX x0 = x, v0 = v;
  EXPECT_EQ(push_out_of_sphere(center, radius, finger_velocity, {}, x, v), 2);
  EXPECT_EQ(Vec3(x.segment<3>(3)), Vec3(x0.segment<3>(3)));
  EXPECT_EQ(Vec3(v.segment<3>(3)), Vec3(v0.segment<3>(3)));
  for (const Eigen::Index i : {0, 6}) {
    const Vec3 p = x.segment<3>(i);
    EXPECT_NEAR((p - center).norm(), radius, 1e-15);
    const Vec3 n = (p - center).normalized();
    // Pushed: the normal velocity is at least the finger's, and never pulled back towards it.
    EXPECT_GE(Vec3(v.segment<3>(i)).dot(n), finger_velocity.dot(n) - 1e-15);
    // No drag: the tangential velocity is what it was.
    const Vec3 before = v0.segment<3>(i), after = v.segment<3>(i);
    EXPECT_LT(((after - after.dot(n) * n) - (before - before.dot(n) * n)).norm(), 1e-15);
  }
  EXPECT_GT(Vec3(v.segment<3>(0)).dot((Vec3(x.segment<3>(0)) - center).normalized()), 0.0);
}

}  // namespace
}  // namespace tactus::physics
