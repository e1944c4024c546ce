#pragma once
// `tactus bench --fem`: the implicit step of a scene's FEM bodies timed on their own (no
// devices, gravity only, the scene's fixed regions), so a user can measure the step on
// their own mesh, law, solver and thread count.
#include <optional>
#include <string>
#include <vector>

#include "physics/step_settings.hpp"
#include "scene/model.hpp"

namespace tactus::offline {

struct FemBenchOptions {
  int steps = 200;   ///< timed steps per body, after 5 untimed ones
  unsigned threads = 0;  ///< element-loop threads (core/parallel); 0: as configured
  std::optional<physics::FemLaw> law;            ///< overrides the bodies' materials
  std::optional<physics::LinearSolver> solver;   ///< overrides the bodies' solvers
  std::optional<double> cg_tolerance;            ///< overrides the bodies' CG tolerance
  std::optional<int> factor_reuse_steps;         ///< overrides the bodies' factor_reuse_steps
};

struct FemBenchBody {
  std::string body;
  std::string law, solver;
  std::size_t nodes = 0, tets = 0;
  double time_step = 0.0;   ///< [s]
  unsigned threads = 1;
  double median_ms = 0.0, p99_ms = 0.0;
  /// Where one factorization serves several steps (factor_reuse_steps) the median is the
  /// cheap steps' and the mean says what a simulation period pays.
  double mean_ms = 0.0;
  double ns_per_tet = 0.0;  ///< median step over tets
  double mean_linear_iterations = 0.0;
  /// Shares of the summed step time: element forces and linearization, assembly, linear
  /// solve, and the rest (vector updates, warm starts, the inversion check).
  double share_forces = 0.0, share_assembly = 0.0, share_solve = 0.0, share_other = 0.0;
};

/// Times every FEM body of the scene; throws InputError when it has none.
std::vector<FemBenchBody> bench_fem(const scene::Model& model, const FemBenchOptions& options);

/// The results as a table, one row per body.
std::string format_fem_bench(const std::vector<FemBenchBody>& results);

}  // namespace tactus::offline
