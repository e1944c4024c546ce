// Stability at seed 000's time steps (Fig. 5: 0.01 s for skin and ligament, 0.05 s for muscle
// and the upper leg) and energy conservation of undamped symplectic Euler.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "ms_test_util.hpp"
#include "physics/mass_spring/surface_builder.hpp"
#include "physics/mass_spring/tet_builder.hpp"
#include "physics/mass_spring/tissue_presets.hpp"

namespace tactus::physics {
namespace {

using test::nodes_at;

struct Case {
  const char* tissue;
  Vec3 size;
  int cx, cy, cz;
  double dt;
  double load_sign;  // −1: a press on the top face; +1: a pull (a ligament works in tension)
};

double total_energy(const Body& b, const BodyState& s) { return kinetic_energy(b, s) + potential_energy(b, s); }

/// The case's block, its base fixed, solved with CHOLMOD and `newton_iterations` per step.
Body make_block(const Case& c, int newton_iterations) {
  const TissueMaterial& tissue = tissue_material(c.tissue);
  const auto m = mesh::box_volume(c.size, c.cx, c.cy, c.cz);
  Body b;
  b.model = tet_mass_spring(m, tet_spring_params(tissue));
  b.fix_nodes(nodes_at(b.model->rest_positions(), 2, -c.size.z() / 2));
  b.settings.solver = LinearSolver::cholesky;
  b.settings.newton_iterations = newton_iterations;
  b.settings.newton_tolerance = 1e-9;
  return b;
}

/// The case's press (or pull): a pressure of 5% of E on the top face.
VecX face_load(const Case& c, const Body& b) {
  const TissueMaterial& tissue = tissue_material(c.tissue);
  const auto top = nodes_at(b.model->rest_positions(), 2, c.size.z() / 2);
  // A pressure of 5% of E on the top face (a 5% strain, the small-deformation regime of
  // seed 000), shared by tributary area: border nodes carry half, corners a quarter.
  VecX load = VecX::Zero(b.model->rest_positions().size());
  const VecX& rest = b.model->rest_positions();
  const auto on_side = [](double v, double half) { return std::abs(std::abs(v) - half) < 1e-12; };
  double weight_sum = 0.0;
  for (auto n : top) {
    const double w = (on_side(rest[3 * n], c.size.x() / 2) ? 0.5 : 1.0) * (on_side(rest[3 * n + 1], c.size.y() / 2) ? 0.5 : 1.0);
    load[3 * n + 2] = w;
    weight_sum += w;
  }
  load *= c.load_sign * 0.05 * tissue.youngs_modulus * c.size.x() * c.size.y() / weight_sum;
  return load;
}

void run_case(const Case& c) {
  // Implicit Euler solved to convergence: the one-iteration linearized step is not the
  // backward Euler solution and, for stiff nonlinear springs at these large steps, can gain
  // energy; the converged backward Euler step minimizes the incremental potential and so
  // cannot.
  const Body b = make_block(c, 10);
  const VecX load = face_load(c, b);
  BodyState s = make_state(b);
  const int loaded = static_cast<int>(std::lround(1.0 / c.dt)), released = static_cast<int>(std::lround(2.0 / c.dt));
  for (int i = 0; i < loaded; ++i) {
    step(b, s, c.dt, load);
    ASSERT_TRUE(s.x.allFinite() && s.v.allFinite());
  }
  const double loaded_disp = (s.x - b.model->rest_positions()).cwiseAbs().maxCoeff();
  const double e_removed = total_energy(b, s);
  double e = e_removed;
  for (int i = 0; i < released; ++i) {
    step(b, s, c.dt);
    ASSERT_TRUE(s.x.allFinite() && s.v.allFinite()) << "step " << i;
    const double e_next = total_energy(b, s);
    // Backward Euler dissipates and the arms' update only releases stored energy. Allowed:
    // the Newton tolerance's share and round-off, 1e-9 of the energy at release.
    ASSERT_LE(e_next, e + 1e-9 * std::abs(e_removed)) << "step " << i;
    e = e_next;
  }
  // Bounded: every node within 10% of the block's size of its rest position (the load
  // strains it by 5%; after release it recovers towards rest).
  EXPECT_LT(loaded_disp, 0.1 * c.size.maxCoeff());
  EXPECT_LT((s.x - b.model->rest_positions()).cwiseAbs().maxCoeff(), 0.1 * c.size.maxCoeff());
}

TEST(Stability, SkinAtTenMilliseconds) {
  // 4 mm cubes: flat tetrahedra (10 × 10 × 2 mm cells) snap through under a press.
  run_case({"skin", Vec3(0.02, 0.02, 0.004), 5, 5, 1, 0.01, -1.0});
}
TEST(Stability, LigamentAtTenMilliseconds) { run_case({"ligament", Vec3(0.01, 0.01, 0.04), 2, 2, 6, 0.01, 1.0}); }
TEST(Stability, MuscleAtFiftyMilliseconds) { run_case({"muscle", Vec3(0.05, 0.05, 0.05), 4, 4, 4, 0.05, -1.0}); }
TEST(Stability, UpperLegAtFiftyMilliseconds) {
  // Seed 000's upper leg (2550 tets), lying on its back and pressed from above.
  run_case({"muscle", Vec3(0.5, 0.15, 0.15), 17, 5, 5, 0.05, -1.0});
}

/// The skin block of seed 000 pressed for 1 s, then released for 1 s with
/// `newton_iterations` per implicit step: the largest rise of the total energy over one
/// released step, relative to the energy at release, and the energy after the first one.
struct Release {
  double worst_rise = 0.0, first_energy = 0.0;
  int first_newton_iterations = 0;
};

Release release_skin(int newton_iterations) {
  const Case c{"skin", Vec3(0.02, 0.02, 0.004), 5, 5, 1, 0.01, -1.0};
  const Body b = make_block(c, newton_iterations);
  const VecX load = face_load(c, b);
  BodyState s = make_state(b);
  for (int i = 0; i < 100; ++i) step(b, s, c.dt, load);
  const double released = total_energy(b, s);
  Release r;
  r.worst_rise = -std::numeric_limits<double>::infinity();
  double e = released;
  for (int i = 0; i < 100; ++i) {
    step(b, s, c.dt);
    const double next = total_energy(b, s);
    if (i == 0) {
      r.first_energy = next;
      r.first_newton_iterations = s.last_newton_iterations;
    }
    r.worst_rise = std::max(r.worst_rise, (next - e) / released);
    e = next;
  }
  return r;
}

TEST(Stability, StiffSkinReleasedAtTenMillisecondsGainsNoEnergyWithOneOrMoreNewtonIterations) {
  // Converged backward Euler minimizes the incremental potential, so the energy of the
  // released block can only fall; the linearized one-iteration step is not that solution and
  // was once recorded gaining 0.6% here. Measured now (CHOLMOD, the damped SLS skin preset, a
  // 5%-of-E press): every released step loses energy with 1, 3 or 5 iterations (worst rise
  // -4.9e-4 of the release energy), and the elastic-only skin and a ligament in tension
  // behave alike. Required: no rise beyond 1e-9 of the release energy (Newton tolerance and
  // round-off) for every count, and extra iterations must change the first step (they run:
  // the linearized step is not yet the backward Euler solution there).
  const Release one = release_skin(1);
  EXPECT_LT(one.worst_rise, 1e-9);
  EXPECT_EQ(one.first_newton_iterations, 1);
  for (int iterations : {3, 5}) {
    const Release r = release_skin(iterations);
    EXPECT_LT(r.worst_rise, 1e-9) << iterations;
    EXPECT_GE(r.first_newton_iterations, 2) << iterations;
    EXPECT_GT(std::abs(r.first_energy - one.first_energy), 1e-4 * one.first_energy) << iterations;
  }
}

/// Mean total energy over a window of steps.
double mean_energy(const Body& b, BodyState& s, int steps, double dt) {
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) {
    step(b, s, dt);
    sum += total_energy(b, s);
  }
  return sum / steps;
}

void expect_no_drift(const Body& b, BodyState& s, double dt) {
  // Symplectic Euler's energy oscillates by O(ω dt) within a period but does not drift: the
  // mean over the first and last 500 of 10,000 steps must agree within 1% of the energy.
  const double e0 = total_energy(b, s);
  ASSERT_GT(e0, 0.0);
  const double first = mean_energy(b, s, 500, dt);
  for (int i = 0; i < 9000; ++i) step(b, s, dt);
  const double last = mean_energy(b, s, 500, dt);
  EXPECT_LT(std::abs(last - first), 0.01 * e0);
  EXPECT_TRUE(s.x.allFinite());
}

TEST(Stability, UndampedSymplecticEulerTetBlockConservesEnergy) {
  // 20 mm cube, E = 5 kPa, ρ = 1000: the stiffest mode has ω ≈ 2.5e3 rad/s, ω dt ≈ 0.12.
  TetSpringParams p;
  p.youngs_modulus = 5e3;
  const auto m = mesh::box_volume(Vec3(0.02, 0.02, 0.02), 2, 2, 2);
  Body b;
  b.model = tet_mass_spring(m, p);
  b.fix_nodes(nodes_at(b.model->rest_positions(), 2, -0.01));
  b.settings.integrator = Integrator::symplectic_euler;
  BodyState s = make_state(b);
  for (auto n : nodes_at(b.model->rest_positions(), 2, 0.01)) s.x[3 * n + 2] += 5e-4;
  expect_no_drift(b, s, 5e-5);
}

TEST(Stability, UndampedSymplecticEulerSheetConservesEnergy) {
  // 6×6 quads of 10 mm with edge and diagonal springs (k = 50 N/m, 1 g nodes): ω dt ≈ 0.06.
  SurfaceSpringParams p;
  p.diagonal = true;
  p.node_mass = 1e-3;
  const auto m = mesh::grid_plate_quads(0.06, 0.06, 6, 6);
  Body b;
  b.model = surface_mass_spring(m, p);
  b.fix_nodes(nodes_at(b.model->rest_positions(), 0, -0.03));
  b.settings.integrator = Integrator::symplectic_euler;
  BodyState s = make_state(b);
  s.x += test::random_vector(s.x.size(), 7, 5e-4);
  for (Eigen::Index i = 2; i < s.x.size(); i += 3) s.x[i] = 0.0;  // in-plane motion
  for (auto n : nodes_at(b.model->rest_positions(), 0, -0.03)) s.x.segment<3>(3 * n) = b.model->rest_positions().segment<3>(3 * n);
  expect_no_drift(b, s, 1e-4);
}

}  // namespace
}  // namespace tactus::physics
