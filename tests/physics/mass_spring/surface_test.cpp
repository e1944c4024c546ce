// Surface sheets of seed 004 §4.2: which springs the builders make, what the "torsional"
// terms resist, and a pinned sheet sagging under gravity.
#include <gtest/gtest.h>

#include <cmath>

#include "ms_test_util.hpp"
#include "physics/mass_spring/surface_builder.hpp"

namespace tactus::physics {
namespace {

using test::nodes_at;

TEST(SurfaceSheet, Seed004PresetHasOnlyLongitudinalSpringsAndDamping) {
  const int nx = 4, ny = 3;
  const auto net = surface_mass_spring(mesh::grid_plate_quads(0.04, 0.03, nx, ny), skin_seed004(40.0, 0.2, 2e-3));
  EXPECT_EQ(net->springs().size(), static_cast<std::size_t>(nx * (ny + 1) + ny * (nx + 1)));  // quad edges
  EXPECT_TRUE(net->angles().empty());
  EXPECT_TRUE(net->arms().empty());
  for (const auto& s : net->springs()) {
    EXPECT_DOUBLE_EQ(s.stiffness, 40.0);
    EXPECT_DOUBLE_EQ(s.damping, 0.0);
    EXPECT_NEAR(s.rest_length, 0.01, 1e-15);  // only edges, no diagonals (0.01·√2)
  }
  for (std::int32_t n = 0; n < static_cast<std::int32_t>(net->node_count()); ++n) {
    EXPECT_DOUBLE_EQ(net->nodal_damping(n), 0.2);
    EXPECT_DOUBLE_EQ(net->lumped_mass()[3 * n], 2e-3);
  }
}

/// uᵀ K u at rest for the shear mode of one 10 mm quad: top edge moved along x by 1.
double shear_stiffness(const SurfaceSpringParams& p) {
  const auto net = surface_mass_spring(mesh::grid_plate_quads(0.01, 0.01, 1, 1), p);
  auto s = net->make_scratch();
  const VecX& x = net->rest_positions();
  net->linearize(x, VecX::Zero(x.size()), VecX(), *s);
  VecX u = VecX::Zero(x.size()), ku = VecX::Zero(x.size());
  for (auto n : nodes_at(x, 1, 0.005)) u[3 * n] = 1.0;
  net->add_stiffness_product(u, ku, *s);
  return u.dot(ku);
}

TEST(SurfaceSheet, TorsionalTermsResistInPlaneShear) {
  // Shearing the quad by δ turns all four corner angles by δ/l: uᵀKu = 4 k_θ / l². Edge
  // springs alone give a mechanism (zero); a diagonal pair gives k_d (each stretches δ/√2).
  SurfaceSpringParams p;
  p.node_mass = 1e-3;
  const double without = shear_stiffness(p);
  EXPECT_NEAR(without, 0.0, 1e-12);
  p.torsional = true;
  p.torsional_stiffness = 2e-3;
  EXPECT_NEAR(shear_stiffness(p), 4 * 2e-3 / (0.01 * 0.01), 1e-9);
  EXPECT_GT(shear_stiffness(p), without);
  p.torsional = false;
  p.diagonal = true;
  EXPECT_NEAR(shear_stiffness(p), p.diagonal_stiffness, 1e-9);
}

TEST(SurfaceSheet, BuildersMakeTheExpectedSprings) {
  const int nx = 5, ny = 4;
  SurfaceSpringParams p;
  p.node_mass = 1e-3;
  p.diagonal = p.torsional = p.bending = true;
  const auto quads = surface_mass_spring(mesh::grid_plate_quads(0.05, 0.04, nx, ny), p);
  const std::size_t edges = nx * (ny + 1) + ny * (nx + 1);
  const std::size_t skip_one = (ny + 1) * (nx - 1) + (nx + 1) * (ny - 1);  // along grid lines, over one node
  EXPECT_EQ(quads->springs().size(), edges + 2 * nx * ny + skip_one);
  EXPECT_EQ(quads->angles().size(), static_cast<std::size_t>(4 * nx * ny));
  for (std::size_t k = edges + 2 * nx * ny; k < quads->springs().size(); ++k)
    EXPECT_NEAR(quads->springs()[k].rest_length, 0.02, 1e-12);  // skip-one spans two cells

  const auto tris = surface_mass_spring(mesh::grid_plate(0.05, 0.04, nx, ny), p);
  const std::size_t tri_edges = edges + nx * ny;  // one diagonal per quad
  const std::size_t interior = tri_edges - 2 * (nx + ny);
  EXPECT_EQ(tris->springs().size(), tri_edges + interior);  // edges + one flap spring each
  EXPECT_EQ(tris->angles().size(), static_cast<std::size_t>(3 * 2 * nx * ny));
}

TEST(SurfaceSheet, MassesLumpFromArealDensity) {
  SurfaceSpringParams p;
  p.areal_density = 2.0;
  const auto net = surface_mass_spring(mesh::grid_plate_quads(0.03, 0.02, 3, 2), p);
  EXPECT_NEAR(net->lumped_mass().sum() / 3.0, 2.0 * 0.03 * 0.02, 1e-15);
  EXPECT_NEAR(net->lumped_mass()[0], 2.0 * 1e-4 / 4.0, 1e-15);  // a corner holds a quarter cell
}

TEST(SurfaceSheet, PinnedSheetSagsAndSettlesOnTheStaticSolution) {
  // The seed-004 skin, 6×6 cells of 10 mm, pinned along its border, under gravity. A flat
  // membrane has no first-order out-of-plane stiffness, so the static Newton solve starts from
  // a small bowl; the damped dynamic run starts flat. After 10 s (1000 damping times m/k_d)
  // both must agree within 1e-6 of the sag depth (the static residual and the dynamic
  // remainder are both far below that).
  const double size = 0.06;
  const auto m = mesh::grid_plate_quads(size, size, 6, 6);
  Body b;
  b.model = surface_mass_spring(m, skin_seed004(50.0, 0.1, 1e-3));
  std::vector<std::int32_t> border;
  const VecX& rest = b.model->rest_positions();
  for (Eigen::Index n = 0; 3 * n < rest.size(); ++n)
    if (std::abs(std::abs(rest[3 * n]) - size / 2) < 1e-12 || std::abs(std::abs(rest[3 * n + 1]) - size / 2) < 1e-12)
      border.push_back(static_cast<std::int32_t>(n));
  b.fix_nodes(border);
  b.gravity = Vec3(0, 0, -9.81);

  BodyState st = make_state(b);
  for (Eigen::Index n = 0; 3 * n < rest.size(); ++n) {
    const double u = 2 * rest[3 * n] / size, w = 2 * rest[3 * n + 1] / size;
    st.x[3 * n + 2] = -2e-3 * (1 - u * u) * (1 - w * w);
  }
  const auto r = solve_static(b, st, {}, 100, 1e-12);
  ASSERT_TRUE(r.converged) << r.residual;
  const Eigen::Index centre = 3 * (3 * 7 + 3) + 2;
  const double sag = st.x[centre];
  EXPECT_LT(sag, -1e-3);

  BodyState dyn = make_state(b);
  b.settings.solver = LinearSolver::cholesky;
  for (int i = 0; i < 5000; ++i) step(b, dyn, 2e-3);
  EXPECT_LT((dyn.x - st.x).cwiseAbs().maxCoeff(), 1e-6 * std::abs(sag));
  EXPECT_NEAR(dyn.x[centre], sag, 1e-6 * std::abs(sag));
}

TEST(SurfaceSheet, ExplicitEulerOfSeed004Settles) {
  // The paper's integrator (eq. 5) on its skin, border pinned, pressed at the centre. Stable
  // when dt is below k_d/(m ω²) of the stiffest mode (here 2.5e-4 s > 1e-4 s). Settling: the
  // speed at the end is below 1% of its peak, and the centre has moved into the press.
  const auto m = mesh::grid_plate_quads(0.06, 0.06, 6, 6);
  Body b;
  b.model = surface_mass_spring(m, skin_seed004(50.0, 0.1, 1e-3));
  const VecX& rest = b.model->rest_positions();
  std::vector<std::int32_t> border;
  for (Eigen::Index n = 0; 3 * n < rest.size(); ++n)
    if (std::abs(rest[3 * n]) > 0.0299 || std::abs(rest[3 * n + 1]) > 0.0299) border.push_back(static_cast<std::int32_t>(n));
  b.fix_nodes(border);
  b.settings.integrator = Integrator::explicit_euler;
  BodyState s = make_state(b);
  VecX f = VecX::Zero(s.x.size());
  const Eigen::Index centre = 3 * (3 * 7 + 3) + 2;
  f[centre] = -0.01;
  double peak = 0.0;
  for (int i = 0; i < 20000; ++i) {
    step(b, s, 1e-4, f);
    ASSERT_TRUE(s.x.allFinite());
    peak = std::max(peak, s.v.norm());
  }
  EXPECT_LT(s.v.norm(), 0.01 * peak);
  EXPECT_LT(s.x[centre], -1e-3);
}

}  // namespace
}  // namespace tactus::physics
