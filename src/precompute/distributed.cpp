#include "precompute/distributed.hpp"

#include <cstdlib>
#include <exception>
#include <string>

#include "core/error.hpp"

#if TACTUS_WITH_MPI
// The C API only: the deprecated C++ bindings would need their own library.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <chrono>
#include <vector>

#include "precompute/wavefront.hpp"
#endif

namespace tactus::precompute::distributed {

int launched_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
    if (const char* v = std::getenv(name)) {
      const int n = std::atoi(v);
      if (n > 0) return n;
    }
  return 1;
}

#if TACTUS_WITH_MPI

bool available() { return true; }

namespace {

constexpr int kTaskTag = 1;
constexpr int kStopTag = 2;
constexpr int kResultTag = 3;

}  // namespace

Session::Session() {
  if (launched_size() <= 1) return;
  int already = 0;
  MPI_Initialized(&already);
  if (!already) MPI_Init(nullptr, nullptr);
  initialized_ = !already;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

Session::~Session() {
  if (!initialized_) return;
  if (std::uncaught_exceptions() > 0) MPI_Abort(MPI_COMM_WORLD, 1);
  MPI_Finalize();
}

BuildStats schedule(Space& space, const BuildOptions& options, const Session& session) {
  const auto t0 = std::chrono::steady_clock::now();
  BuildStats stats;
  stats.workers = static_cast<unsigned>(session.size() - 1);
  Wavefront wave(space.grid, space.start, space.status);
  const auto dofs = static_cast<int>(space.displacement.rows());
  auto record = [&](const PointResult& r) {
    space.store(r);
    if (options.on_result) options.on_result(r);
  };
  for (auto p : wave.take_unreachable()) record(unreachable_result(p));

  std::vector<int> idle;
  for (int r = session.size() - 1; r >= 1; --r) idle.push_back(r);
  bool stop = false;
  std::vector<char> reason;
  while (!wave.finished()) {
    // Hand every ready transition to an idle rank.
    while (!stop && !idle.empty()) {
      const auto task = wave.next();
      if (!task) break;
      const int rank = idle.back();
      idle.pop_back();
      const std::int64_t head[2] = {static_cast<std::int64_t>(task->point), task->source};
      MPI_Send(head, 2, MPI_INT64_T, rank, kTaskTag, MPI_COMM_WORLD);
      if (task->source >= 0)
        MPI_Send(space.displacement.col(static_cast<Eigen::Index>(task->source)).data(), dofs, MPI_DOUBLE, rank,
                 kTaskTag, MPI_COMM_WORLD);
    }
    if (wave.in_flight() == 0) break;  // stopped, or nothing can run any more
    // The next result from any rank; its remaining parts come from the same rank in order.
    std::int64_t head[5];
    MPI_Status st;
    MPI_Recv(head, 5, MPI_INT64_T, MPI_ANY_SOURCE, kResultTag, MPI_COMM_WORLD, &st);
    const int from = st.MPI_SOURCE;
    double values[5];
    MPI_Recv(values, 5, MPI_DOUBLE, from, kResultTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    PointResult r;
    r.point = static_cast<std::size_t>(head[0]);
    r.status = static_cast<PointStatus>(head[1]);
    r.source = head[2];
    r.iterations = static_cast<int>(head[3]);
    r.residual = values[0];
    r.seconds = values[1];
    r.force = Vec3(values[2], values[3], values[4]);
    if (head[4] > 0) {
      reason.resize(static_cast<std::size_t>(head[4]));
      MPI_Recv(reason.data(), static_cast<int>(head[4]), MPI_CHAR, from, kResultTag, MPI_COMM_WORLD,
               MPI_STATUS_IGNORE);
      r.reason.assign(reason.begin(), reason.end());
    }
    if (r.status == PointStatus::solved) {
      r.displacement.resize(dofs);
      MPI_Recv(r.displacement.data(), dofs, MPI_DOUBLE, from, kResultTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    }
    idle.push_back(from);
    wave.complete(r.point, r.status);
    ++stats.computed;
    stats.solve_seconds += r.seconds;
    record(r);
    for (auto p : wave.take_unreachable()) {
      record(unreachable_result(p));
      ++stats.unreachable;
    }
    if (options.stop_after > 0 && stats.computed >= options.stop_after && !wave.finished()) {
      stop = true;
      stats.stopped = true;
    }
    if (options.on_progress) options.on_progress(wave.resolved(), space.status.size());
  }
  for (int rank = 1; rank < session.size(); ++rank) MPI_Send(nullptr, 0, MPI_INT64_T, rank, kStopTag, MPI_COMM_WORLD);
  stats.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

void serve(ConfigurationSolver& solver, const Space& space, const Session&) {
  const auto dofs = static_cast<int>(space.displacement.rows());
  VecX source(dofs);
  for (;;) {
    std::int64_t head[2];
    MPI_Status st;
    MPI_Recv(head, 2, MPI_INT64_T, 0, MPI_ANY_TAG, MPI_COMM_WORLD, &st);
    if (st.MPI_TAG == kStopTag) return;
    if (head[1] >= 0) MPI_Recv(source.data(), dofs, MPI_DOUBLE, 0, kTaskTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    const PointResult r = run_task(solver, space, static_cast<std::size_t>(head[0]), head[1], source);
    const std::int64_t out[5] = {static_cast<std::int64_t>(r.point), static_cast<std::int64_t>(r.status), r.source,
                                 r.iterations, static_cast<std::int64_t>(r.reason.size())};
    const double values[5] = {r.residual, r.seconds, r.force.x(), r.force.y(), r.force.z()};
    MPI_Send(out, 5, MPI_INT64_T, 0, kResultTag, MPI_COMM_WORLD);
    MPI_Send(values, 5, MPI_DOUBLE, 0, kResultTag, MPI_COMM_WORLD);
    if (!r.reason.empty())
      MPI_Send(r.reason.data(), static_cast<int>(r.reason.size()), MPI_CHAR, 0, kResultTag, MPI_COMM_WORLD);
    if (r.status == PointStatus::solved)
      MPI_Send(r.displacement.data(), dofs, MPI_DOUBLE, 0, kResultTag, MPI_COMM_WORLD);
  }
}

#else

bool available() { return false; }

Session::Session() {
  if (launched_size() > 1)
    throw InputError("started by an MPI launcher with " + std::to_string(launched_size()) +
                     " ranks, but this build has no MPI support (configure with TACTUS_WITH_MPI=ON and Open MPI "
                     "installed), or run it without mpirun");
}

Session::~Session() = default;

BuildStats schedule(Space&, const BuildOptions&, const Session&) {
  throw std::logic_error("distributed::schedule needs a build with MPI");
}

void serve(ConfigurationSolver&, const Space&, const Session&) {
  throw std::logic_error("distributed::serve needs a build with MPI");
}

#endif

}  // namespace tactus::precompute::distributed
