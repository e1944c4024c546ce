#pragma once
// How a body is stepped: the integrator, the linear solver of implicit steps and their
// tolerances. A small header of its own, so that the scene's model holds these settings
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
};

}  // namespace tactus::physics
