#pragma once
// Vega FEM's Baraff–Witkin cloth (ClothBW) stepped by Vega's implicit backward Euler
// (ImplicitBackwardEulerSparse, one linearized step, Jacobi-preconditioned CG), behind an
// interface of plain arrays so that the benchmark's sources see no Vega header.
#include <memory>
#include <vector>

namespace vega_bench {

struct ClothSetup {
  std::vector<double> rest;         ///< 3N rest positions [m]
  std::vector<double> masses;       ///< N node masses [kg]
  std::vector<int> triangles;       ///< 3T vertex indices
  std::vector<double> triangle_uv;  ///< 6T: (u, v) of each triangle's corners [m of fabric]
  /// ClothBW::MaterialGroup: E = ½k_t α²((|w_u|−1)² + (|w_v|−1)²) + ½k_s α²(w_u·w_v)² per
  /// triangle (α = area^¾), ½k_b(θ − θ₀)² per interior edge, k_b mixed from the two values by
  /// the edge's (u, v) direction.
  double tensile = 0.0, shear = 0.0, bend_u = 0.0, bend_v = 0.0;
  std::vector<int> fixed_dofs;  ///< ascending
  std::vector<double> external;  ///< 3N constant external force [N] (gravity)
  double dt = 0.0;
  double damping_stiffness = 0.0, damping_mass = 0.0;  ///< Rayleigh: D = a·M + b·K
};

class Cloth {
 public:
  explicit Cloth(const ClothSetup& setup);
  ~Cloth();
  Cloth(const Cloth&) = delete;
  Cloth& operator=(const Cloth&) = delete;

  /// Displacements from rest and velocities (3N each).
  void set_state(const std::vector<double>& u, const std::vector<double>& v);
  /// One DoTimestep of the integrator.
  void step();
  /// The integrator's timers of the last step [s]: ClothBW's force and tangent stiffness,
  /// and the CG solve.
  [[nodiscard]] double force_time() const;
  [[nodiscard]] double solve_time() const;
  /// Solves the last step's system again (the integrator's matrix and right-hand side) with a
  /// CGSolver that, like the integrator's, took its Jacobi preconditioner from the first
  /// step's matrix, from zero, to `tolerance`: returns its iterations and sets `seconds`.
  /// With the integrator's tolerance (1e-6) it repeats the integrator's own solve. Call it
  /// after every step from the first, or not at all.
  int resolve(double tolerance, double& seconds);
  [[nodiscard]] const double* displacements() const;
  [[nodiscard]] const double* velocities() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vega_bench
