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

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <optional>
#include <random>
#include <thread>
#include <vector>

#include "core/clock.hpp"
#include "core/log.hpp"
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
constexpr int kCpuTag = 4;  // a solver rank's CPU seconds, sent when it stops

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

namespace {

/// The rest of a result whose head (point, status, source, iterations, reason length) came
/// from `from`: its parts follow from the same rank in order.
PointResult receive_result(const std::int64_t (&head)[5], int from, int dofs, std::vector<char>& reason) {
  double values[14];
  MPI_Recv(values, 14, MPI_DOUBLE, from, kResultTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  PointResult r;
  r.point = static_cast<std::size_t>(head[0]);
  r.status = static_cast<PointStatus>(head[1]);
  r.source = head[2];
  r.iterations = static_cast<int>(head[3]);
  r.residual = values[0];
  r.seconds = values[1];
  r.force = Vec3(values[2], values[3], values[4]);
  r.force_gradient = Eigen::Map<const Mat3>(values + 5);
  if (head[4] > 0) {
    reason.resize(static_cast<std::size_t>(head[4]));
    MPI_Recv(reason.data(), static_cast<int>(head[4]), MPI_CHAR, from, kResultTag, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    r.reason.assign(reason.begin(), reason.end());
  }
  if (r.status == PointStatus::solved) {
    r.displacement.resize(dofs);
    MPI_Recv(r.displacement.data(), dofs, MPI_DOUBLE, from, kResultTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    r.displacement_gradient.resize(dofs, 3);
    MPI_Recv(r.displacement_gradient.data(), 3 * dofs, MPI_DOUBLE, from, kResultTag, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
  }
  return r;
}

/// The next result's head from any rank, or nothing when none is waiting.
std::optional<int> probe_result(std::int64_t (&head)[5]) {
  int flag = 0;
  MPI_Status st;
  MPI_Iprobe(MPI_ANY_SOURCE, kResultTag, MPI_COMM_WORLD, &flag, &st);
  if (!flag) return std::nullopt;
  MPI_Recv(head, 5, MPI_INT64_T, st.MPI_SOURCE, kResultTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return st.MPI_SOURCE;
}

/// TACTUS_PRECOMPUTE_STALL="RANK:TASK:SECONDS": rank RANK sleeps SECONDS before its TASK-th
/// task (counted from 1). A fault injected by the tests of reissue; unset, nothing.
struct Stall {
  int rank = -1;
  long task = 0;
  double seconds = 0.0;
};
Stall stall_from_environment() {
  Stall s;
  if (const char* v = std::getenv("TACTUS_PRECOMPUTE_STALL"))
    if (std::sscanf(v, "%d:%ld:%lf", &s.rank, &s.task, &s.seconds) != 3) s = Stall{};
  return s;
}

/// TACTUS_PRECOMPUTE_LATENCY="MS:JITTER_MS": the even solver ranks (2, 4, …) hold every task
/// they receive and every result they send MS ± JITTER_MS milliseconds (uniform), as a
/// network of that one-way latency between them and the scheduler would (half the ranks far
/// away, as seed 001's two clusters 300 km apart). For the latency study of
/// docs/precompute.md; unset, nothing.
class Latency {
 public:
  explicit Latency(int rank) : rng_(static_cast<unsigned>(rank)) {
    const char* v = std::getenv("TACTUS_PRECOMPUTE_LATENCY");
    double ms = 0.0, jitter = 0.0;
    if (!v || rank % 2 != 0 || std::sscanf(v, "%lf:%lf", &ms, &jitter) != 2 || !(ms >= 0.0) || !(jitter >= 0.0)) return;
    mean_ = 1e-3 * ms;
    jitter_ = 1e-3 * std::min(jitter, ms);
  }
  /// One message's delay.
  void hold() {
    if (mean_ <= 0.0) return;
    std::uniform_real_distribution<double> u(-jitter_, jitter_);
    std::this_thread::sleep_for(std::chrono::duration<double>(mean_ + u(rng_)));
  }

 private:
  double mean_ = 0.0, jitter_ = 0.0;
  std::mt19937 rng_;
};

}  // namespace

BuildStats schedule(Space& space, const BuildOptions& options, const Session& session) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  BuildStats stats;
  stats.workers = static_cast<unsigned>(session.size() - 1);
  Wavefront wave(space.grid, space.start, space.status);
  const auto dofs = static_cast<int>(space.displacement.rows());
  auto record = [&](const PointResult& r) {
    space.store(r);
    if (options.on_result) options.on_result(r);
  };
  for (auto p : wave.take_unreachable()) record(unreachable_result(p));

  // Per rank: the task it owes an answer for (point -1: none), when it was sent, and whether
  // it has been given up on (the task reissued, the rank kept out of the pool until it
  // answers).
  struct Owed {
    Task task;
    std::int64_t point = -1;
    clock::time_point sent;
    bool overdue = false;
  };
  std::vector<Owed> owed(static_cast<std::size_t>(session.size()));
  std::deque<Task> reissue;
  std::vector<double> solve_times;
  auto timeout = [&] {
    double median = 0.0;
    if (!solve_times.empty()) {
      std::vector<double> v = solve_times;
      std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
      median = v[v.size() / 2];
    }
    return std::max(options.reissue_floor, options.reissue_factor * median);
  };
  // Whether point p is already owed by a rank not overdue, or waiting to be reissued.
  auto covered = [&](std::int64_t p) {
    for (const auto& o : owed)
      if (o.point == p && !o.overdue) return true;
    for (const auto& t : reissue)
      if (static_cast<std::int64_t>(t.point) == p) return true;
    return false;
  };

  std::vector<int> idle;
  for (int r = session.size() - 1; r >= 1; --r) idle.push_back(r);
  bool stop = false;
  std::vector<char> reason;
  while (!wave.finished()) {
    // Hand every ready transition, reissued ones first, to an idle rank.
    while (!stop && !idle.empty()) {
      std::optional<Task> task;
      while (!task && !reissue.empty()) {
        const Task t = reissue.front();
        reissue.pop_front();
        if (wave.status()[t.point] == PointStatus::pending) task = t;  // not answered meanwhile
      }
      if (!task) task = wave.next();
      if (!task) break;
      const int rank = idle.back();
      idle.pop_back();
      const std::int64_t head[2] = {static_cast<std::int64_t>(task->point), task->source};
      MPI_Send(head, 2, MPI_INT64_T, rank, kTaskTag, MPI_COMM_WORLD);
      if (task->source >= 0)
        MPI_Send(space.displacement.col(static_cast<Eigen::Index>(task->source)).data(), dofs, MPI_DOUBLE, rank,
                 kTaskTag, MPI_COMM_WORLD);
      owed[static_cast<std::size_t>(rank)] = {*task, static_cast<std::int64_t>(task->point), clock::now(), false};
    }
    if (wave.in_flight() == 0) break;  // stopped, or nothing can run any more
    std::int64_t head[5];
    const std::optional<int> from = probe_result(head);
    if (!from) {
      // Nothing arrived: give up on transitions owed for longer than the timeout.
      const auto now = clock::now();
      const double limit = timeout();
      for (std::size_t rank = 1; rank < owed.size(); ++rank) {
        Owed& o = owed[rank];
        if (o.point < 0 || o.overdue || std::chrono::duration<double>(now - o.sent).count() <= limit) continue;
        o.overdue = true;
        if (wave.status()[o.task.point] != PointStatus::pending || covered(o.point)) continue;
        reissue.push_back(o.task);
        ++stats.reissued;
        log::warn("rank {} has not answered point {} in {:.1f} s (timeout {:.1f} s): handed to another rank", rank,
                  o.point, std::chrono::duration<double>(now - o.sent).count(), limit);
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      continue;
    }
    PointResult r = receive_result(head, *from, dofs, reason);
    owed[static_cast<std::size_t>(*from)].point = -1;
    idle.push_back(*from);
    if (wave.status()[r.point] != PointStatus::pending) {
      // Another rank answered first: this answer is late and is not recorded again.
      ++stats.late;
      continue;
    }
    solve_times.push_back(r.seconds);
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
  // Ranks that still owe an answer (overdue ones) get a last chance to send it, so that
  // every rank is back in its receive and takes the stop; a rank silent beyond that is hung.
  const auto drain_start = clock::now();
  const double drain = std::max(timeout(), 10.0);
  for (;;) {
    bool owing = false;
    for (std::size_t rank = 1; rank < owed.size(); ++rank) owing = owing || owed[rank].point >= 0;
    if (!owing || std::chrono::duration<double>(clock::now() - drain_start).count() > drain) break;
    std::int64_t head[5];
    if (const std::optional<int> from = probe_result(head)) {
      receive_result(head, *from, dofs, reason);
      owed[static_cast<std::size_t>(*from)].point = -1;
      ++stats.late;
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  for (int rank = 1; rank < session.size(); ++rank) {
    if (owed[static_cast<std::size_t>(rank)].point >= 0) {
      ++stats.unresponsive;
      continue;  // a hung rank takes no message
    }
    MPI_Send(nullptr, 0, MPI_INT64_T, rank, kStopTag, MPI_COMM_WORLD);
    double cpu = 0.0;
    MPI_Recv(&cpu, 1, MPI_DOUBLE, rank, kCpuTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    stats.solver_cpu_seconds += cpu;
  }
  stats.wall_seconds = std::chrono::duration<double>(clock::now() - t0).count();
  return stats;
}

void serve(ConfigurationSolver& solver, const Space& space, const Session& session) {
  const auto dofs = static_cast<int>(space.displacement.rows());
  const Stall stall = stall_from_environment();
  Latency latency(session.rank());
  long tasks = 0;
  VecX source(dofs);
  for (;;) {
    std::int64_t head[2];
    MPI_Status st;
    MPI_Recv(head, 2, MPI_INT64_T, 0, MPI_ANY_TAG, MPI_COMM_WORLD, &st);
    if (st.MPI_TAG == kStopTag) {
      const double cpu = process_cpu_seconds();
      MPI_Send(&cpu, 1, MPI_DOUBLE, 0, kCpuTag, MPI_COMM_WORLD);
      return;
    }
    if (head[1] >= 0) MPI_Recv(source.data(), dofs, MPI_DOUBLE, 0, kTaskTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    latency.hold();
    if (++tasks == stall.task && session.rank() == stall.rank)
      std::this_thread::sleep_for(std::chrono::duration<double>(stall.seconds));
    const PointResult r = run_task(solver, space, static_cast<std::size_t>(head[0]), head[1], source);
    const std::int64_t out[5] = {static_cast<std::int64_t>(r.point), static_cast<std::int64_t>(r.status), r.source,
                                 r.iterations, static_cast<std::int64_t>(r.reason.size())};
    latency.hold();
    double values[14] = {r.residual, r.seconds, r.force.x(), r.force.y(), r.force.z()};
    Eigen::Map<Mat3>(values + 5) = r.force_gradient;
    MPI_Send(out, 5, MPI_INT64_T, 0, kResultTag, MPI_COMM_WORLD);
    MPI_Send(values, 14, MPI_DOUBLE, 0, kResultTag, MPI_COMM_WORLD);
    if (!r.reason.empty())
      MPI_Send(r.reason.data(), static_cast<int>(r.reason.size()), MPI_CHAR, 0, kResultTag, MPI_COMM_WORLD);
    if (r.status == PointStatus::solved) {
      MPI_Send(r.displacement.data(), dofs, MPI_DOUBLE, 0, kResultTag, MPI_COMM_WORLD);
      MPI_Send(r.displacement_gradient.data(), 3 * dofs, MPI_DOUBLE, 0, kResultTag, MPI_COMM_WORLD);
    }
  }
}

void Session::abort_job(int code) {
  if (initialized_) MPI_Abort(MPI_COMM_WORLD, code);
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

void Session::abort_job(int) {}

BuildStats schedule(Space&, const BuildOptions&, const Session&) {
  throw std::logic_error("distributed::schedule needs a build with MPI");
}

void serve(ConfigurationSolver&, const Space&, const Session&) {
  throw std::logic_error("distributed::serve needs a build with MPI");
}

#endif

}  // namespace tactus::precompute::distributed
