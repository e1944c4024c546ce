#pragma once
// Building a configuration space on this machine: a pool of worker threads, each with its
// own ConfigurationSolver, takes the wavefront's ready transitions.
#include <cstddef>
#include <functional>
#include <memory>
#include <string>

#include "precompute/configuration_solver.hpp"
#include "precompute/space.hpp"

namespace tactus::precompute {

using SolverFactory = std::function<std::unique_ptr<ConfigurationSolver>()>;

struct BuildOptions {
  unsigned threads = 1;
  /// Stop handing out work after this many new results (0 = never): what a killed job leaves
  /// behind, for testing resume.
  std::size_t stop_after = 0;
  /// Every new outcome (unreachable points included), one at a time, in completion order:
  /// the checkpoint journal appends it here.
  std::function<void(const PointResult&)> on_result;
  /// MPI only: a transition not answered within max(reissue_floor, reissue_factor × the
  /// running median solve time) [s] is handed to another rank; the first answer counts.
  double reissue_factor = 10.0;
  double reissue_floor = 60.0;
  /// MPI only: transitions a rank may owe at once. 1: each rank gets its next one when it
  /// answers (a far rank waits a round trip per point); 2: the next one waits in its queue
  /// while it solves, which hides the task's travel.
  unsigned in_flight = 1;
  /// Points resolved so far (resumed ones included) and the total.
  std::function<void(std::size_t resolved, std::size_t total)> on_progress;
};

struct BuildStats {
  std::size_t computed = 0;     ///< solves run by this build (not resumed ones)
  std::size_t unreachable = 0;  ///< marked unreachable by this build
  std::size_t retried = 0;      ///< failed transitions tried again from another neighbour
  double wall_seconds = 0.0;
  double solve_seconds = 0.0;   ///< sum of the solves' wall times over all workers
  unsigned workers = 1;
  /// MPI: CPU time (user + system, getrusage) of the solver ranks, summed; each rank sends
  /// its own when it stops. 0 for a build on local threads.
  double solver_cpu_seconds = 0.0;
  bool stopped = false;         ///< stop_after cut the build short
  std::size_t reissued = 0;     ///< MPI: transitions handed to another rank after a timeout
  std::size_t late = 0;         ///< MPI: answers that came after another rank's and were ignored
  int unresponsive = 0;         ///< MPI: ranks still silent at the end (hung)
};

/// An empty space for `body` under `settings`: the grid through the undeformed contact
/// point, the model identity, the rest shape and elements, every point pending.
Space make_space(const physics::Body& body, const SpaceSettings& settings, std::string scene_text);

/// Where point p's transition starts and ends: the patch positions of its source and of p.
Vec3 patch_position(const Space& space, std::size_t point);

/// Fills the pending points of `space` (allocated; a resumed build holds earlier outcomes).
/// The first worker exception is rethrown after every worker has stopped.
BuildStats build_local(Space& space, const SolverFactory& make_solver, const BuildOptions& options);

/// Runs one task on `solver`: the start point from rest, any other from its source.
PointResult run_task(ConfigurationSolver& solver, const Space& space, std::size_t point, std::int64_t source,
                     const VecX& source_displacement);

/// Says in a failed point's reason how many neighbours it was tried from, when more than one.
void note_tries(PointResult& r, int failed_tries);

/// The outcome recorded for a point every candidate source of which failed.
PointResult unreachable_result(std::size_t point);

}  // namespace tactus::precompute
