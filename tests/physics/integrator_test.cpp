// Integrators and static solves against closed-form mechanics, on a model small enough to
// check by hand: linear (isotropic) springs with parallel dashpots between nodes.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <thread>
#include <vector>

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

// --- Contact springs: the hand's push coupled into the implicit step ---------------------

/// A light node (1 g) on a 200 N/m tissue spring with a 0.1 N·s/m dashpot: one implicit
/// 10 ms step takes it 91 % of the way to its static position under a load,
/// h²k / (m + h·c + h²k) = 0.02 / 0.022.
Body tissue_node(LinearSolver solver = LinearSolver::conjugate_gradient) {
  Body b;
  b.model = std::make_shared<SpringChain>(2, 0.1, 0.001, 200.0, 0.1);
  b.fix_nodes({0});
  b.settings.integrator = Integrator::implicit_euler;
  b.settings.solver = solver;
  b.settings.cg_tolerance = 1e-12;
  return b;
}

/// A finger held still 2 N deep into the node at rest, through a 300 N/m proxy spring, pushing
/// along +x; each 10 ms period starts from the force the haptic loop renders at the node's
/// position then, as the simulation loop does. Returns the forces rendered, one per period.
std::vector<double> press(bool coupled, LinearSolver solver = LinearSolver::conjugate_gradient) {
  const Body b = tissue_node(solver);
  BodyState s = make_state(b);
  const double k_contact = 300.0, finger = 0.1 + 2.0 / k_contact;
  const std::array<NodeShare, 1> node{{{1, 1.0}}};
  std::vector<double> rendered;
  for (int period = 0; period < 60; ++period) {
    const double force = std::max(0.0, k_contact * (finger - s.x[3]));
    rendered.push_back(force);
    std::array<ContactSpring, 1> spring{{{node, Vec3::UnitX(), force, coupled ? k_contact : 0.0, force}}};
    step(b, s, 0.01, {}, spring);
  }
  return rendered;
}

TEST(ContactSprings, ThePushSettlesWhereTissueAndContactBalance) {
  // Two springs in series: F = F0·k_t / (k_t + k_c) = 2 · 200 / 500 = 0.8 N, the tissue 4 mm in.
  for (const auto solver : {LinearSolver::conjugate_gradient, LinearSolver::cholesky}) {
    const std::vector<double> f = press(true, solver);
    EXPECT_NEAR(f.back(), 0.8, 1e-6) << static_cast<int>(solver);
    double swing = 0.0;  // after the first periods, no period-to-period swing
    for (std::size_t i = 21; i < f.size(); ++i) swing = std::max(swing, std::abs(f[i] - f[i - 1]));
    EXPECT_LT(swing, 1e-6) << static_cast<int>(solver);
  }
}

TEST(ContactSprings, AConstantPushOverThePeriodSwingsForever) {
  // The failure the coupling removes: the push held constant over each period moves the
  // tissue most of the way to F/k_t, and with k_c > k_t the next period's push overshoots the
  // other way (gain −1.5 · 0.91), until it swings between nothing and a full push.
  const std::vector<double> f = press(false);
  double swing = 0.0;
  for (std::size_t i = f.size() - 10; i < f.size(); ++i) swing = std::max(swing, std::abs(f[i] - f[i - 1]));
  EXPECT_GT(swing, 1.0);
}

TEST(ContactSprings, WithoutStiffnessTheyAreTheConstantLoad) {
  for (const auto solver : {LinearSolver::conjugate_gradient, LinearSolver::cholesky}) {
    const Body b = tissue_node(solver);
    BodyState with_spring = make_state(b), with_load = make_state(b);
    const std::array<NodeShare, 1> node{{{1, 1.0}}};
    VecX load = VecX::Zero(6);
    load.segment<3>(3) = 1.5 * Vec3(0.6, 0.0, 0.8);
    for (int i = 0; i < 20; ++i) {
      std::array<ContactSpring, 1> spring{{{node, Vec3(0.6, 0.0, 0.8), 1.5, 0.0, 0.0}}};
      step(b, with_spring, 0.01, {}, spring);
      step(b, with_load, 0.01, load);
      EXPECT_DOUBLE_EQ(spring[0].force_end, 1.5);
    }
    EXPECT_LT((with_spring.x - with_load.x).norm(), 1e-12) << static_cast<int>(solver);
  }
}

TEST(ContactSprings, NeverPull) {
  // The node flies away along the push faster than the contact can follow: the push ends at
  // zero and the node moves as if nothing touched it. Both ways of coupling: a separate solve
  // per spring (a body's first solve), and the springs folded into the matrix-free operator
  // (once the solver's path is known), where the spring is let go and the step solved again.
  for (const bool path_known : {false, true}) {
    const Body b = tissue_node();
    BodyState touched = make_state(b), free = make_state(b);
    if (path_known) step(b, touched, 0.01), step(b, free, 0.01);
    touched.v[3] = free.v[3] = 2.0;
    const std::array<NodeShare, 1> node{{{1, 1.0}}};
    std::array<ContactSpring, 1> spring{{{node, Vec3::UnitX(), 0.1, 1000.0, 0.1}}};
    step(b, touched, 0.01, {}, spring);
    step(b, free, 0.01);
    EXPECT_EQ(spring[0].force_end, 0.0) << path_known;
    EXPECT_LT((touched.x - free.x).norm(), 1e-9) << path_known;
    EXPECT_EQ(spring[0].stiffness, 1000.0);  // the caller's spring is not changed
  }
}

TEST(ContactSprings, BilateralOnesPullBack) {
  // A grasp's hold across the pads' plane: the same node flying away, now held by a spring
  // that pulls as well as pushes. It ends pulling, by its slope times how far the node went,
  // and the node goes less far than a free one. Both ways of coupling, as above.
  for (const bool path_known : {false, true}) {
    const Body b = tissue_node();
    BodyState held = make_state(b), free = make_state(b);
    if (path_known) step(b, held, 0.01), step(b, free, 0.01);
    held.v[3] = free.v[3] = 2.0;
    const double start = held.x[3];
    const std::array<NodeShare, 1> node{{{1, 1.0}}};
    std::array<ContactSpring, 1> spring{{{node, Vec3::UnitX(), 0.1, 1000.0, 0.1, true}}};
    step(b, held, 0.01, {}, spring);
    step(b, free, 0.01);
    EXPECT_LT(spring[0].force_end, 0.0) << path_known;
    EXPECT_NEAR(spring[0].force_end, 0.1 - 1000.0 * (held.x[3] - start), 1e-9) << path_known;
    EXPECT_LT(held.x[3], free.x[3] - 5e-4) << path_known;  // 0.25 mm against 0.91 mm
  }
}

TEST(ContactSprings, ExplicitIntegratorsHoldTheStartingPush) {
  Body b = tissue_node();
  b.settings.integrator = Integrator::symplectic_euler;
  BodyState with_spring = make_state(b), with_load = make_state(b);
  const std::array<NodeShare, 1> node{{{1, 1.0}}};
  std::array<ContactSpring, 1> spring{{{node, Vec3::UnitX(), 0.7, 300.0, 0.0}}};
  VecX load = VecX::Zero(6);
  load[3] = 0.7;
  step(b, with_spring, 1e-4, {}, spring);
  step(b, with_load, 1e-4, load);
  EXPECT_EQ(with_spring.x, with_load.x);
  EXPECT_EQ(spring[0].force_end, 0.7);
}

TEST(ContactSprings, MoreThanTheLimitAreRefused) {
  const Body b = tissue_node();
  BodyState s = make_state(b);
  const std::array<NodeShare, 1> node{{{1, 1.0}}};
  std::vector<ContactSpring> springs(kMaxContactSprings + 1, ContactSpring{node, Vec3::UnitX(), 0.1, 10.0, 0.1});
  EXPECT_THROW(step(b, s, 0.01, {}, springs), std::invalid_argument);
}

}  // namespace
}  // namespace tactus::physics
