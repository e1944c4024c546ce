#pragma once
// Building a space over MPI ranks: rank 0 schedules the wavefront's ready transitions to the
// solver ranks as they become idle (dynamic load balance: solves differ in cost), gathers the
// results and records them; ranks 1.. solve. Without MPI in the build, everything here
// reports a single process.
#include "precompute/builder.hpp"

namespace tactus::precompute::distributed {

/// Whether this build has MPI support (TACTUS_WITH_MPI).
bool available();
/// The job size the launcher (mpirun, srun) announced in the environment; 1 when the
/// process was not started by one.
int launched_size();

/// MPI for the life of the object, initialized only when launched_size() > 1. Throws
/// InputError when launched with several ranks by a build without MPI (each rank would
/// build the whole space on its own). Aborts the job when destroyed during an exception, so
/// that no rank waits for ever on a failed one.
class Session {
 public:
  Session();
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
  [[nodiscard]] int rank() const { return rank_; }
  [[nodiscard]] int size() const { return size_; }
  /// Ends every rank of the job now with `code` (MPI_Abort): for a hung rank that would keep
  /// MPI_Finalize from returning. Nothing without MPI.
  void abort_job(int code);
  /// Rank 0's `go`, on every rank (a broadcast every rank must reach): whether the solver
  /// ranks serve another schedule.
  [[nodiscard]] bool decide(bool go) const;

 private:
  int rank_ = 0;
  int size_ = 1;
  bool initialized_ = false;
};

/// Rank 0: hands out every pending point of `space` to ranks 1..size-1 and records the
/// results (options.threads is ignored). A transition not answered within the timeout
/// (options.reissue_*) is handed to another rank and its rank kept out of the pool until it
/// answers; the first answer for a point is recorded, a later one ignored. At the end,
/// ranks still owing an answer get max(timeout, 10 s) to send it; any silent beyond that is
/// counted in stats.unresponsive and sent no stop.
BuildStats schedule(Space& space, const BuildOptions& options, const Session& session);
/// Ranks 1..: solves the tasks rank 0 sends until it says stop.
void serve(ConfigurationSolver& solver, const Space& space, const Session& session);

}  // namespace tactus::precompute::distributed
