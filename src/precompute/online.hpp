#pragma once
// On-line construction of a configuration space (seed 001 §3.4, after Filipovič et al.):
// configurations are solved while the user moves, around the interaction point and ahead of
// it along its direction of motion, instead of in a separate phase before.
//
//  - OnlineScheduler (no threads, deterministic): which grid point to solve next. The
//    candidates are the pending points next to a solved one (the frontier); the one nearest
//    the predicted tool path (from the tool's position, along its velocity, `lookahead`
//    seconds ahead) wins, and it is reached from a solved neighbour, the wavefront's own
//    candidates first (so a point reached the same way as offline gets the same bits).
//  - OnlineBuilder: worker threads that run the scheduler's transitions, and the haptic
//    side: observe() and render() publish the tool and answer forces without allocating or
//    locking, from solved points only.
//  - simulate_online(): the same scheduler against a tool path in simulated time, with a
//    given cost per solve (deterministic: tests, and the scaling model of the benchmarks).
// docs/precompute.md ("On-line construction") states the rules and the fallback bound.
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "physics/body.hpp"
#include "precompute/space.hpp"
#include "precompute/wavefront.hpp"

namespace tactus::precompute {

struct OnlineSettings {
  /// How far ahead the path is predicted [s]: the scheduler works along position + velocity
  /// · τ for τ in [0, lookahead].
  double lookahead = 1.0;
  /// Weight of the distance along the predicted path against the distance from it: points
  /// the tool reaches sooner go first, but a point beside the path (a corner of the cells
  /// the tool will cross) beats one far ahead on it.
  double along_weight = 0.25;
  /// The rendered force changes by at most this much from one query to the next [N]
  /// (1 kHz: 100 N/s). It bounds the step a fallback or a newly completed cell can cause.
  double max_force_step = 0.1;
  /// The velocity estimate is smoothed over this time constant [s].
  double velocity_smoothing = 0.02;
};

/// Which points to solve and from where. Not thread-safe (the builder locks around it).
class OnlineScheduler {
 public:
  OnlineScheduler(const Grid& grid, std::size_t start, OnlineSettings settings = {});

  /// The next transition for a tool at `position` moving at `velocity`: the start point
  /// first, then the frontier point nearest the predicted path. Nothing when the frontier is
  /// empty (everything solved, failed or in flight). The point is in flight until complete().
  std::optional<Task> next(const Vec3& position, const Vec3& velocity);
  /// Records a finished task's outcome. A failure goes back to the frontier to be tried from
  /// another solved neighbour while there is one it was not tried from; then it returns
  /// false (the point stays pending: record nothing for it yet). Otherwise returns true.
  bool complete(std::size_t point, PointStatus outcome);

  /// Lower is sooner: distance from the predicted path plus along_weight · distance along it.
  [[nodiscard]] double priority(std::size_t point, const Vec3& position, const Vec3& velocity) const;
  /// The solved neighbour a point would be reached from now: the wavefront's candidates
  /// first, then the other face neighbours, none it failed from; -1 when there is none.
  [[nodiscard]] std::int64_t source_for(std::size_t point) const;

  [[nodiscard]] const std::vector<PointStatus>& status() const { return status_; }
  [[nodiscard]] std::size_t frontier_size() const { return frontier_.size(); }
  [[nodiscard]] std::size_t in_flight() const { return in_flight_; }
  [[nodiscard]] const Grid& grid() const { return grid_; }

 private:
  void add_neighbours_to_frontier(std::size_t point);
  /// Calls visit(q) for each grid point one step along an axis from `point`.
  template <class Visit>
  void for_each_neighbour(std::size_t point, Visit&& visit) const;
  /// Bit of tried_[point] for its face neighbour q (0-5).
  [[nodiscard]] std::uint8_t direction_bit(std::size_t point, std::size_t q) const;

  Grid grid_;
  std::size_t start_;
  OnlineSettings settings_;
  Wavefront rule_;  ///< only for its candidate order
  std::vector<PointStatus> status_;
  std::vector<std::uint8_t> busy_;      ///< in flight, or in the frontier
  std::vector<std::uint8_t> tried_;     ///< per point, a bit per face neighbour it failed from
  std::vector<std::int64_t> source_;    ///< per point, the source of its latest task
  std::vector<std::size_t> frontier_;   ///< pending points with a solved neighbour
  bool start_handed_out_ = false;
  std::size_t in_flight_ = 0;
};

/// What the haptic side gets for a position.
struct OnlineQuery {
  Vec3 force = Vec3::Zero();  ///< force the body exerts on the tool [N]; always finite
  bool complete = false;      ///< every corner of the cell the query weighs was solved
  bool fallback = false;      ///< not complete: the nearest solved corner's force, or the last force
  bool limited = false;       ///< the change was cut to max_force_step
};

/// The lookup behind OnlineBuilder::render, on any status/force arrays. `state(q)` is 0 for
/// a point not resolved yet, 1 solved, 2 failed (or unreachable). Over the cell of p
/// (clamped onto the grid's box), the corners of nonzero trilinear weight:
///  - all resolved, at least one solved: `complete`; trilinear over the solved ones, their
///    weights renormalized (what Interpolator gives from the finished space; exact at a
///    solved grid point);
///  - otherwise not complete; `force` is the solved corner of largest weight, and `found`
///    is false when none is solved.
struct CellLookup {
  Vec3 force = Vec3::Zero();
  bool complete = false;
  bool found = false;
};
template <class StateFn, class ForceFn>
CellLookup lookup_cell(const Grid& grid, const Vec3& p, StateFn&& state, ForceFn&& force) noexcept;

/// One haptic frame of the fallback rule: the lookup's force when found (complete or the
/// nearest solved corner), else `last`; a non-finite target keeps `last`; the change from
/// `last` is cut to max_step. Updates `last` to the rendered force.
OnlineQuery render_step(const CellLookup& lookup, Vec3& last, double max_step) noexcept;

/// One solve: point, its source (-1: the start, from rest), the source's displacement.
using TransitionFn = std::function<PointResult(std::size_t point, std::int64_t source, const VecX& source_displacement)>;
/// Called once per worker thread, on that thread: its own solver.
using TransitionFactory = std::function<TransitionFn()>;

/// Workers that run real transitions: each builds its own ConfigurationSolver for `body`.
TransitionFactory solver_transitions(const physics::Body& body, const SpaceSettings& settings, const Grid& grid);

class OnlineBuilder {
 public:
  /// `space`: from make_space (allocated, every point pending). Starts `workers` threads at
  /// once; the first solves the start point.
  OnlineBuilder(Space space, TransitionFactory factory, unsigned workers, OnlineSettings settings = {});
  ~OnlineBuilder();
  OnlineBuilder(const OnlineBuilder&) = delete;
  OnlineBuilder& operator=(const OnlineBuilder&) = delete;

  // The haptic thread (one): no allocation, no lock.
  /// The tool is at `position` at time `t` [s] (monotonic): updates the velocity estimate
  /// and publishes both to the workers.
  void observe(const Vec3& position, double t) noexcept;
  /// The force to render at p: from solved points only, never NaN, never more than
  /// max_force_step away from the previous render().
  OnlineQuery render(const Vec3& p) noexcept;
  /// The raw lookup (no fallback, no step bound).
  [[nodiscard]] CellLookup lookup(const Vec3& p) const noexcept;
  /// Nodal displacement (3N) at p for the viewer (any thread but the haptic one: it locks):
  /// trilinear over the solved corners of p's cell, weights renormalized; zero when none is
  /// solved. Returns whether one was. Allocates only when u has another size.
  bool shape(const Vec3& p, VecX& u) const;

  /// Stops the workers after their current solve. Idempotent.
  void stop();
  /// Rethrows the first exception a worker raised, if any.
  void check() const;

  /// Whether point p is solved or failed (any thread).
  [[nodiscard]] bool resolved(std::size_t p) const noexcept {
    return published_[p].load(std::memory_order_acquire) != 0;
  }
  /// Solved so far (any thread).
  [[nodiscard]] std::size_t solved_count() const { return solved_count_.load(std::memory_order_acquire); }
  /// Solves started for each point (a test that no point is solved twice).
  [[nodiscard]] std::vector<int> solve_counts() const;
  /// The space so far (call after stop(): a copy under the lock otherwise).
  [[nodiscard]] Space snapshot() const;
  [[nodiscard]] const Grid& grid() const { return grid_; }

 private:
  void work(unsigned index);

  Grid grid_;
  OnlineSettings settings_;
  TransitionFactory factory_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  Space space_;                       ///< written under mutex_
  OnlineScheduler scheduler_;         ///< under mutex_
  std::vector<int> solve_counts_;     ///< under mutex_
  bool stop_ = false;
  std::exception_ptr error_;

  /// Per point: 1 once solved and its force (in forces_) published, 2 once failed;
  /// release/acquire pairs with the force.
  std::unique_ptr<std::atomic<std::uint8_t>[]> published_;
  std::vector<Vec3> forces_;  ///< written once per point before published_
  std::atomic<std::size_t> solved_count_{0};

  // The tool, as the haptic thread last published it (component-wise: a torn read only
  // blurs the prediction for one pick).
  std::atomic<double> position_[3];
  std::atomic<double> velocity_[3];
  // Haptic-thread state.
  Vec3 last_position_ = Vec3::Zero();
  Vec3 velocity_estimate_ = Vec3::Zero();
  double last_time_ = 0.0;
  bool observed_ = false;
  Vec3 last_force_ = Vec3::Zero();

  std::vector<std::thread> threads_;
};

/// A tool path: straight segments through waypoints, walked at a constant speed after a
/// dwell at the first waypoint. The drivers below lengthen the dwell until the start point's
/// neighbourhood (the up to 27 points within one cell of it) is resolved: the user touches
/// and holds still until the space around the touch is there, then moves; what is measured
/// is the speed sustained while moving.
struct ToolPath {
  std::vector<Vec3> waypoints;
  double speed = 0.01;  ///< [m/s]
  double dwell = 0.5;   ///< [s] at the first waypoint before moving
  [[nodiscard]] double length() const;
  [[nodiscard]] double duration() const { return dwell + length() / speed; }
  [[nodiscard]] Vec3 at(double t) const;
};

/// The scripted path of the speed search on `grid` from its start point: one spacing down,
/// to the box's +x side, to its +y side, to its −x side (clamped into the box).
ToolPath scripted_path(const Grid& grid, std::size_t start);

struct DriveResult {
  double speed = 0.0;
  double wait = 0.0;           ///< [s] at the start before moving (the dwell, lengthened)
  std::size_t queries = 0;     ///< haptic queries while moving (after the dwell)
  std::size_t complete = 0;    ///< of those, the cell was complete
  std::size_t solved = 0;      ///< points solved by the end
  double max_step = 0.0;       ///< largest change of the rendered force between queries [N]
  bool finite = true;          ///< every rendered force was finite
  [[nodiscard]] double fraction() const {
    return queries ? static_cast<double>(complete) / static_cast<double>(queries) : 0.0;
  }
};

/// Drives `path` in simulated time at `rate` queries per second against `workers` workers
/// that each take cost(point) seconds per solve, with the OnlineScheduler. Deterministic.
DriveResult simulate_online(const Grid& grid, std::size_t start, const ToolPath& path, unsigned workers,
                            const std::function<double(std::size_t)>& cost, OnlineSettings settings = {},
                            double rate = 1000.0);

/// Drives `path` in real time at 1 kHz against `builder` (render() each tick). Gives up
/// (no query counted) when the neighbourhood of the start is not resolved within
/// `max_wait` seconds.
DriveResult drive_online(OnlineBuilder& builder, const ToolPath& path, double max_wait = 300.0);

/// The start point and its neighbours within one cell (up to 27 points).
std::vector<std::size_t> neighbourhood(const Grid& grid, std::size_t point);

/// The largest speed at which `trial(speed)` keeps fraction() >= criterion: doubling from
/// `first` until a trial fails (halving, at most 4 times, when `first` fails), then
/// `bisections` bisections. Trials in the order run.
struct SpeedSearch {
  std::vector<DriveResult> trials;
  double max_speed = 0.0;  ///< 0: even first / 16 failed
  bool bounded = false;    ///< a trial failed: max_speed is a maximum, not just a speed that passed
};
SpeedSearch search_speed(const std::function<DriveResult(double speed)>& trial, double first, double criterion,
                         int bisections, double ceiling = 1.0);

/// The speed search on a real body: each trial a fresh OnlineBuilder (every point pending)
/// with `workers` solver threads, driven in real time along scripted_path at 1 kHz.
struct OnlineSpeedOptions {
  unsigned workers = 2;
  double first = 0.004;      ///< first speed tried [m/s]
  double criterion = 0.99;   ///< fraction of haptic queries that must find their cell complete
  int bisections = 3;
  double dwell = 0.5;        ///< [s] at the start point before moving
  OnlineSettings settings;
  /// After each trial: its result and the space it built (solve times per point).
  std::function<void(const DriveResult&, const Space&)> on_trial;
};
SpeedSearch online_speed(const physics::Body& body, const SpaceSettings& settings, const OnlineSpeedOptions& options);

// ---------------------------------------------------------------------------------------

/// Calls visit(q, w) for each corner q of the cell of p (clamped onto the grid's box) with a
/// nonzero trilinear weight w.
template <class Visit>
void for_each_cell_corner(const Grid& grid, const Vec3& p, Visit&& visit) noexcept {
  int lower[3];
  double t[3];
  for (int a = 0; a < 3; ++a) {
    const int n = grid.counts[static_cast<std::size_t>(a)];
    double u = (p[a] - grid.origin[a]) / grid.spacing;
    if (!(u >= 0.0)) u = 0.0;  // also NaN
    if (u > n - 1) u = n - 1;
    int c = static_cast<int>(u);
    if (c > n - 2) c = n - 2;
    if (c < 0) c = 0;
    lower[a] = c;
    t[a] = n > 1 ? u - c : 0.0;
  }
  for (int corner = 0; corner < 8; ++corner) {
    int idx[3];
    double w = 1.0;
    for (int a = 0; a < 3; ++a) {
      const int bit = (corner >> a) & 1;
      idx[a] = lower[a] + bit;
      w *= bit ? t[a] : 1.0 - t[a];
    }
    if (w == 0.0) continue;
    if (!grid.contains(idx[0], idx[1], idx[2])) continue;
    visit(grid.index(idx[0], idx[1], idx[2]), w);
  }
}

template <class StateFn, class ForceFn>
CellLookup lookup_cell(const Grid& grid, const Vec3& p, StateFn&& state, ForceFn&& force) noexcept {
  CellLookup out;
  double best = -1.0, sum_w = 0.0;
  Vec3 sum = Vec3::Zero();
  bool resolved = true;
  for_each_cell_corner(grid, p, [&](std::size_t q, double w) {
    const int s = state(q);
    if (s != 1) {
      resolved = resolved && s != 0;
      return;
    }
    const Vec3 f = force(q);
    sum += w * f;
    sum_w += w;
    if (w > best) {
      best = w;
      out.force = f;
    }
  });
  out.found = best >= 0.0;
  out.complete = resolved && out.found;
  if (out.complete) out.force = sum_w == 1.0 ? sum : Vec3(sum / sum_w);
  return out;
}

}  // namespace tactus::precompute
