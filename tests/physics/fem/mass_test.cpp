// Consistent mass of the tetrahedral FEM: its totals, its use in the implicit integrator's
// three linear-solver paths, and the first axial mode of a bar against 1D theory.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "fem_test_util.hpp"

namespace tactus::physics {
namespace {

using fem_test::material;

VecX random_values(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  VecX v(n);
  for (auto& c : v) c = u(rng);
  return v;
}

Eigen::MatrixXd dense(Eigen::Index n, const std::vector<Triplet>& triplets) {
  SparseMatrix m(n, n);
  m.setFromTriplets(triplets.begin(), triplets.end());
  return Eigen::MatrixXd(m);
}

/// Total momentum sum_i (M v)_i per axis.
Vec3 momentum(const ForceModel& model, const VecX& v) {
  VecX p = VecX::Zero(v.size());
  model.add_mass_product(1.0, v, p);
  Vec3 sum = Vec3::Zero();
  for (Eigen::Index i = 0; i < p.size(); i += 3) sum += p.segment<3>(i);
  return sum;
}

TEST(FemConsistentMass, ElementMatrixTotalMassAndRigidTranslation) {
  // P1 tetrahedron: M_e = rho V/20 (1 + delta_ab) I3 (e.g. Zienkiewicz & Taylor). Every
  // entry exact to round-off (1e-15 relative); the totals 1^T M 1 = rho V per axis, and a
  // rigid translation's momentum M v = (rho V) v, whatever the mesh.
  const double rho = 1200.0;
  const TetFem tet(fem_test::single_tet(), material(FemLaw::linear, 1e4, 0.3, rho), FemMass::consistent);
  EXPECT_FALSE(tet.mass_is_diagonal());
  const double V = tet.elements()[0].volume;
  std::vector<Triplet> triplets;
  tet.add_mass_triplets(1.0, triplets);
  const Eigen::MatrixXd M = dense(12, triplets);
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          const double expected = i != j ? 0.0 : rho * V / 20.0 * (a == b ? 2.0 : 1.0);
          EXPECT_NEAR(M(3 * a + i, 3 * b + j), expected, 1e-15 * rho * V);
        }
  const mesh::TetMesh block = mesh::box_volume(Vec3(0.03, 0.02, 0.01), 3, 2, 2);
  const TetFem fem(block, material(FemLaw::corotational, 1e4, 0.3, rho), FemMass::consistent);
  const double mass = rho * 0.03 * 0.02 * 0.01;
  const Vec3 v0(0.3, -0.2, 0.5);
  VecX v(fem.rest_positions().size());
  for (Eigen::Index i = 0; i < v.size(); i += 3) v.segment<3>(i) = v0;
  EXPECT_LT((momentum(fem, v) - mass * v0).norm(), 1e-12 * mass * v0.norm());
  const VecX ones = VecX::Ones(v.size());
  VecX m_ones = VecX::Zero(v.size());
  fem.add_mass_product(1.0, ones, m_ones);
  EXPECT_NEAR(ones.dot(m_ones), 3.0 * mass, 1e-12 * mass);
  // The product and the triplets are the same matrix, and M is symmetric positive definite.
  triplets.clear();
  fem.add_mass_triplets(1.0, triplets);
  const Eigen::MatrixXd Mb = dense(v.size(), triplets);
  const VecX in = random_values(v.size(), 3);
  VecX out = VecX::Zero(v.size());
  fem.add_mass_product(1.0, in, out);
  EXPECT_LT((out - Mb * in).norm(), 1e-13 * out.norm());
  EXPECT_LT((Mb - Mb.transpose()).norm(), 1e-15 * Mb.norm());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Mb).eigenvalues().minCoeff(), 0.0);
}

TEST(FemConsistentMass, SystemProductAssemblyAndTripletsAgree) {
  // a M + b D + c K with D = alpha M + beta K: the one-pass product, the block matrix of the
  // CG path and the triplets of the CHOLMOD path hold the same matrix (round-off, 1e-12).
  const mesh::TetMesh m = mesh::box_volume(Vec3(0.02, 0.02, 0.02), 2, 2, 2);
  for (FemLaw law : fem_test::all_laws()) {
    FemMaterial mat = material(law, 1e4, 0.45);
    mat.rayleigh_mass = 3.0;
    mat.rayleigh_stiffness = 0.01;
    const TetFem fem(m, mat, FemMass::consistent);
    auto s = fem.make_scratch();
    const VecX x = fem_test::deformed(fem.rest_positions(), fem_test::rotation(0.4, Vec3(1, 2, 3)) *
                                                                Vec3(1.1, 0.95, 1.02).asDiagonal());
    fem.linearize(x, VecX::Zero(x.size()), VecX(), *s);
    const double a = 1.0, b = 0.01, c = 1e-4;
    std::vector<Triplet> triplets;
    fem.add_triplets(c, b, triplets, *s);
    fem.add_mass_triplets(a, triplets);
    const Eigen::MatrixXd reference = dense(x.size(), triplets);
    const VecX in = random_values(x.size(), 11);
    VecX out = VecX::Zero(x.size());
    fem.add_system_product(a, b, c, in, out, *s);
    EXPECT_LT((out - reference * in).norm(), 1e-12 * out.norm()) << to_string(law);
    // The damping force is -D v: its mass part uses the consistent M too.
    const VecX v = random_values(x.size(), 5);
    VecX damped(x.size()), undamped(x.size()), product = VecX::Zero(x.size());
    fem.forces(x, v, VecX(), damped, *s);
    fem.forces(x, VecX::Zero(x.size()), VecX(), undamped, *s);
    fem.add_damping_product(v, product, *s);
    EXPECT_LT((damped - undamped + product).norm(), 1e-12 * product.norm()) << to_string(law);
    const BlockMatrix* assembled = fem.assemble_system(a, b, c, *s);
    if (!assembled) continue;  // hyperelastic laws solve matrix-free
    Eigen::MatrixXd blocks = Eigen::MatrixXd::Zero(x.size(), x.size());
    for (std::size_t i = 0; i < assembled->diagonal.size(); ++i) blocks.block<3, 3>(3 * i, 3 * i) = assembled->diagonal[i];
    for (std::size_t i = 0; i + 1 < assembled->row_start.size(); ++i)
      for (auto k = assembled->row_start[i]; k < assembled->row_start[i + 1]; ++k) {
        const auto j = static_cast<Eigen::Index>(assembled->column[static_cast<std::size_t>(k)]);
        blocks.block<3, 3>(3 * i, 3 * j) = assembled->upper[static_cast<std::size_t>(k)];
        blocks.block<3, 3>(3 * j, 3 * i) = assembled->upper[static_cast<std::size_t>(k)].transpose();
      }
    EXPECT_LT((blocks - reference).norm(), 1e-12 * reference.norm()) << to_string(law);
  }
}

TEST(FemConsistentMass, ImplicitStepsConserveMomentumOnEverySolverPath) {
  // A free, deformed, spinning block: internal forces sum to zero, so backward Euler keeps
  // the total momentum M v exactly; with a consistent M that holds only if the step solves
  // with that M. CHOLMOD solves exactly (round-off: 1e-9 of the momentum scale m |v|); CG to
  // 1e-12 relative, the same bound. The three paths (assembled CG for the corotational law,
  // matrix-free CG for neo-Hookean, CHOLMOD) must also agree with each other. Newton runs to
  // 1e-12: the paths linearize neo-Hookean differently (CG the projected tangent, CHOLMOD the
  // exact one where definite), so they meet only at the converged step.
  const mesh::TetMesh m = mesh::box_volume(Vec3(0.02, 0.02, 0.02), 2, 2, 2);
  for (FemLaw law : {FemLaw::corotational, FemLaw::neo_hookean}) {
    std::vector<VecX> finals;
    for (auto solver : {LinearSolver::conjugate_gradient, LinearSolver::cholesky}) {
      Body b;
      b.model = std::make_shared<TetFem>(m, material(law, 1e4, 0.3), FemMass::consistent);
      b.settings.solver = solver;
      b.settings.cg_tolerance = 1e-12;
      b.settings.cg_max_iterations = 2000;
      b.settings.newton_iterations = 10;
      b.settings.newton_tolerance = 1e-12;
      BodyState s = make_state(b);
      s.x = fem_test::deformed(s.x, Vec3(1.1, 0.95, 1.0).asDiagonal());
      const Vec3 drift(0.1, -0.05, 0.02);
      for (Eigen::Index i = 0; i < s.v.size(); i += 3)
        s.v.segment<3>(i) = drift + Vec3(0, 0, 2.0).cross(Vec3(s.x.segment<3>(i)));
      const Vec3 p0 = momentum(*b.model, s.v);
      const double scale = 1000.0 * 8e-6 * s.v.cwiseAbs().maxCoeff();
      for (int i = 0; i < 20; ++i) step(b, s, 2e-3);
      EXPECT_LT((momentum(*b.model, s.v) - p0).norm(), 1e-9 * scale) << to_string(law);
      finals.push_back(s.x);
    }
    EXPECT_LT((finals[0] - finals[1]).norm(), 1e-8 * finals[1].norm()) << to_string(law);
  }
}

TEST(FemConsistentMass, ExplicitIntegratorsRefuseIt) {
  Body b;
  b.model = std::make_shared<TetFem>(fem_test::single_tet(), material(FemLaw::linear), FemMass::consistent);
  BodyState s = make_state(b);
  for (auto integrator : {Integrator::explicit_euler, Integrator::symplectic_euler, Integrator::rk4}) {
    b.settings.integrator = integrator;
    EXPECT_THROW(step(b, s, 1e-4), std::invalid_argument);
  }
}

/// First axial eigenfrequency [Hz] of a fixed-free bar of n cells along x (one cell across),
/// from the generalized eigenproblem K u = omega^2 M u on the axial dofs.
double bar_frequency(int cells, FemMass mass, double L, double a, double E, double rho) {
  const mesh::TetMesh m = mesh::box_volume(Vec3(L, a, a), cells, 1, 1);
  const TetFem fem(m, material(FemLaw::linear, E, 0.0, rho), mass);
  auto s = fem.make_scratch();
  fem.linearize(fem.rest_positions(), VecX(), VecX(), *s);
  const auto n = fem.rest_positions().size();
  std::vector<Triplet> k, mt;
  fem.add_triplets(1.0, 0.0, k, *s);
  fem.add_mass_triplets(1.0, mt);
  const Eigen::MatrixXd K = dense(n, k), M = dense(n, mt);
  // Free axial dofs: x of every node off the clamped face x = -L/2. The lateral dofs are held:
  // with nu = 0 the exact axial mode has no lateral motion, so this changes nothing in the
  // continuum and removes the bending modes, which lie below the axial one.
  std::vector<Eigen::Index> dofs;
  for (Eigen::Index i = 0; 3 * i < n; ++i)
    if (std::abs(m.vertices[static_cast<std::size_t>(i)].x() + L / 2) > 1e-12) dofs.push_back(3 * i);
  const auto d = static_cast<Eigen::Index>(dofs.size());
  Eigen::MatrixXd Kf(d, d), Mf(d, d);
  for (Eigen::Index i = 0; i < d; ++i)
    for (Eigen::Index j = 0; j < d; ++j) {
      Kf(i, j) = K(dofs[static_cast<std::size_t>(i)], dofs[static_cast<std::size_t>(j)]);
      Mf(i, j) = M(dofs[static_cast<std::size_t>(i)], dofs[static_cast<std::size_t>(j)]);
    }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(Kf, Mf);
  return std::sqrt(solver.eigenvalues().minCoeff()) / (2.0 * std::numbers::pi);
}

TEST(FemConsistentMass, BarAxialModeIsBracketedByLumpedAndConsistentMass) {
  // Fixed-free bar, nu = 0 so 1D theory is exact: f1 = sqrt(E/rho) / (4 L) = 25 Hz here.
  // Consistent mass is the Rayleigh-Ritz mass of the conforming P1 space, so its frequency is
  // an upper bound; lumping moves mass to the nodes and lowers it below f1. Both errors are
  // O(h^2) (1D: +-(k h)^2/24 relative): halving h must cut each by more than 3 (4 at the
  // asymptote), and the finest mesh must be within 0.1%.
  const double L = 0.1, a = 0.01, E = 1e5, rho = 1000.0;
  const double f1 = std::sqrt(E / rho) / (4.0 * L);
  double last_lumped = 0.0, last_consistent = 0.0;
  for (int cells : {4, 8, 16, 32}) {
    const double lumped = bar_frequency(cells, FemMass::lumped, L, a, E, rho);
    const double consistent = bar_frequency(cells, FemMass::consistent, L, a, E, rho);
    EXPECT_LT(lumped, f1) << cells;
    EXPECT_GT(consistent, f1) << cells;
    if (last_lumped > 0.0) {
      EXPECT_GT((f1 - last_lumped) / (f1 - lumped), 3.0) << cells;
      EXPECT_GT((last_consistent - f1) / (consistent - f1), 3.0) << cells;
    }
    last_lumped = lumped;
    last_consistent = consistent;
  }
  EXPECT_LT(std::abs(last_lumped / f1 - 1.0), 1e-3);
  EXPECT_LT(std::abs(last_consistent / f1 - 1.0), 1e-3);
}

}  // namespace
}  // namespace tactus::physics
