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
#include <array>
#include <chrono>
#include <cstdio>
#include <deque>
#include <iterator>
#include <list>
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

/// A task's head: point, source, and when the scheduler sent it (now_ns(); the latency
/// emulation's clock). A result's head: point, status, source, iterations, reason length,
/// and when the scheduler may see it (0: at once; the latency emulation's far ranks).
constexpr int kTaskHead = 3;
constexpr int kResultHead = 6;
/// A result's numbers: residual, seconds, force (3), ∂force/∂x (9), torque (3), ∂torque/∂x (9).
constexpr int kResultValues = 26;

/// The rest of a result whose head came from `from`: its parts follow from the same rank in
/// order.
PointResult receive_result(const std::int64_t (&head)[kResultHead], int from, int dofs, std::vector<char>& reason) {
  double values[kResultValues];
  MPI_Recv(values, kResultValues, MPI_DOUBLE, from, kResultTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  PointResult r;
  r.point = static_cast<std::size_t>(head[0]);
  r.status = static_cast<PointStatus>(head[1]);
  r.source = head[2];
  r.iterations = static_cast<int>(head[3]);
  r.residual = values[0];
  r.seconds = values[1];
  r.force = Vec3(values[2], values[3], values[4]);
  r.force_gradient = Eigen::Map<const Mat3>(values + 5);
  r.torque = Vec3(values[14], values[15], values[16]);
  r.torque_gradient = Eigen::Map<const Mat3>(values + 17);
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
std::optional<int> probe_result(std::int64_t (&head)[kResultHead]) {
  int flag = 0;
  MPI_Status st;
  MPI_Iprobe(MPI_ANY_SOURCE, kResultTag, MPI_COMM_WORLD, &flag, &st);
  if (!flag) return std::nullopt;
  MPI_Recv(head, kResultHead, MPI_INT64_T, st.MPI_SOURCE, kResultTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
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

/// TACTUS_PRECOMPUTE_LATENCY="MS:JITTER_MS": the even solver ranks (2, 4, …) see every task
/// MS ± JITTER_MS milliseconds (uniform) after the scheduler sent it, and the scheduler sees
/// their results that long after they were sent, as a network of that one-way latency
/// between them would (half the ranks far away, as seed 001's two clusters 300 km apart).
/// The delays are delivery times: a task queued behind another one is not delayed again,
/// and a solver is not held while its result travels. For the latency study of
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
  /// One message's delay [ns]; 0 on a near rank.
  Nanos delay() {
    if (mean_ <= 0.0) return 0;
    std::uniform_real_distribution<double> u(-jitter_, jitter_);
    return static_cast<Nanos>((mean_ + u(rng_)) * static_cast<double>(kNanosPerSecond));
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

  // Per rank: the tasks it owes answers for, in the order sent (a rank answers in that
  // order); the first one's clock runs from when it could start (sent, or the answer
  // before it seen), and a rank whose first task is overdue has been given up on (its tasks
  // reissued, the rank kept out of the pool until it answers).
  struct Owed {
    Task task;
    clock::time_point since;
    bool overdue = false;
  };
  const std::size_t in_flight = std::max<std::size_t>(options.in_flight, 1);
  std::vector<std::deque<Owed>> owed(static_cast<std::size_t>(session.size()));
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
  // Whether point p is already owed by a rank not given up on, or waiting to be reissued.
  auto covered = [&](std::size_t p) {
    for (const auto& q : owed)
      for (const auto& o : q)
        if (o.task.point == p && !o.overdue) return true;
    for (const auto& t : reissue)
      if (t.point == p) return true;
    return false;
  };
  auto owing = [&] {
    std::size_t n = 0;
    for (const auto& q : owed) n += q.size();
    return n;
  };
  // Results of far ranks waiting for their delivery time (the latency emulation).
  struct Delayed {
    Nanos deliver = 0;
    int from = 0;
    PointResult result;
  };
  std::vector<Delayed> delayed;

  bool stop = false;
  // The rank seen answering `r`: its first owed task is done, the next one starts.
  auto accept = [&](int from, PointResult&& r) {
    auto& q = owed[static_cast<std::size_t>(from)];
    if (!q.empty()) q.pop_front();
    if (!q.empty()) q.front().since = clock::now();
    if (wave.status()[r.point] != PointStatus::pending || r.source != wave.source_of(r.point)) {
      // Another rank answered first (or the point has moved on to another source since):
      // this answer is late and is not recorded again.
      ++stats.late;
      return;
    }
    solve_times.push_back(r.seconds);
    ++stats.computed;
    stats.solve_seconds += r.seconds;
    if (wave.complete(r.point, r.status)) {
      note_tries(r, wave.failed_tries(r.point));
      record(r);
    } else {
      ++stats.retried;
    }
    for (auto p : wave.take_unreachable()) {
      record(unreachable_result(p));
      ++stats.unreachable;
    }
    if (options.stop_after > 0 && stats.computed >= options.stop_after && !wave.finished()) {
      stop = true;
      stats.stopped = true;
    }
    if (options.on_progress) options.on_progress(wave.resolved(), space.status.size());
  };
  // An answer after the build: the rank owes one less, nothing is recorded.
  auto drop = [&](int from) {
    auto& q = owed[static_cast<std::size_t>(from)];
    if (!q.empty()) q.pop_front();
    ++stats.late;
  };
  // The next result: a delayed one whose time has come, else one from the wire (held back
  // if it carries a later delivery time). False when none is ready.
  std::vector<char> reason;
  auto next_result = [&](bool count_as_late) {
    const Nanos now = now_ns();
    for (std::size_t k = 0; k < delayed.size(); ++k)
      if (delayed[k].deliver <= now) {
        Delayed d = std::move(delayed[k]);
        delayed.erase(delayed.begin() + static_cast<std::ptrdiff_t>(k));
        if (count_as_late) drop(d.from);
        else accept(d.from, std::move(d.result));
        return true;
      }
    std::int64_t head[kResultHead];
    const std::optional<int> from = probe_result(head);
    if (!from) return false;
    PointResult r = receive_result(head, *from, dofs, reason);
    if (head[5] > now) {
      delayed.push_back({head[5], *from, std::move(r)});
      return true;
    }
    if (count_as_late) drop(*from);
    else accept(*from, std::move(r));
    return true;
  };

  // Tasks on their way: each send's buffers and requests until it completes.
  struct Sending {
    int rank = 0;
    std::array<std::int64_t, kTaskHead> head{};
    std::array<MPI_Request, 2> requests{MPI_REQUEST_NULL, MPI_REQUEST_NULL};
  };
  std::list<Sending> sending;
  auto reap = [&] {
    for (auto it = sending.begin(); it != sending.end();) {
      int done = 0;
      MPI_Testall(2, it->requests.data(), &done, MPI_STATUSES_IGNORE);
      it = done ? sending.erase(it) : std::next(it);
    }
  };

  while (!wave.finished()) {
    reap();
    // Hand the ready transitions, reissued ones first, to the ranks with the fewest owed,
    // up to `in_flight` each; a rank given up on takes none.
    for (std::size_t load = 0; load < in_flight && !stop; ++load)
      for (int rank = 1; rank < session.size() && !stop; ++rank) {
        auto& q = owed[static_cast<std::size_t>(rank)];
        if (q.size() != load || (!q.empty() && q.front().overdue)) continue;
        std::optional<Task> task;
        while (!task && !reissue.empty()) {
          const Task t = reissue.front();
          reissue.pop_front();
          // Not answered meanwhile, nor moved on to another source after a failure.
          if (wave.status()[t.point] == PointStatus::pending && t.source == wave.source_of(t.point)) task = t;
        }
        if (!task) task = wave.next();
        if (!task) break;
        // Sent without waiting: a rank still solving the task before this one takes it only
        // when it asks, and meanwhile its answer must be received (a blocking send of the
        // source's displacements, too large to be buffered, would wait for the rank while
        // the rank waits for us to take its answer).
        Sending& out = sending.emplace_back();
        out.rank = rank;
        out.head = {static_cast<std::int64_t>(task->point), task->source, now_ns()};
        MPI_Isend(out.head.data(), kTaskHead, MPI_INT64_T, rank, kTaskTag, MPI_COMM_WORLD, &out.requests[0]);
        if (task->source >= 0)  // a solved point's column: it is not written again
          MPI_Isend(space.displacement.col(static_cast<Eigen::Index>(task->source)).data(), dofs, MPI_DOUBLE, rank,
                    kTaskTag, MPI_COMM_WORLD, &out.requests[1]);
        q.push_back({*task, clock::now(), false});
      }
    if (wave.in_flight() == 0) break;  // stopped, or nothing can run any more
    if (next_result(false)) continue;
    // Nothing arrived: give up on ranks whose first task is owed for longer than the timeout,
    // and hand all they owe to others.
    const auto now = clock::now();
    const double limit = timeout();
    for (std::size_t rank = 1; rank < owed.size(); ++rank) {
      auto& q = owed[rank];
      if (q.empty() || q.front().overdue || std::chrono::duration<double>(now - q.front().since).count() <= limit)
        continue;
      log::warn("rank {} has not answered point {} in {:.1f} s (timeout {:.1f} s): {} handed to another rank", rank,
                q.front().task.point, std::chrono::duration<double>(now - q.front().since).count(), limit,
                q.size() == 1 ? "it is" : "its tasks are");
      for (auto& o : q) {
        o.overdue = true;
        if (wave.status()[o.task.point] != PointStatus::pending || o.task.source != wave.source_of(o.task.point) ||
            covered(o.task.point))
          continue;
        reissue.push_back(o.task);
        ++stats.reissued;
      }
    }
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  // Ranks that still owe answers (overdue ones, or tasks sent before a stop) get a last
  // chance to send them, so that every rank is back in its receive and takes the stop; a rank
  // silent beyond that is hung.
  const auto drain_start = clock::now();
  const double drain = std::max(timeout(), 10.0);
  while (owing() > 0 && std::chrono::duration<double>(clock::now() - drain_start).count() <= drain)
    if (!next_result(true)) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  for (int rank = 1; rank < session.size(); ++rank) {
    if (!owed[static_cast<std::size_t>(rank)].empty()) {
      ++stats.unresponsive;
      continue;  // a hung rank takes no message
    }
    // Every task sent to it was taken (it answered them all) before the stop.
    for (auto& out : sending)
      if (out.rank == rank) MPI_Waitall(2, out.requests.data(), MPI_STATUSES_IGNORE);
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
  // This schedule's share only: a probe space's levels are served one after another.
  const double cpu0 = process_cpu_seconds();
  for (;;) {
    std::int64_t head[kTaskHead];
    MPI_Status st;
    MPI_Recv(head, kTaskHead, MPI_INT64_T, 0, MPI_ANY_TAG, MPI_COMM_WORLD, &st);
    if (st.MPI_TAG == kStopTag) {
      const double cpu = process_cpu_seconds() - cpu0;
      MPI_Send(&cpu, 1, MPI_DOUBLE, 0, kCpuTag, MPI_COMM_WORLD);
      return;
    }
    if (head[1] >= 0) MPI_Recv(source.data(), dofs, MPI_DOUBLE, 0, kTaskTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (const Nanos d = latency.delay(); d > 0) sleep_until(head[2] + d);  // the task's arrival
    if (++tasks == stall.task && session.rank() == stall.rank)
      std::this_thread::sleep_for(std::chrono::duration<double>(stall.seconds));
    const PointResult r = run_task(solver, space, static_cast<std::size_t>(head[0]), head[1], source);
    const Nanos travel = latency.delay();
    const std::int64_t out[kResultHead] = {static_cast<std::int64_t>(r.point), static_cast<std::int64_t>(r.status),
                                           r.source, r.iterations, static_cast<std::int64_t>(r.reason.size()),
                                           travel > 0 ? now_ns() + travel : 0};
    double values[kResultValues] = {r.residual, r.seconds, r.force.x(), r.force.y(), r.force.z()};
    Eigen::Map<Mat3>(values + 5) = r.force_gradient;
    for (int k = 0; k < 3; ++k) values[14 + k] = r.torque[k];
    Eigen::Map<Mat3>(values + 17) = r.torque_gradient;
    MPI_Send(out, kResultHead, MPI_INT64_T, 0, kResultTag, MPI_COMM_WORLD);
    MPI_Send(values, kResultValues, MPI_DOUBLE, 0, kResultTag, MPI_COMM_WORLD);
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

bool Session::decide(bool go) const {
  if (!initialized_) return go;
  int value = go ? 1 : 0;
  MPI_Bcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return value != 0;
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

bool Session::decide(bool go) const { return go; }

BuildStats schedule(Space&, const BuildOptions&, const Session&) {
  throw std::logic_error("distributed::schedule needs a build with MPI");
}

void serve(ConfigurationSolver&, const Space&, const Session&) {
  throw std::logic_error("distributed::serve needs a build with MPI");
}

#endif

}  // namespace tactus::precompute::distributed
