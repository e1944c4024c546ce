// Time integration of FEM bodies: energy behaviour, recovery from a squashed state,
// stability at large time steps and viscoelastic relaxation.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>

#include "fem_test_util.hpp"

namespace tactus::physics {
namespace {

using fem_test::material;

double energy(const Body& b, const BodyState& s) { return kinetic_energy(b, s) + potential_energy(b, s); }

TEST(FemDynamics, SymplecticEulerConservesEnergyOver10000Steps) {
  // A free 2 cm cube (6 tets) stretched 3% and released. Its stiffest mode has
  // omega ~ 1e3 rad/s; at dt = 1e-5 symplectic Euler's energy error oscillates with
  // relative amplitude ~ omega dt / 2 = 0.5% and does not drift, so 1% is the bound.
  for (FemLaw law : fem_test::all_laws()) {
    Body b;
    b.model = std::make_shared<TetFem>(mesh::box_volume(Vec3(0.02, 0.02, 0.02), 1, 1, 1), material(law, 1e4, 0.3));
    b.settings.integrator = Integrator::symplectic_euler;
    BodyState s = make_state(b);
    s.x = fem_test::deformed(s.x, Vec3(1.03, 1.0, 1.0).asDiagonal());
    const double e0 = energy(b, s);
    double worst = 0.0;
    for (int i = 0; i < 10000; ++i) {
      step(b, s, 1e-5);
      worst = std::max(worst, std::abs(energy(b, s) - e0) / e0);
    }
    EXPECT_LT(worst, 0.01) << to_string(law);
    EXPECT_GT(kinetic_energy(b, s), 0.0);
  }
}

TEST(FemDynamics, ImplicitEulerNeverGainsEnergy) {
  // Backward Euler is dissipative for these conservative forces; with a tight linear solve
  // and Newton to convergence, any gain beyond round-off (1e-9 relative) is a defect.
  for (FemLaw law : fem_test::all_laws()) {
    for (auto solver : {LinearSolver::conjugate_gradient, LinearSolver::cholesky}) {
      Body b;
      b.model = std::make_shared<TetFem>(mesh::box_volume(Vec3(0.02, 0.02, 0.02), 1, 1, 1), material(law, 1e4, 0.3));
      b.settings.solver = solver;
      b.settings.cg_tolerance = 1e-12;
      b.settings.newton_iterations = 10;
      b.settings.newton_tolerance = 1e-12;
      BodyState s = make_state(b);
      s.x = fem_test::deformed(s.x, fem_test::rotation(0.3, Vec3(0, 0, 1)) * Vec3(1.2, 0.9, 1.0).asDiagonal());
      double e = energy(b, s);
      for (int i = 0; i < 60; ++i) {
        step(b, s, 1e-3);
        const double next = energy(b, s);
        ASSERT_LE(next, e * (1 + 1e-9)) << to_string(law) << " step " << i;
        e = next;
      }
    }
  }
}

/// Largest relative deviation of any tet edge length from its rest length.
double worst_edge_strain(const TetFem& fem, const VecX& x) {
  double worst = 0.0;
  const VecX& X = fem.rest_positions();
  for (const auto& el : fem.elements())
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const auto a = 3 * el.nodes[static_cast<std::size_t>(i)], c = 3 * el.nodes[static_cast<std::size_t>(j)];
        const double rest = (X.segment<3>(a) - X.segment<3>(c)).norm();
        worst = std::max(worst, std::abs((x.segment<3>(a) - x.segment<3>(c)).norm() - rest) / rest);
      }
  return worst;
}

/// A neo-Hookean block squashed 35 % and twisted, at rest: the start of the steps below.
struct SquashedBlock {
  Body body;
  BodyState state;
  explicit SquashedBlock(LinearSolver solver) {
    body.model = std::make_shared<TetFem>(mesh::box_volume(Vec3(0.02, 0.02, 0.02), 2, 2, 2),
                                          material(FemLaw::neo_hookean, 1e4, 0.45));
    body.settings.solver = solver;
    body.settings.cg_tolerance = 1e-14;
    body.settings.cg_max_iterations = 5000;
    state = make_state(body);
    state.x = fem_test::deformed(state.x, fem_test::rotation(0.2, Vec3(0, 0, 1)) * Vec3(1.1, 1.05, 0.65).asDiagonal());
  }
  /// The linearized step's velocity solved densely, (M + h²K) v = h f(x) from rest, with the
  /// exact or the projected tangent; and the smallest eigenvalue of that matrix (its
  /// condition number goes to the test's record, condition_exact / condition_projected).
  [[nodiscard]] std::pair<VecX, double> dense_step(double h, bool exact) const {
    const auto scratch = body.model->make_scratch();
    const VecX v = VecX::Zero(state.x.size());
    VecX f(state.x.size());
    body.model->forces(state.x, v, state.q, f, *scratch);
    if (!exact || !body.model->linearize_exact(state.x, v, state.q, *scratch))
      body.model->linearize(state.x, v, state.q, *scratch);
    std::vector<Triplet> triplets;
    body.model->add_triplets(h * h, 0.0, triplets, *scratch);
    body.model->add_mass_triplets(1.0, triplets);
    SparseMatrix a(state.x.size(), state.x.size());
    a.setFromTriplets(triplets.begin(), triplets.end());
    const Eigen::MatrixXd dense(a);
    const VecX eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(dense).eigenvalues();
    const double lowest = eigenvalues.minCoeff();
    ::testing::Test::RecordProperty(exact ? "condition_exact" : "condition_projected",
                                    std::to_string(eigenvalues.maxCoeff() / eigenvalues.cwiseAbs().minCoeff()));
    return {dense.fullPivLu().solve(h * f), lowest};
  }
  [[nodiscard]] VecX stepped(double h) {
    step(body, state, h);
    return state.v;
  }
};

TEST(FemDynamics, DirectStepsLinearizeWithTheExactTangentWhereDefinite) {
  // At 1 ms the mass outweighs the squashed elements' negative stiffness: the direct solver
  // takes the exact tangent, CG the projected one, and each matches its dense solve (the
  // two tangents differ here: the steps differ by more than the solves' round-off).
  const double h = 1e-3;
  SquashedBlock direct(LinearSolver::cholesky), cg(LinearSolver::conjugate_gradient);
  const auto [exact, exact_lowest] = direct.dense_step(h, true);
  const auto [projected, projected_lowest] = direct.dense_step(h, false);
  ASSERT_GT(exact_lowest, 0.0);
  ASSERT_GT((exact - projected).norm(), 1e-6 * exact.norm()) << "the tangents do not differ here";
  EXPECT_LT((direct.stepped(h) - exact).norm(), 1e-10 * exact.norm());
  EXPECT_LT((cg.stepped(h) - projected).norm(), 1e-10 * projected.norm());
}

TEST(FemDynamics, DirectStepsFallBackToTheProjectedTangentWhereTheExactIsNotDefinite) {
  // At a 10 s step M + h²K with the exact tangent is indefinite (the squashed block's
  // stress softens it along some modes): Cholesky says so and the step takes the projected
  // tangent, as its dense solve. That matrix's condition number is 2e9 (recorded: the mass alone
  // holds the rigid modes), so round-off allows about 2e-7 between the two solves; 1e-6
  // leaves room and is far below the exact tangent's step (over 1e-3 away).
  const double h = 10.0;
  SquashedBlock direct(LinearSolver::cholesky);
  const auto [exact, exact_lowest] = direct.dense_step(h, true);
  const auto [projected, projected_lowest] = direct.dense_step(h, false);
  ASSERT_LT(exact_lowest, 0.0) << "the exact system is definite here";
  ASSERT_GT(projected_lowest, 0.0);
  ASSERT_GT((exact - projected).norm(), 1e-3 * projected.norm());
  const VecX v = direct.stepped(h);
  ASSERT_TRUE(v.allFinite());
  EXPECT_LT((v - projected).norm(), 1e-6 * projected.norm());
}

TEST(FemDynamics, SquashedNeoHookeanBlockRecoversItsShape) {
  // Squashed to 5% of its height, and flattened onto a plane (every element J = 0), then
  // released with implicit Euler and mass damping. Recovery is judged up to a rigid motion:
  // every edge back to its rest length within 1% (the residual motion after 1 s of damping
  // at alpha = 20/s is far below that).
#ifdef TACTUS_SANITIZED
  const int cells = 2;  // 48 tets: the same squashed start and second of recovery
#else
  const int cells = 3;
#endif
  for (double height : {0.05, 0.0}) {
    FemMaterial mat = material(FemLaw::neo_hookean, 1e4, 0.3);
    mat.rayleigh_mass = 20.0;
    auto fem = std::make_shared<TetFem>(mesh::box_volume(Vec3(0.02, 0.02, 0.02), cells, cells, cells), mat);
    Body b;
    b.model = fem;
    b.settings.newton_iterations = 3;
    BodyState s = make_state(b);
    s.x = fem_test::deformed(s.x, Vec3(1.0, 1.0, height).asDiagonal());
    for (int i = 0; i < 1000; ++i) {
      step(b, s, 1e-3);
      ASSERT_TRUE(s.x.allFinite() && s.v.allFinite()) << "height " << height << " step " << i;
    }
    EXPECT_LT(worst_edge_strain(*fem, s.x), 0.01) << "height " << height;
    for (std::size_t e = 0; e < fem->elements().size(); ++e) EXPECT_GT(fem->deformation_gradient(s.x, e).determinant(), 0.0);
  }
}

TEST(FemDynamics, SoftTissueBlockIsStableAtTheSeedTimeSteps) {
  // Seed 000 Fig. 5 steps soft tissue at 0.01 s and 0.05 s. A 10 cm block of E = 10 kPa,
  // nu = 0.45, clamped at its base and sagging under gravity, must stay finite and settle:
  // after 4 s backward Euler has damped the ~4 Hz fundamental, so the state lies within 10%
  // of the static sag (static solve on the same model).
#ifdef TACTUS_SANITIZED
  const int cells = 3;  // 162 tets: the fundamental and the settling time barely change
#else
  const int cells = 4;
#endif
  for (FemLaw law : {FemLaw::corotational, FemLaw::neo_hookean, FemLaw::linear}) {
    mesh::TetMesh m = mesh::box_volume(Vec3(0.1, 0.1, 0.1), cells, cells, cells);
    Body b;
    b.model = std::make_shared<TetFem>(m, material(law, 1e4, 0.45, 1050.0));
    b.fix_nodes(fem_test::nodes_at(m, 2, -0.05));
    b.gravity = Vec3(-9.81, 0, 0);  // sideways: bending and shear, not just compression
    BodyState ref = make_state(b);
    ASSERT_TRUE(solve_static(b, ref).converged);
    const double sag = (ref.x - b.model->rest_positions()).cwiseAbs().maxCoeff();
    ASSERT_GT(sag, 1e-3);
    for (double dt : {0.01, 0.05}) {
      BodyState s = make_state(b);
      const int steps = static_cast<int>(std::lround(4.0 / dt));
      for (int i = 0; i < steps; ++i) {
        step(b, s, dt);
        ASSERT_TRUE(s.x.allFinite()) << to_string(law) << " dt " << dt << " step " << i;
        ASSERT_LT((s.x - b.model->rest_positions()).cwiseAbs().maxCoeff(), 3 * sag) << to_string(law) << " dt " << dt;
      }
      EXPECT_LT((s.x - ref.x).cwiseAbs().maxCoeff(), 0.1 * sag) << to_string(law) << " dt " << dt;
    }
  }
}

/// A 10 cm block clamped at its base, sagging sideways under gravity with a load on its top
/// face, stepped at 10 ms by Cholesky with one factorization for every `reuse` steps.
struct SaggingBlock {
  mesh::TetMesh mesh = mesh::box_volume(Vec3(0.1, 0.1, 0.1), 3, 3, 3);
  Body body;
  BodyState state;
  VecX load;
  SaggingBlock(FemLaw law, int reuse) {
    FemMaterial mat = material(law, 1e4, 0.45, 1050.0);
    mat.rayleigh_mass = 1.0;
    mat.rayleigh_stiffness = 0.01;
    body.model = std::make_shared<TetFem>(mesh, mat);
    body.fix_nodes(fem_test::nodes_at(mesh, 2, -0.05));
    body.gravity = Vec3(-9.81, 0, 0);
    body.settings.solver = LinearSolver::cholesky;
    body.settings.factor_reuse_steps = reuse;
    state = make_state(body);
    load = VecX::Zero(state.x.size());
    for (std::int32_t n : fem_test::nodes_at(mesh, 2, 0.05)) load[3 * n + 1] = 0.05;
  }
  void run(int steps, int substeps = 1) {
    for (int i = 0; i < steps * substeps; ++i) step(body, state, 0.01 / substeps, load);
  }
};

TEST(FemDynamics, AReusedFactorStepsALinearBodyAsAFreshOne) {
  // A linear law's M + hD + h²K never changes, so the frozen step A·v' = M·v + h·(f_e + f_ext)
  // is the linearized step itself: the two runs agree to round-off (1e-10 of the motion),
  // with a fifth of the factorizations. A slip in the damping or the mass term would move the
  // runs apart by a share of the step (the Rayleigh terms are 1 % and 10 % of it here).
  SaggingBlock fresh(FemLaw::linear, 1), reused(FemLaw::linear, 5);
  fresh.run(40);
  reused.run(40);
  const double motion = (fresh.state.x - fresh.body.model->rest_positions()).norm();
  ASSERT_GT(motion, 1e-3);
  EXPECT_LT((reused.state.x - fresh.state.x).norm(), 1e-10 * motion);
  EXPECT_LT((reused.state.v - fresh.state.v).norm(), 1e-10 * fresh.state.v.norm() + 1e-14);
  EXPECT_EQ(factorizations(fresh.state), 40);
  EXPECT_EQ(factorizations(reused.state), 8);
}

TEST(FemDynamics, AReusedFactorFollowsAHyperelasticBodyClosely) {
  // Neo-Hookean, the tangent of the step that factorized standing in for up to three steps
  // after it (scenes/liver.toml's setting). The lag is held against the step's own error:
  // over 3 s of sagging and swinging, the reused factor's path keeps closer to the fresh
  // one's than the fresh 10 ms path keeps to four 2.5 ms steps (measured: 0.52 against
  // 3.4 mm, of 34 mm of motion; the bound is a quarter), and both settle on the same sag.
  SaggingBlock fresh(FemLaw::neo_hookean, 1), reused(FemLaw::neo_hookean, 4), fine(FemLaw::neo_hookean, 1);
  double lag = 0.0, step_error = 0.0;
  for (int i = 0; i < 300; ++i) {
    fresh.run(1);
    reused.run(1);
    fine.run(1, 4);
    ASSERT_TRUE(reused.state.x.allFinite()) << "step " << i;
    lag = std::max(lag, (reused.state.x - fresh.state.x).cwiseAbs().maxCoeff());
    step_error = std::max(step_error, (fine.state.x - fresh.state.x).cwiseAbs().maxCoeff());
  }
  ::testing::Test::RecordProperty("lag_over_step_error", std::to_string(lag / step_error));
  ASSERT_GT(step_error, 1e-3);
  EXPECT_LT(lag, 0.25 * step_error);
  EXPECT_LT((reused.state.x - fresh.state.x).cwiseAbs().maxCoeff(), 1e-6 * step_error);
  EXPECT_EQ(factorizations(reused.state), 75);
}

// A finger's reaction on a soft organ lands on one or two surface nodes at once, and a coarse
// TetGen surface has thin elements under some of them (scenes/liver.toml: 0.55 N arriving on
// a node above elements of 7e-9 m^3, about 2 mm across, 6 kPa neo-Hookean, dt = 10 ms, the
// linearized implicit step). That step moved the node 3.4 mm, through the elements under it
// (J = -0.29); the next linearization, of inverted elements, overshot further, and within
// four steps the positions were 10^13 m and the Cholesky factorization failed ("not positive
// definite"). The same here: 2 N landing on a node above a 1 mm layer. Every element stays
// right side out and the node settles.
TEST(FemDynamics, LoadLandingOverAThinElementTurnsNoElementInsideOut) {
  // Also with one factorization for four steps (scenes/liver.toml's): a reused step that
  // would turn an element inside out is taken again with a fresh factor, then halved.
  for (int reuse : {1, 4}) {
    FemMaterial mat = material(FemLaw::neo_hookean, 6e3, 0.47, 1060.0);
    mat.rayleigh_mass = 1.0;
    mat.rayleigh_stiffness = 0.01;
    mesh::TetMesh m = mesh::box_volume(Vec3(0.06, 0.06, 0.03), 6, 6, 6);
    for (Vec3& p : m.vertices)
      if (std::abs(p.z() - 0.01) < 1e-9) p.z() = 0.014;  // the top layer 1 mm thick
    auto fem = std::make_shared<TetFem>(m, mat);
    Body b;
    b.model = fem;
    b.settings.integrator = Integrator::implicit_euler;
    b.settings.solver = LinearSolver::cholesky;
    b.settings.factor_reuse_steps = reuse;
    b.gravity = Vec3(0.0, 0.0, -9.81);
    b.fix_nodes(fem_test::nodes_at(m, 2, -0.015));
    std::int32_t top = -1;
    for (std::size_t i = 0; i < m.vertices.size(); ++i)
      if (m.vertices[i].isApprox(Vec3(0.0, 0.0, 0.015), 1e-9)) top = static_cast<std::int32_t>(i);
    ASSERT_GE(top, 0);
    BodyState s = make_state(b);
    VecX load = VecX::Zero(s.x.size());
    load.segment<3>(3 * top) = Vec3(-0.8, 0.0, -2.0);  // pressing in and sideways, all at once
    for (int i = 0; i < 100; ++i) {
      step(b, s, 0.01, load);
      ASSERT_TRUE(s.x.allFinite()) << "reuse " << reuse << " step " << i;
      double j_min = 1.0;
      for (std::size_t e = 0; e < fem->elements().size(); ++e)
        j_min = std::min(j_min, fem->deformation_gradient(s.x, e).determinant());
      ASSERT_GT(j_min, 0.0) << "reuse " << reuse << ": an element inside out after step " << i;
    }
    EXPECT_LT(s.v.cwiseAbs().maxCoeff(), 0.01) << reuse;  // settled after 1 s, not flying off
    EXPECT_LT((s.x - fem->rest_positions()).cwiseAbs().maxCoeff(), 0.03) << reuse;  // the block is 3 cm high
    ::testing::Test::RecordProperty("factorizations_" + std::to_string(reuse), std::to_string(factorizations(s)));
  }
}

TEST(FemDynamics, AnalysingAheadChangesNoStep) {
  // The analysis taken ahead on a copy leaves the steps after it the same bits.
  for (int reuse : {1, 4}) {
    SaggingBlock plain(FemLaw::neo_hookean, reuse), ahead(FemLaw::neo_hookean, reuse);
    const VecX start = ahead.state.x;
    analyse_ahead(ahead.body, ahead.state, 0.01);
    ASSERT_EQ(ahead.state.x, start);
    EXPECT_EQ(factorizations(ahead.state), 0);
    plain.run(9);
    ahead.run(9);
    EXPECT_EQ(plain.state.x, ahead.state.x) << reuse;
    EXPECT_EQ(plain.state.v, ahead.state.v) << reuse;
    EXPECT_EQ(factorizations(plain.state), factorizations(ahead.state)) << reuse;
  }
}

/// Prescribed homogeneous deformation of a unit-cell block (every node fixed), held for
/// `steps` steps of dt; returns the force on the x = +L/2 face's x dofs after each step.
std::vector<double> held_block_reaction(const FemMaterial& mat, const Mat3& F, double dt, int steps, int axis) {
  const double L = 0.01;
  const mesh::TetMesh m = mesh::box_volume(Vec3(L, L, L), 2, 2, 2);
  auto fem = std::make_shared<TetFem>(m, mat);
  Body b;
  b.model = fem;
  b.fixed_dofs.assign(3 * m.vertices.size(), 1);
  BodyState s = make_state(b);
  s.x = fem_test::deformed(s.x, F);
  const auto face = fem_test::nodes_at(m, 0, L / 2);
  std::vector<double> out;
  VecX f;
  auto reaction = [&] {
    fem->forces(s.x, s.v, s.q, f, *s.model_scratch);
    double r = 0.0;
    for (auto n : face) r -= f[3 * n + axis];
    return r;
  };
  out.push_back(reaction());  // t = 0+: the instantaneous response
  for (int i = 0; i < steps; ++i) {
    step(b, s, dt);
    out.push_back(reaction());
  }
  return out;
}

TEST(FemViscoelastic, StandardLinearSolidRelaxesUnderAStepStrain) {
  // One Prony term relaxing bulk and shear alike: E(t) = E0 (g_inf + g exp(-t/tau)), so
  // under a held uniaxial-stress strain the face force is A eps E(t), from E0 at t = 0+ to
  // E_inf = E0 (1 - g). Simo-Hughes' update makes the branch stress exp(-t/tau)
  // (e^x - 1)/x with x = dt/tau, a relative error x/2 = 0.5% of the branch; bound 0.6 g x.
  const double E0 = 1e5, nu = 0.3, g = 0.6, tau = 0.1, dt = 1e-3, eps = 0.01, L = 0.01;
  for (FemLaw law : {FemLaw::linear, FemLaw::corotational}) {
    FemMaterial mat = material(law, E0, nu);
    mat.prony = {{g, tau}};
    mat.prony_relaxes_bulk = true;
    const auto r = held_block_reaction(mat, Vec3(1 + eps, 1 - nu * eps, 1 - nu * eps).asDiagonal(), dt, 500, 0);
    const double scale = E0 * eps * L * L;
    // The corotated strain of diag(1+eps, ...) is exact (R = I); linear strain exact too.
    EXPECT_NEAR(r.front(), scale, 1e-9 * scale) << to_string(law);
    double worst = 0.0;
    for (std::size_t i = 0; i < r.size(); ++i) {
      const double t = static_cast<double>(i) * dt;
      worst = std::max(worst, std::abs(r[i] - scale * (1 - g + g * std::exp(-t / tau))) / scale);
    }
    EXPECT_LT(worst, 0.6 * g * dt / tau) << to_string(law);
    EXPECT_NEAR(r.back(), scale * (1 - g), 0.01 * scale);  // 5 tau: e^-5 = 0.7% left
  }
}

TEST(FemViscoelastic, ShearRelaxationFollowsATwoTermPronySeries) {
  // Simple shear x += gamma z is isochoric, so only the shear modulus acts:
  // face force = mu(t) gamma A with mu(t) = mu (g_inf + g1 e^(-t/tau1) + g2 e^(-t/tau2)).
  // The linear law's strain is exact; error bound as above, summed over the terms.
  const double E0 = 1e5, nu = 0.4, gamma = 0.01, L = 0.01, dt = 5e-4;
  FemMaterial mat = material(FemLaw::linear, E0, nu);
  mat.prony = {{0.3, 0.02}, {0.4, 0.2}};
  Mat3 F = Mat3::Identity();
  F(2, 0) = gamma;  // z displacement grows with x: shear traction on the x faces, along z
  const auto r = held_block_reaction(mat, F, dt, 1000, 2);
  const double mu = E0 / (2 * (1 + nu)), scale = mu * gamma * L * L;
  double worst = 0.0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double t = static_cast<double>(i) * dt;
    const double expected = scale * (0.3 + 0.3 * std::exp(-t / 0.02) + 0.4 * std::exp(-t / 0.2));
    worst = std::max(worst, std::abs(r[i] - expected) / scale);
  }
  EXPECT_LT(worst, 0.6 * (0.3 * dt / 0.02 + 0.4 * dt / 0.2));
  EXPECT_NEAR(r.front(), scale, 1e-9 * scale);
}

const std::vector<FemLaw>& hyperelastic_laws() {
  static const std::vector<FemLaw> laws{FemLaw::stvk, FemLaw::neo_hookean, FemLaw::mooney_rivlin};
  return laws;
}

TEST(FemViscoelastic, HyperelasticLawsRelaxAsTheStandardLinearSolidAtSmallStrain) {
  // The same held uniaxial-stress step strain as the linear test, at eps = 1e-4 so that every
  // law's instantaneous response is Hooke's to O(eps) (bound 1e-3 of the force); the
  // relaxation then follows E(t) = E0 (g_inf + g exp(-t/tau)) with the Simo-Hughes bound above.
  const double E0 = 1e5, nu = 0.3, g = 0.6, tau = 0.1, dt = 1e-3, eps = 1e-4, L = 0.01;
  for (FemLaw law : hyperelastic_laws()) {
    FemMaterial mat = material(law, E0, nu);
    mat.prony = {{g, tau}};
    mat.prony_relaxes_bulk = true;
    const auto r = held_block_reaction(mat, Vec3(1 + eps, 1 - nu * eps, 1 - nu * eps).asDiagonal(), dt, 500, 0);
    const double scale = E0 * eps * L * L;
    EXPECT_NEAR(r.front(), scale, 1e-3 * scale) << to_string(law);
    double worst = 0.0;
    for (std::size_t i = 0; i < r.size(); ++i) {
      const double t = static_cast<double>(i) * dt;
      worst = std::max(worst, std::abs(r[i] - scale * (1 - g + g * std::exp(-t / tau))) / scale);
    }
    EXPECT_LT(worst, 0.6 * g * dt / tau + 1e-3) << to_string(law);
  }
}

TEST(FemViscoelastic, EveryLawRelaxesByGInfinityAtLargeStrain) {
  // A held finite deformation (30% stretch, shear and a rotation): the branches relax the
  // whole instantaneous stress, so after 25 tau (two terms, e^-25 ~ 1e-11 left) every nodal
  // force is g_inf times its instantaneous value. Bound 1e-9 of the largest force.
  const double g1 = 0.3, g2 = 0.45, g_inf = 1 - g1 - g2;
  Mat3 F = fem_test::rotation(0.5, Vec3(1, 1, 0)) * Vec3(1.3, 0.85, 0.95).asDiagonal();
  F(0, 2) += 0.2;
  for (FemLaw law : fem_test::all_laws()) {
    FemMaterial mat = material(law, 1e5, 0.4);
    mat.prony = {{g1, 0.02}, {g2, 0.1}};
    mat.prony_relaxes_bulk = true;
    const mesh::TetMesh m = mesh::box_volume(Vec3(0.01, 0.01, 0.01), 2, 2, 2);
    Body b;
    b.model = std::make_shared<TetFem>(m, mat);
    b.fixed_dofs.assign(3 * m.vertices.size(), 1);
    BodyState s = make_state(b);
    s.x = fem_test::deformed(s.x, F);
    VecX instantaneous, relaxed;
    b.model->forces(s.x, s.v, s.q, instantaneous, *s.model_scratch);
    for (int i = 0; i < 250; ++i) step(b, s, 0.01);
    b.model->forces(s.x, s.v, s.q, relaxed, *s.model_scratch);
    EXPECT_LT((relaxed - g_inf * instantaneous).cwiseAbs().maxCoeff(), 1e-9 * instantaneous.cwiseAbs().maxCoeff())
        << to_string(law);
  }
}

TEST(FemViscoelastic, HyperelasticTangentIncludesTheBranchStress) {
  // With branch stresses O the force is -V F (S0 + O) g_a; its exact (unprojected) tangent
  // must match central differences of the force (step 1e-7: error O(h^2) ~ 1e-12 of K dx,
  // round-off ~ 1e-9; bound 1e-6).
  const mesh::TetMesh m = mesh::box_volume(Vec3(0.02, 0.02, 0.02), 1, 1, 1);
  for (FemLaw law : hyperelastic_laws()) {
    FemMaterial mat = material(law, 1e4, 0.35);
    mat.prony = {{0.4, 0.05}};
    mat.project_tangent = false;
    const TetFem fem(m, mat);
    auto s = fem.make_scratch();
    VecX x = fem_test::deformed(fem.rest_positions(), fem_test::rotation(0.3, Vec3(0, 1, 1)) *
                                                        Vec3(1.15, 0.9, 1.05).asDiagonal());
    // Branch history of a real relaxation: one step from rest to x.
    VecX q = VecX::Zero(static_cast<Eigen::Index>(fem.internal_size()));
    fem.update_internal(x, 0.01, q, *s);
    x = fem_test::deformed(fem.rest_positions(), Vec3(1.05, 1.0, 0.98).asDiagonal());
    const VecX v = VecX::Zero(x.size());
    VecX dx(x.size());
    for (Eigen::Index i = 0; i < dx.size(); ++i) dx[i] = std::sin(1.7 * static_cast<double>(i) + 0.3);
    fem.linearize(x, v, q, *s);
    VecX k = VecX::Zero(x.size());
    fem.add_stiffness_product(dx, k, *s);
    const double h = 1e-7;
    VecX fp(x.size()), fm(x.size());
    fem.forces(x + h * dx, v, q, fp, *s);
    fem.forces(x - h * dx, v, q, fm, *s);
    EXPECT_LT((k + (fp - fm) / (2 * h)).norm(), 1e-6 * k.norm()) << to_string(law);
    // And the offset is really there: the force differs from the elastic one.
    VecX elastic(x.size()), viscous(x.size());
    fem.forces(x, v, VecX(), elastic, *s);
    fem.forces(x, v, q, viscous, *s);
    EXPECT_GT((viscous - elastic).norm(), 1e-3 * elastic.norm()) << to_string(law);
  }
}

TEST(FemViscoelastic, HyperelasticBlockCreepsUnderConstantLoadToTheRelaxedElasticSolution) {
  // A block clamped at its base carries a constant tensile load on its top face. Quasi-static
  // creep: equilibrium at each time, then the branches relax over dt. At t = 0+ the block
  // is the elastic block under the load; as t -> infinity the stress is g_inf S0(F), so the
  // block is the elastic block under load / g_inf, a solve with no history. Required: a
  // monotone rise between the two (creep), both ends within 1e-6 of the displacement
  // (static tolerances 1e-10; e^-40 of the history left).
  const double g = 0.5, tau = 0.1, size = 0.01;
  const mesh::TetMesh m = mesh::box_volume(Vec3(size, size, size), 2, 2, 2);
  const auto top = fem_test::nodes_at(m, 2, size / 2);
  for (FemLaw law : hyperelastic_laws()) {
    FemMaterial mat = material(law, 1e4, 0.3);
    auto tip = [&](const FemMaterial& mm, double load_scale, int steps, std::vector<double>* history) {
      Body b;
      b.model = std::make_shared<TetFem>(m, mm);
      b.fix_nodes(fem_test::nodes_at(m, 2, -size / 2));
      b.settings.solver = LinearSolver::cholesky;
      VecX f = VecX::Zero(b.model->rest_positions().size());
      for (auto n : top) f[3 * n + 2] = load_scale * 0.1 / static_cast<double>(top.size());  // 1 kPa
      BodyState s = make_state(b);
      auto lift = [&] {
        double sum = 0.0;
        for (auto n : top) sum += s.x[3 * n + 2] - b.model->rest_positions()[3 * n + 2];
        return sum / static_cast<double>(top.size());
      };
      EXPECT_TRUE(solve_static(b, s, f, 50, 1e-10).converged) << to_string(law);
      if (history) history->push_back(lift());
      for (int i = 0; i < steps; ++i) {
        b.model->update_internal(s.x, tau / 10, s.q, *s.model_scratch);
        EXPECT_TRUE(solve_static(b, s, f, 50, 1e-10).converged) << to_string(law) << " step " << i;
        if (history) history->push_back(lift());
      }
      return lift();
    };
    const double instantaneous = tip(mat, 1.0, 0, nullptr);
    const double relaxed = tip(mat, 1.0 / (1 - g), 0, nullptr);
    mat.prony = {{g, tau}};
    mat.prony_relaxes_bulk = true;
    std::vector<double> history;
    tip(mat, 1.0, 400, &history);
    EXPECT_GT(relaxed, 1.5 * instantaneous) << to_string(law);  // the creep is large
    EXPECT_NEAR(history.front(), instantaneous, 1e-6 * instantaneous) << to_string(law);
    EXPECT_NEAR(history.back(), relaxed, 1e-6 * relaxed) << to_string(law);
    for (std::size_t i = 1; i < history.size(); ++i) ASSERT_GE(history[i], history[i - 1] - 1e-12) << to_string(law);
  }
}

}  // namespace
}  // namespace tactus::physics
