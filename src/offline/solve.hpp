#pragma once
// `tactus solve`: a scene's deformable bodies without devices, in lockstep, to static
// equilibrium or to a time, under the loads and prescribed displacements the scene declares.
#include <optional>
#include <string>
#include <vector>

#include "core/math.hpp"
#include "scene/model.hpp"

namespace tactus::offline {

struct SolveOptions {
  bool static_solve = false;        ///< equilibrium by load stepping (else dynamics)
  double until = 1.0;               ///< dynamic runs: end time [s]
  double report_every = 0.0;        ///< dynamic runs: seconds between CSV rows (0: every step)
  std::vector<scene::Probe> extra_probes;  ///< from --probe FILE, for every body
  /// The progress bar's label (core/progress.hpp); empty = "solving BODY" (static) or
  /// "simulating BODY" (dynamics).
  std::string progress;
};

/// One row of results: at a time (dynamic) or a load step (static).
struct SolveRow {
  double time = 0.0;       ///< [s], or the load fraction in (0, 1] for static solves
  int step = 0;
  std::vector<Vec3> probe_displacements;   ///< per column group, see SolveResult
  std::vector<Vec3> reactions;             ///< per fixed/prescribed region [N]
  int linear_iterations = 0;
  bool converged = true;                   ///< static: Newton met its tolerance (every sub-step)
};

struct BodySolve {
  std::string body;
  std::vector<std::string> probe_names;
  std::vector<std::string> region_names;  ///< fixed regions then prescribed motions
  std::vector<SolveRow> rows;
  std::vector<Vec3> final_positions;      ///< simulation nodes
  /// Static: why the solve stopped early (empty when every load step converged); the last
  /// row is the failed step, at the last equilibrium reached.
  std::string failure;
  int step_halvings = 0;  ///< static: load steps halved to converge, summed
};

struct SolveResult {
  std::vector<BodySolve> bodies;  ///< one per deformable body, in scene order
};

SolveResult solve(const scene::Model& model, const SolveOptions& options);

/// CSV with one row per SolveRow (columns documented in docs/solve-output.md).
std::string to_csv(const BodySolve& body, bool static_solve);

/// Reads probes from a CSV file "name,x,y,z" (a header line is optional; # comments).
std::vector<scene::Probe> read_probe_file(const std::string& path);

}  // namespace tactus::offline
