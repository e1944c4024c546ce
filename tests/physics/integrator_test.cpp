// Integrators and static solves against closed-form mechanics, on a model small enough to
// check by hand: linear (isotropic) springs with parallel dashpots between nodes.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <thread>

#include "physics/body.hpp"

namespace tactus::physics {
namespace {

/// Nodes on the x axis joined by linear springs f = −k (d − d0) and dashpots f = −c ḋ,
/// where d = x_j − x_i. Linear, so K and D are exact and constant.
class SpringChain final : public ForceModel {
 public:
  SpringChain(int nodes, double spacing, double mass, double k, double c) : k_(k), c_(c) {
    rest_ = VecX::Zero(3 * nodes);
    for (int i = 0; i < nodes; ++i) rest_[3 * i] = i * spacing;
    mass_ = VecX::Constant(3 * nodes, mass);
  }
  std::size_t node_count() const override { return static_cast<std::size_t>(rest_.size() / 3); }
  const VecX& rest_positions() const override { return rest_; }
  const VecX& lumped_mass() const override { return mass_; }

  void forces(const VecX& x, const VecX& v, const VecX&, VecX& f, Scratch&) const override {
    f.setZero();
    for (Eigen::Index i = 0; i + 3 < x.size(); i += 3) {
      const Vec3 d = x.segment<3>(i + 3) - x.segment<3>(i) - (rest_.segment<3>(i + 3) - rest_.segment<3>(i));
      const Vec3 dv = v.segment<3>(i + 3) - v.segment<3>(i);
      const Vec3 fs = k_ * d + c_ * dv;
      f.segment<3>(i) += fs;
      f.segment<3>(i + 3) -= fs;
    }
  }
  void linearize(const VecX&, const VecX&, const VecX&, Scratch&) const override {}
  void add_stiffness_product(const VecX& dx, VecX& out, const Scratch&) const override { laplacian(k_, dx, out); }
  void add_damping_product(const VecX& dv, VecX& out, const Scratch&) const override { laplacian(c_, dv, out); }
  void add_diagonal(double a, double b, VecX& out, const Scratch&) const override {
    for (Eigen::Index i = 0; i + 3 < out.size(); i += 3)
      for (int j = 0; j < 6; ++j) out[i + j] += a * k_ + b * c_;
  }
  void add_triplets(double a, double b, std::vector<Triplet>& out, const Scratch&) const override {
    const double w = a * k_ + b * c_;
    for (Eigen::Index i = 0; i + 3 < rest_.size(); i += 3)
      for (int j = 0; j < 3; ++j) {
        out.emplace_back(i + j, i + j, w);
        out.emplace_back(i + 3 + j, i + 3 + j, w);
        out.emplace_back(i + j, i + 3 + j, -w);
        out.emplace_back(i + 3 + j, i + j, -w);
      }
  }
  double elastic_energy(const VecX& x, const VecX&) const override {
    double e = 0.0;
    for (Eigen::Index i = 0; i + 3 < x.size(); i += 3) {
      const Vec3 d = x.segment<3>(i + 3) - x.segment<3>(i) - (rest_.segment<3>(i + 3) - rest_.segment<3>(i));
      e += 0.5 * k_ * d.squaredNorm();
    }
    return e;
  }

 private:
  void laplacian(double w, const VecX& in, VecX& out) const {
    for (Eigen::Index i = 0; i + 3 < in.size(); i += 3) {
      const Vec3 d = w * (in.segment<3>(i) - in.segment<3>(i + 3));
      out.segment<3>(i) += d;
      out.segment<3>(i + 3) -= d;
    }
  }
  VecX rest_, mass_;
  double k_, c_;
};

Body oscillator(Integrator integrator, double c = 0.0) {
  Body b;
  b.model = std::make_shared<SpringChain>(2, 0.1, 0.5, 200.0, c);
  b.fix_nodes({0});
  b.settings.integrator = integrator;
  return b;
}

// One mass m on a spring k, released from x = A: x(t) = A cos(ω t), ω = √(k/m) = 20 rad/s.
double error_after_one_second(Integrator integrator, double dt) {
  Body b = oscillator(integrator);
  BodyState s = make_state(b);
  const double amplitude = 0.01;
  s.x[3] += amplitude;
  const int steps = static_cast<int>(std::lround(1.0 / dt));
  for (int i = 0; i < steps; ++i) step(b, s, dt);
  return std::abs((s.x[3] - 0.1) - amplitude * std::cos(20.0 * 1.0)) / amplitude;
}

TEST(Integrators, Rk4MatchesTheHarmonicOscillator) {
  // RK4 is fourth order: at ω·dt = 0.02 its phase error over 20 rad is ~1e-7.
  EXPECT_LT(error_after_one_second(Integrator::rk4, 1e-3), 1e-5);
}

TEST(Integrators, FirstOrderMethodsConvergeAtFirstOrder) {
  for (auto integ : {Integrator::symplectic_euler, Integrator::implicit_euler}) {
    const double coarse = error_after_one_second(integ, 1e-3);
    const double fine = error_after_one_second(integ, 2.5e-4);
    EXPECT_LT(fine, coarse) << static_cast<int>(integ);
    EXPECT_LT(fine, 0.15) << static_cast<int>(integ);
  }
}

TEST(Integrators, SymplecticEulerConservesEnergyOver10000Steps) {
  Body b = oscillator(Integrator::symplectic_euler);
  BodyState s = make_state(b);
  s.x[3] += 0.01;
  const double e0 = kinetic_energy(b, s) + potential_energy(b, s);
  double worst = 0.0;
  for (int i = 0; i < 10000; ++i) {
    step(b, s, 1e-3);
    worst = std::max(worst, std::abs(kinetic_energy(b, s) + potential_energy(b, s) - e0) / e0);
  }
  // Symplectic Euler's energy oscillates with amplitude ~ ω·dt/2 = 1% and does not drift;
  // the mean over the last period must stay within 1% of the start.
  EXPECT_LT(worst, 0.011);
}

TEST(Integrators, ImplicitEulerNeverGainsEnergy) {
  for (auto solver : {LinearSolver::conjugate_gradient, LinearSolver::cholesky}) {
    Body b = oscillator(Integrator::implicit_euler);
    b.settings.solver = solver;
    b.settings.cg_tolerance = 1e-10;
    BodyState s = make_state(b);
    s.x[3] += 0.01;
    const double e0 = kinetic_energy(b, s) + potential_energy(b, s);
    double e = e0;
    for (int i = 0; i < 2000; ++i) {
      step(b, s, 1e-2);  // ω·dt = 0.2
      const double e_next = kinetic_energy(b, s) + potential_energy(b, s);
      // Round-off allowance relative to the initial energy (the energy decays to ~1e-28 e0).
      ASSERT_LE(e_next, e + 1e-14 * e0) << "step " << i;
      e = e_next;
    }
  }
}

std::size_t thread_count_of_process() {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) ++n;
  return n;
}

// CHOLMOD's OpenMP regions (a team of 4 per factorization) cost futex wake-ups and context
// switches per supernode on a shared 2-core machine, for loops that BLAS's arithmetic
// dwarfs: Cholesky steps run them on the calling thread, so they start no thread, and the
// factor is the same bits as with a team.
TEST(Integrators, CholeskyStepsStartNoOpenMpTeam) {
  Body b;
  b.model = std::make_shared<SpringChain>(400, 0.01, 0.01, 200.0, 0.1);  // 1,200 dofs: CHOLMOD's regions run
  b.fix_nodes({0});
  b.settings.integrator = Integrator::implicit_euler;
  b.settings.solver = LinearSolver::cholesky;
  BodyState s = make_state(b);
  s.x[3 * 399] += 0.01;
  // ThreadSanitizer's runtime starts a thread of its own with the process's first thread:
  // start one first, so that only threads the steps start are counted.
  std::thread([] {}).join();
  const std::size_t before = thread_count_of_process();
  std::thread([&] {  // a fresh thread, as the simulation loop's
    for (int i = 0; i < 5; ++i) step(b, s, 1e-2);
  }).join();
  for (int i = 0; i < 5; ++i) step(b, s, 1e-2);
  EXPECT_EQ(thread_count_of_process(), before);
  EXPECT_TRUE(s.x.allFinite());
}

TEST(Integrators, ExplicitEulerGainsEnergyAsTheTheoryPredicts) {
  // Explicit Euler multiplies the oscillator's energy by (1 + ω²dt²) every step.
  Body b = oscillator(Integrator::explicit_euler);
  BodyState s = make_state(b);
  s.x[3] += 0.01;
  const double e0 = kinetic_energy(b, s) + potential_energy(b, s);
  for (int i = 0; i < 100; ++i) step(b, s, 1e-3);
  const double e = kinetic_energy(b, s) + potential_energy(b, s);
  EXPECT_NEAR(e / e0, std::pow(1.0 + 400.0 * 1e-6, 100), 1e-9);
}

TEST(Integrators, KelvinVoigtCreepFollowsTheClosedForm) {
  // Spring k and dashpot c in parallel, massless limit approached with a light node, under a
  // step force F: u(t) = (F/k)(1 − exp(−t k/c)). The node mass (1e-6 kg) adds an inertial
  // time m/c = 1e-7 s, negligible against k/c's time constant c/k = 0.05 s. Implicit Euler at
  // dt = 1e-4 has a first-order error ~ dt/(2τ) = 0.1% of F/k.
  Body b;
  const double k = 200.0, c = 10.0, force = 2.0;
  b.model = std::make_shared<SpringChain>(2, 0.1, 1e-6, k, c);
  b.fix_nodes({0});
  b.settings.cg_tolerance = 1e-12;
  BodyState s = make_state(b);
  VecX f = VecX::Zero(6);
  f[3] = force;
  const double dt = 1e-4;
  double worst = 0.0;
  for (int i = 1; i <= 2000; ++i) {
    step(b, s, dt, f);
    const double t = i * dt;
    const double expected = force / k * (1.0 - std::exp(-t * k / c));
    worst = std::max(worst, std::abs((s.x[3] - 0.1) - expected));
  }
  EXPECT_LT(worst / (force / k), 2e-3);
}

TEST(Integrators, FixedNodesStayPut) {
  Body b = oscillator(Integrator::implicit_euler);
  b.gravity = Vec3(0, 0, -9.81);
  BodyState s = make_state(b);
  for (int i = 0; i < 100; ++i) step(b, s, 1e-3);
  EXPECT_EQ(s.x.segment<3>(0), Vec3::Zero());
  EXPECT_LT(s.x[5], 0.0);  // the free node falls
}

TEST(StaticSolve, ChainUnderTipLoadStretchesBySumOfCompliances) {
  for (auto solver : {LinearSolver::conjugate_gradient, LinearSolver::cholesky}) {
    Body b;
    b.model = std::make_shared<SpringChain>(5, 0.1, 0.01, 100.0, 0.0);
    b.fix_nodes({0});
    b.settings.solver = solver;
    b.settings.cg_tolerance = 1e-12;
    BodyState s = make_state(b);
    VecX f = VecX::Zero(15);
    f[12] = 3.0;
    const auto r = solve_static(b, s, f);
    EXPECT_TRUE(r.converged);
    EXPECT_NEAR(s.x[12] - 0.4, 4 * 3.0 / 100.0, 1e-9);
  }
}

TEST(ForceModel, DefaultSystemProductIsMassPlusDampingPlusStiffness) {
  // out += (a M + b D + c K) in, accumulated onto what out holds.
  SpringChain chain(4, 0.1, 0.5, 200.0, 3.0);
  auto scratch = chain.make_scratch();
  VecX in(12), out = VecX::Constant(12, 1.0), expected = VecX::Constant(12, 1.0), k = VecX::Zero(12),
               d = VecX::Zero(12);
  for (Eigen::Index i = 0; i < in.size(); ++i) in[i] = std::sin(1.0 + static_cast<double>(i));
  chain.add_stiffness_product(in, k, *scratch);
  chain.add_damping_product(in, d, *scratch);
  const double a = 2.0, b = 0.3, c = 1e-2;
  expected += a * chain.lumped_mass().cwiseProduct(in) + b * d + c * k;
  chain.add_system_product(a, b, c, in, out, *scratch);
  EXPECT_LT((out - expected).norm(), 1e-12 * expected.norm());
}

TEST(Step, RejectsNonPositiveTimeStep) {
  Body b = oscillator(Integrator::implicit_euler);
  BodyState s = make_state(b);
  EXPECT_THROW(step(b, s, 0.0), std::invalid_argument);
  EXPECT_THROW(step(b, s, std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace tactus::physics
