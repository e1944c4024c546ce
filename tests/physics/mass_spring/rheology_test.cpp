// Creep and relaxation of Kelvin–Voigt and standard-linear-solid springs against their
// closed forms, for one spring and for a tetrahedral block.
#include <gtest/gtest.h>

#include <cmath>

#include "ms_test_util.hpp"
#include "physics/mass_spring/tet_builder.hpp"
#include "physics/mass_spring/viscoelastic.hpp"

namespace tactus::physics {
namespace {

using test::force_sum;
using test::nodes_at;

/// One spring along x from a fixed node 0 to node 1 (0.1 m), node 1 of mass m.
Body one_spring(double k, double c, const std::vector<SpringArm>& arms, double mass) {
  VecX rest(6);
  rest << 0, 0, 0, 0.1, 0, 0;
  auto net = std::make_shared<SpringNetwork>(rest, Eigen::Vector2d(1.0, mass));
  net->add_spring(0, 1, k, c, arms);
  Body b;
  b.model = net;
  b.fix_nodes({0});
  b.settings.cg_tolerance = 1e-12;
  return b;
}

TEST(Rheology, KelvinVoigtSpringCreepsAsTheClosedForm) {
  // u(t) = (F/k)(1 − e^(−t k/c)). The node mass 1e-6 kg adds an inertial time m/c = 1e-7 s,
  // negligible against c/k = 0.05 s. Implicit Euler at dt = 1e-4 has a first-order error
  // about dt/(2·0.05) = 0.1% of F/k; 2e-3 allows that and fails for a wrong c or k (errors of
  // tens of percent).
  const double k = 200.0, c = 10.0, force = 2.0, dt = 1e-4;
  Body b = one_spring(k, c, {}, 1e-6);
  BodyState s = make_state(b);
  VecX f = VecX::Zero(6);
  f[3] = force;
  double worst = 0.0;
  for (int i = 1; i <= 3000; ++i) {
    step(b, s, dt, f);
    worst = std::max(worst, std::abs((s.x[3] - 0.1) - force / k * (1.0 - std::exp(-i * dt * k / c))));
  }
  EXPECT_LT(worst / (force / k), 2e-3);
}

TEST(Rheology, StandardLinearSolidRelaxesExactlyUnderHeldStrain) {
  // F(t) = ε (k∞ + k1 e^(−t/τ)), τ = c1/k1. The arm update is the exact solution for a held
  // strain, so only round-off separates the two: 1e-12 relative. Checked at dt = τ/10 and at
  // dt = 10τ (stable and exact for any step).
  const double kinf = 100.0, k1 = 300.0, c1 = 30.0, tau = c1 / k1, strain = 0.01;
  for (double dt : {tau / 10, 10 * tau}) {
    Body b = one_spring(kinf, 0.0, {{k1, c1}}, 1e-3);
    b.fix_nodes({0, 1});
    BodyState s = make_state(b);
    s.x[3] += strain;
    for (int i = 0; i <= 50; ++i) {
      const double t = i * dt;
      const double expected = strain * (kinf + k1 * std::exp(-t / tau));
      EXPECT_NEAR(-force_sum(*b.model, s, {1}, 0), expected, 1e-12 * strain * (kinf + k1)) << "t = " << t;
      step(b, s, dt);
    }
  }
}

TEST(Rheology, StandardLinearSolidCreepsWithTheRetardationTime) {
  // Under a constant force F the elongation goes from F/(k∞ + k1) to F/k∞ with the retardation
  // time τ_c = c1 (k∞ + k1)/(k∞ k1) = 0.4 s (not the relaxation time c1/k1 = 0.1 s). Node mass
  // 1e-9 kg: the inertial period 2π√(m/k) ≈ 10 µs is damped out by implicit Euler within the
  // first steps, so errors are counted from t = 2 ms. The arm update is first order in
  // dt/τ = 1e-3, so 2e-3 of F/k∞; using τ = 0.1 s instead of τ_c would fail by ~30%.
  const double kinf = 100.0, k1 = 300.0, c1 = 30.0, force = 1.0, dt = 1e-4;
  const double tau_c = c1 * (kinf + k1) / (kinf * k1);
  Body b = one_spring(kinf, 0.0, {{k1, c1}}, 1e-9);
  BodyState s = make_state(b);
  VecX f = VecX::Zero(6);
  f[3] = force;
  double worst = 0.0;
  for (int i = 1; i <= 20000; ++i) {
    step(b, s, dt, f);
    const double t = i * dt;
    const double expected = force / kinf - (force / kinf - force / (kinf + k1)) * std::exp(-t / tau_c);
    if (t >= 2e-3) worst = std::max(worst, std::abs((s.x[3] - 0.1) - expected));
  }
  EXPECT_LT(worst / (force / kinf), 2e-3);
}

TEST(Rheology, PronyAndSlsParametersMapToArms) {
  // Prony normalized on E0: E(t)/E0 = g∞ + Σ g_i e^(−t/τ_i); relative to E∞ that is
  // (g∞ + Σ g_i e^(−t/τ_i))/g∞.
  const auto p = ViscoelasticParams::prony({{0.5, 0.2}, {0.2, 3.0}});
  for (double t : {0.0, 0.1, 1.0, 10.0})
    EXPECT_NEAR(p.relaxation_ratio(t), (0.3 + 0.5 * std::exp(-t / 0.2) + 0.2 * std::exp(-t / 3.0)) / 0.3, 1e-12);
  const auto sls = ViscoelasticParams::standard_linear_solid(10e3, 30e3, 0.5);
  EXPECT_DOUBLE_EQ(sls.instantaneous_ratio(), 4.0);
  EXPECT_THROW(ViscoelasticParams::prony({{0.6, 1.0}, {0.5, 1.0}}), InputError);
  EXPECT_THROW(ViscoelasticParams::kelvin_voigt(-1.0), InputError);
}

// --- A 20 mm cube of 3×3×3 cells, bottom face fixed, loaded or displaced on its top face.

struct Block {
  Body body;
  std::vector<std::int32_t> top;
};

Block block(const ViscoelasticParams& visco) {
  const auto m = mesh::box_volume(Vec3(0.02, 0.02, 0.02), 3, 3, 3);
  TetSpringParams p;
  p.youngs_modulus = 5e3;
  // A light block (1 kg/m³): its stiffest inertial period (~1 ms) is far below the 50 ms
  // viscous times and is damped by implicit Euler in a few steps, so the curves are the
  // quasi-static rheology, as in a creep or relaxation test.
  p.density = 1.0;
  p.viscoelastic = visco;
  Block out;
  out.body.model = tet_mass_spring(m, p);
  out.body.fix_nodes(nodes_at(out.body.model->rest_positions(), 2, -0.01));
  out.body.settings.solver = LinearSolver::cholesky;  // the light block is ill-conditioned for CG
  out.top = nodes_at(out.body.model->rest_positions(), 2, 0.01);
  return out;
}

double mean_top_z(const Block& b, const BodyState& s) {
  double z = 0.0;
  for (auto n : b.top) z += s.x[3 * n + 2] - 0.01;
  return z / static_cast<double>(b.top.size());
}

VecX top_load(const Block& b, double total) {
  VecX f = VecX::Zero(b.body.model->rest_positions().size());
  for (auto n : b.top) f[3 * n + 2] = total / static_cast<double>(b.top.size());
  return f;
}

/// Static top displacement under the load with the long-term springs only.
double long_term_displacement(double total) {
  Block b = block({});
  BodyState s = make_state(b.body);
  EXPECT_TRUE(solve_static(b.body, s, top_load(b, total)).converged);
  return mean_top_z(b, s);
}

TEST(Rheology, KelvinVoigtBlockCreepsMonotonicallyToTheStaticDisplacement) {
  // Dashpots proportional to the springs (c = τ k) make the block one Kelvin–Voigt element
  // with K_eff = F/u∞: u(t) = u∞ (1 − e^(−t/τ)). Tolerances: monotone to 1e-9 u∞ (round-off),
  // the closed form within 2% of u∞ (implicit Euler's dt/2τ = 1% plus the finite-strain
  // nonlinearity at 1% strain), the end within 0.5%.
  const double load = 0.02, tau = 0.05, dt = 1e-3;
  const double u_inf = long_term_displacement(load);
  Block b = block(ViscoelasticParams::kelvin_voigt(tau));
  BodyState s = make_state(b.body);
  const VecX f = top_load(b, load);
  double previous = 0.0, worst = 0.0;
  for (int i = 1; i <= 500; ++i) {
    step(b.body, s, dt, f);
    const double u = mean_top_z(b, s);
    ASSERT_GE(u, previous - 1e-9 * u_inf) << "step " << i;
    worst = std::max(worst, std::abs(u - u_inf * (1.0 - std::exp(-i * dt / tau))));
    previous = u;
  }
  EXPECT_LT(worst, 0.02 * u_inf);
  EXPECT_NEAR(previous, u_inf, 0.005 * u_inf);
}

TEST(Rheology, KelvinVoigtBlockDoesNotRelaxUnderHeldDisplacement) {
  // What seed 000's Voigt model cannot do: with the top held, the reaction stays constant.
  Block b = block(ViscoelasticParams::kelvin_voigt(0.05));
  b.body.fix_nodes(b.top);
  BodyState s = make_state(b.body);
  for (auto n : b.top) s.x[3 * n + 2] += 2e-4;
  ASSERT_TRUE(solve_static(b.body, s).converged);
  const double f0 = force_sum(*b.body.model, s, b.top, 2);
  for (int i = 0; i < 300; ++i) step(b.body, s, 1e-3);
  EXPECT_NEAR(force_sum(*b.body.model, s, b.top, 2), f0, 1e-6 * std::abs(f0));
}

TEST(Rheology, StandardLinearSolidBlockRelaxesUnderHeldDisplacement) {
  // Every spring carries the same arm (k1 = g k, τ), so the instantaneous equilibrium stays the
  // equilibrium while the arms relax and the reaction follows F(t) = F∞ (1 + g e^(−t/τ)). The
  // arm update is exact for a held strain; 1e-5 covers the static solve and CG tolerances.
  const double g = 2.0, tau = 0.1, dt = 1e-3;
  Block b = block(ViscoelasticParams::standard_linear_solid(1.0, g, tau));
  b.body.fix_nodes(b.top);
  BodyState s = make_state(b.body);
  for (auto n : b.top) s.x[3 * n + 2] += 2e-4;
  ASSERT_TRUE(solve_static(b.body, s).converged);
  const double f0 = force_sum(*b.body.model, s, b.top, 2);
  double previous = std::abs(f0);
  for (int i = 1; i <= 500; ++i) {
    step(b.body, s, dt);
    const double fz = std::abs(force_sum(*b.body.model, s, b.top, 2));
    EXPECT_LT(fz, previous);
    EXPECT_NEAR(fz, std::abs(f0) * (1.0 + g * std::exp(-i * dt / tau)) / (1.0 + g), 1e-5 * std::abs(f0));
    previous = fz;
  }
}

TEST(Rheology, StandardLinearSolidBlockCreepsToTheLongTermDisplacement) {
  // From u∞/(1 + g) to u∞ with the retardation time τ (1 + g). Monotone after the first
  // 10 ms (the light block's inertial transient); the closed form within 2% of u∞ (first-order
  // arm update at dt/τ = 1%, finite strain); the end within 0.5%.
  const double g = 2.0, tau = 0.1, dt = 1e-3, load = 0.02;
  const double u_inf = long_term_displacement(load);
  Block b = block(ViscoelasticParams::standard_linear_solid(1.0, g, tau));
  BodyState s = make_state(b.body);
  const VecX f = top_load(b, load);
  double previous = 0.0, worst = 0.0;
  for (int i = 1; i <= 2000; ++i) {
    step(b.body, s, dt, f);
    const double u = mean_top_z(b, s);
    const double t = i * dt;
    if (t > 0.01) {
      ASSERT_GE(u, previous - 1e-9 * u_inf) << "t = " << t;
      worst = std::max(worst, std::abs(u - (u_inf - (u_inf - u_inf / (1 + g)) * std::exp(-t / (tau * (1 + g))))));
    }
    previous = u;
  }
  EXPECT_LT(worst, 0.02 * u_inf);
  EXPECT_NEAR(previous, u_inf, 0.005 * u_inf);
}

}  // namespace
}  // namespace tactus::physics
