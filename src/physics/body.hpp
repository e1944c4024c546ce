#pragma once
// A body: a force model with its constraints, gravity and the integrator settings. Immutable;
// BodyState carries what changes.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "physics/force_model.hpp"
#include "physics/nodules.hpp"
#include "physics/step_settings.hpp"

namespace tactus::physics {

struct Body {
  std::shared_ptr<const ForceModel> model;
  /// One flag per degree of freedom (3N): fixed dofs are not integrated; their position is
  /// whatever the state holds (the caller may prescribe a motion) and their velocity zero.
  std::vector<std::uint8_t> fixed_dofs;
  Vec3 gravity = Vec3::Zero();
  StepSettings settings;
  /// Spheres the nodes touch only from outside, enforced after every step (seed 004).
  NoduleSet nodules;

  /// Fixes all three dofs of the given nodes.
  void fix_nodes(const std::vector<std::int32_t>& nodes);
  [[nodiscard]] std::size_t fixed_node_count() const;
};

struct SolverScratch;  // integrator buffers (defined in integrator.cpp)

/// Where the time of implicit steps and static iterations goes, summed over the steps [s]
/// (for `tactus bench --fem`): element forces and their linearization, the system's
/// assembly (Cholesky's matrix or the assembled CG's blocks), and the linear solve
/// (factorization and substitution, or the CG iterations).
struct StepProfile {
  double forces = 0.0, assembly = 0.0, solve = 0.0;
};

struct BodyState {
  VecX x, v, q;  ///< positions, velocities (3N), internal variables
  double time = 0.0;
  std::unique_ptr<Scratch> model_scratch;
  std::shared_ptr<SolverScratch> solver_scratch;

  /// Statistics of the last step.
  int last_linear_iterations = 0;
  int last_newton_iterations = 0;
  /// When set, steps add their parts' times here (two clock reads a part); null: none.
  StepProfile* profile = nullptr;
};

/// The rest state: x = rest positions, v = 0, q = 0.
BodyState make_state(const Body& body);

/// A node's share of a contact's push.
struct NodeShare {
  std::int32_t node = -1;
  double share = 0.0;
};

/// The hand's push on the body through one contact, coupled implicitly: it acts along
/// `direction` on a weighted set of nodes, and falls by `stiffness` for each metre the
/// weighted nodes give way along `direction` during the step (the contact law's slope: a
/// proxy resting on the surface follows it, so its spring relaxes), never below zero. A
/// push held constant over a step much longer than the haptic frame makes soft tissue
/// overshoot under it and swing back at the next step; coupled, the step ends where the
/// tissue and the contact balance.
struct ContactSpring {
  std::span<const NodeShare> nodes;  ///< shares sum to 1
  Vec3 direction = Vec3::UnitZ();    ///< unit, the push on the body
  double force = 0.0;                ///< at the start of the step [N]
  double stiffness = 0.0;            ///< [N/m]; 0: a constant push
  double force_end = 0.0;            ///< out: the push at the end of the step [N]
  /// A hold rather than a contact: it pulls back (a negative push) as well as pushes.
  bool bilateral = false;
};
inline constexpr std::size_t kMaxContactSprings = 8;

/// Advances the body by dt under the external forces f_ext (3N, may be empty) and the
/// contact springs (at most kMaxContactSprings). implicit_euler couples the springs into its
/// solve; the explicit integrators apply each spring's starting force as a constant load.
/// Throws std::invalid_argument for a non-positive dt or too many springs.
void step(const Body& body, BodyState& state, double dt, const VecX& f_ext = {},
          std::span<ContactSpring> springs = {});

/// A static solve that stops improving (round-off) counts as converged below this relative
/// residual.
inline constexpr double kStagnationTolerance = 1e-6;

struct StaticResult {
  bool converged = false;
  bool stagnated = false;  ///< stopped at round-off before reaching the tolerance
  /// Balanced, but with an element turned inside out (volume ratio J ≤ 0) that the rest state
  /// does not have: an equilibrium of the wrong branch, never reported as converged.
  bool inverted = false;
  int iterations = 0;
  double residual = 0.0;        ///< final |f| over free dofs, relative to the force scale
  double residual_force = 0.0;  ///< final |f| over free dofs [N]
  int projected_iterations = 0;  ///< Newton steps on the projected tangent (the exact one not definite)
};
/// Newton with a line search on the total potential energy to static equilibrium
/// f(x) + f_ext + m·g = 0 over the free dofs (the fixed dofs hold their current positions).
StaticResult solve_static(const Body& body, BodyState& state, const VecX& f_ext = {},
                          const StaticSettings& settings = {});
inline StaticResult solve_static(const Body& body, BodyState& state, const VecX& f_ext, int max_iterations,
                                 double tolerance) {
  return solve_static(body, state, f_ext, StaticSettings{max_iterations, tolerance});
}

/// The start of a load step whose held dofs moved: `previous` is the last equilibrium and
/// `state.x` holds it with the held dofs already at their new positions. Moves the free dofs
/// by the linearized response, K_ff·δ = f_free(previous, f_ext) − (K·Δ_held)_free, so that a
/// large step of a prescribed node carries its neighbours along instead of turning their
/// elements inside out (Newton started from such a state can end on an inverted
/// equilibrium). Returns false, leaving the state as it was, where nothing held moved or the
/// linear solve failed.
bool predict_static(const Body& body, BodyState& state, const VecX& previous, const VecX& f_ext = {});

/// Drops what the solvers carry from one solve to the next (the stiffness factor later static
/// solves precondition with, the implicit steps' conjugate-gradient starting guesses), so the
/// next solve's result depends on its inputs alone, not on what this state solved before.
void forget_solver_history(BodyState& state);

/// The body's fixed_dofs changed since this state last solved (a contact set that grew or
/// shrank): the solvers take the new ones at the next solve. The stiffness factor in hand
/// still preconditions the next static solves (it factorizes a definite matrix, only one
/// with other rows held), and the first factorization analyses the new pattern.
void fixed_dofs_changed(const Body& body, BodyState& state);

/// For a body whose implicit steps factorize (Cholesky): takes one step of length dt from the
/// state on a copy and keeps only what the solver learnt of the matrix's pattern (the ordering
/// and symbolic analysis, the assembly's places), so that a real-time loop's first step costs
/// what the others do. The state itself is unchanged. Does nothing for other bodies.
void analyse_ahead(const Body& body, BodyState& state, double dt);

/// Cholesky factorizations this state's solves have made so far (a statistic: static solves
/// factorize only when the factor in hand has aged).
long factorizations(const BodyState& state);

/// The balanced state's first-order response to motions of its held dofs. Each column j of
/// `held` (3N, nonzero on held dofs only) is a unit motion of them; column j of `motion` is
/// the whole state's motion dx/dθ_j (the held part as given, the free part solving
/// K_ff·dx_f = −(K·held_j)_f), and column j of `force_change` the internal force's change
/// −K·dx/dθ_j on every dof, so the reaction at held nodes follows by summing their rows.
/// K is the exact tangent, factorized once for all columns, where Cholesky finds it definite
/// (it is at a stable equilibrium), else the projected one. Returns false where neither
/// solves or the result is not finite.
bool static_response(const Body& body, BodyState& state, const Eigen::MatrixXd& held, Eigen::MatrixXd& motion,
                     Eigen::MatrixXd& force_change);

/// Kinetic energy ½ vᵀMv (the model's mass matrix) and elastic energy; their sum minus the work of gravity is
/// conserved by an undamped exact integrator.
double kinetic_energy(const Body& body, const BodyState& state);
double potential_energy(const Body& body, const BodyState& state);  ///< elastic + gravity

}  // namespace tactus::physics
