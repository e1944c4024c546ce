// The average-nodal-pressure Mooney–Rivlin (physics/fem/nodal_pressure.hpp): its forces, exact
// tangent, products and assembled matrix against each other and against finite differences
// of its energy, the patch test, and how it frees a coarse mesh from volumetric locking.
#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <cmath>
#include <cstdio>
#include <random>

#include "fem_test_util.hpp"
#include "physics/fem/nodal_pressure.hpp"

namespace tactus::physics {
namespace {

FemMaterial nearly_incompressible(double nu, bool nodal) {
  FemMaterial m = fem_test::material(FemLaw::mooney_rivlin, 4.0 * 1000.0 * (1.0 + nu), nu, 1000.0);
  m.c10 = 700.0;
  m.c01 = 300.0;
  m.nodal_pressure = nodal;
  return m;
}

std::shared_ptr<const ForceModel> nodal_model(const mesh::TetMesh& mesh, double nu) {
  return std::make_shared<NodalPressureFem>(std::make_shared<TetFem>(mesh, nearly_incompressible(nu, true)));
}

/// A 2 cm block, deformed by a homogeneous stretch and a random wobble of every node.
VecX wobbled(const ForceModel& model, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  VecX x = fem_test::deformed(model.rest_positions(), Mat3(Vec3(1.05, 0.97, 0.93).asDiagonal()));
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += u(rng);
  return x;
}

VecX force_at(const ForceModel& model, const VecX& x) {
  const auto s = model.make_scratch();
  VecX f = VecX::Zero(x.size());
  model.forces(x, VecX::Zero(x.size()), VecX::Zero(static_cast<Eigen::Index>(model.internal_size())), f, *s);
  return f;
}

TEST(NodalPressure, ForcesAreTheEnergysGradientAndTheTangentTheirs) {
  const mesh::TetMesh mesh = mesh::box_volume(Vec3(0.02, 0.02, 0.02), 2, 2, 2);
  const auto model = nodal_model(mesh, 0.49);
  const VecX x = wobbled(*model, 4e-4, 1);
  const VecX q = VecX::Zero(static_cast<Eigen::Index>(model->internal_size()));
  const VecX f = force_at(*model, x);
  // −∂E/∂x by central differences: the energy is smooth, so 1e-7 m steps leave truncation
  // at ~1e-14 relative and round-off at ~1e-9 of the largest force.
  const double h = 1e-7;
  double worst = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    VecX a = x, b = x;
    a[i] += h;
    b[i] -= h;
    const double fd = -(model->elastic_energy(a, q) - model->elastic_energy(b, q)) / (2.0 * h);
    worst = std::max(worst, std::abs(fd - f[i]));
  }
  EXPECT_LT(worst, 1e-6 * f.cwiseAbs().maxCoeff()) << "largest force " << f.cwiseAbs().maxCoeff();

  // The exact tangent's product against the forces' central difference along random dx.
  const auto s = model->make_scratch();
  ASSERT_TRUE(model->linearize_exact(x, VecX::Zero(x.size()), q, *s));
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  VecX dx(x.size());
  for (Eigen::Index i = 0; i < dx.size(); ++i) dx[i] = u(rng);
  VecX kdx = VecX::Zero(x.size());
  model->add_stiffness_product(dx, kdx, *s);
  const VecX fd = -(force_at(*model, x + h * dx) - force_at(*model, x - h * dx)) / (2.0 * h);
  EXPECT_LT((kdx - fd).norm(), 1e-6 * kdx.norm());

  // The assembled triplets are that same matrix, and their diagonal the diagonal's.
  std::vector<Triplet> triplets;
  model->add_triplets(1.0, 0.0, triplets, *s);
  SparseMatrix k(x.size(), x.size());
  k.setFromTriplets(triplets.begin(), triplets.end());
  EXPECT_LT((k * dx - kdx).norm(), 1e-12 * kdx.norm());
  EXPECT_LT((SparseMatrix(k.transpose()) - k).norm(), 1e-12 * k.norm());
  // The projected linearization (for CG) drops only the geometric part: its diagonal is the
  // exact one's (that part's diagonal blocks are zero).
  ASSERT_TRUE(model->linearize_exact(x, VecX::Zero(x.size()), q, *s));
  VecX diagonal = VecX::Zero(x.size());
  const auto projected = model->make_scratch();
  model->linearize(x, VecX::Zero(x.size()), q, *projected);
  model->add_diagonal(1.0, 0.0, diagonal, *projected);
  std::vector<Triplet> projected_triplets;
  model->add_triplets(1.0, 0.0, projected_triplets, *projected);
  SparseMatrix kp(x.size(), x.size());
  kp.setFromTriplets(projected_triplets.begin(), projected_triplets.end());
  EXPECT_LT((VecX(kp.diagonal()) - diagonal).norm(), 1e-12 * diagonal.norm());
  VecX kpdx = VecX::Zero(x.size());
  model->add_stiffness_product(dx, kpdx, *projected);
  EXPECT_LT((kp * dx - kpdx).norm(), 1e-12 * kpdx.norm());
}

TEST(NodalPressure, HomogeneousDeformationIsRepresentedExactly) {
  // Patch test: under x = F X every node's averaged volume ratio is det F, so every pressure
  // is κ (det F − 1), the interior nodes are balanced, and the force on a face is the
  // homogeneous stress's traction: the element formulation's, whose κ/2 (J − 1)² gives the same.
  const mesh::TetMesh mesh = mesh::box_volume(Vec3(0.02, 0.02, 0.02), 3, 3, 3);
  const auto nodal = std::make_shared<NodalPressureFem>(std::make_shared<TetFem>(mesh, nearly_incompressible(0.49, true)));
  const TetFem element(mesh, nearly_incompressible(0.49, false));
  const Mat3 F = fem_test::rotation(0.3, Vec3(1, 2, 3)) * Mat3(Vec3(1.1, 0.95, 0.9).asDiagonal());
  const VecX x = fem_test::deformed(nodal->rest_positions(), F);
  const double kappa = LawParams::from(nearly_incompressible(0.49, false)).kappa;
  const VecX p = nodal->nodal_pressures(x);
  EXPECT_LT((p.array() - kappa * (F.determinant() - 1.0)).abs().maxCoeff(), 1e-9 * kappa);
  const VecX f = force_at(*nodal, x), reference = force_at(element, x);
  EXPECT_LT((f - reference).cwiseAbs().maxCoeff(), 1e-9 * reference.cwiseAbs().maxCoeff());
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if ((mesh.vertices[v].cwiseAbs().array() < 0.01 - 1e-9).all()) {
      EXPECT_LT(f.segment<3>(3 * static_cast<Eigen::Index>(v)).norm(), 1e-9 * reference.cwiseAbs().maxCoeff());
    }
}

TEST(NodalPressure, ImplicitStepsNeverGainEnergy) {
  // Released from a squeezed, sheared state at ν = 0.49, stepped by backward Euler with
  // Newton to convergence: dissipative for a conservative energy, so any gain beyond
  // round-off (1e-9 relative) is a defect, with either solver (CG takes the projected
  // tangent, matrix-free; Cholesky the exact one).
  const mesh::TetMesh mesh = mesh::box_volume(Vec3(0.02, 0.02, 0.02), 2, 2, 2);
  for (const auto solver : {LinearSolver::conjugate_gradient, LinearSolver::cholesky}) {
    Body b;
    b.model = nodal_model(mesh, 0.49);
    b.settings.solver = solver;
    b.settings.cg_tolerance = 1e-12;
    b.settings.cg_max_iterations = 5000;
    b.settings.newton_iterations = 10;
    b.settings.newton_tolerance = 1e-12;
    BodyState s = make_state(b);
    s.x = fem_test::deformed(s.x, fem_test::rotation(0.3, Vec3(0, 0, 1)) * Mat3(Vec3(1.1, 0.95, 0.9).asDiagonal()));
    double e = kinetic_energy(b, s) + potential_energy(b, s);
    const double e0 = e;
    for (int i = 0; i < 40; ++i) {
      step(b, s, 1e-3);
      const double next = kinetic_energy(b, s) + potential_energy(b, s);
      ASSERT_LE(next, e * (1 + 1e-9)) << (solver == LinearSolver::cholesky ? "cholesky" : "cg") << " step " << i;
      e = next;
    }
    EXPECT_LT(e, e0);
  }
}

}  // namespace
}  // namespace tactus::physics
