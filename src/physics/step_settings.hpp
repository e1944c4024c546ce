#pragma once
// How a body is stepped: the integrator, the linear solver of implicit steps and their
// tolerances, and how static solves balance. A small header of its own, so that the scene's model holds these settings
// without the bodies themselves.
namespace tactus::physics {

enum class Integrator { explicit_euler, symplectic_euler, rk4, implicit_euler };
enum class LinearSolver { conjugate_gradient, cholesky };

struct StepSettings {
  Integrator integrator = Integrator::implicit_euler;
  LinearSolver solver = LinearSolver::conjugate_gradient;
  double cg_tolerance = 1e-4;  ///< relative residual
  int cg_max_iterations = 200;
  int newton_iterations = 1;   ///< 1 = the linearized (Baraff–Witkin) step
  double newton_tolerance = 1e-8;  ///< relative force residual, when newton_iterations > 1
  /// Cholesky implicit steps (linearized, newton_iterations 1): how many steps one numeric
  /// factorization serves. 1 factorizes every step; more keep the system matrix of the step
  /// that factorized (a frozen tangent) for the next ones, which then cost the forces and one
  /// substitution.
  int factor_reuse_steps = 1;

  /// Whether these steps can keep a factorization for the next ones: linearized implicit
  /// Euler solved by Cholesky (factor_reuse_steps is ignored otherwise).
  [[nodiscard]] bool can_reuse_factor() const {
    return integrator == Integrator::implicit_euler && solver == LinearSolver::cholesky && newton_iterations == 1;
  }
};

/// Newton's stopping rule and effort for static solves (physics::solve_static).
struct StaticSettings {
  int max_iterations = 50;
  /// Converged when the out-of-balance force on the free dofs is at most this fraction of
  /// the force scale: the larger of the applied loads with the weight and the reactions of
  /// the held dofs (what the supports and prescribed nodes push), both at the current state.
  double tolerance = 1e-8;
  /// [N] converged at or below this out-of-balance force whatever the scale (a body under no
  /// load, or one whose loads are at round-off).
  double force_tolerance = 1e-10;
};

}  // namespace tactus::physics
