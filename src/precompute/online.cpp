#include "precompute/online.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <queue>
#include <thread>
#include <tuple>
#include <utility>

#include "precompute/builder.hpp"
#include "precompute/configuration_solver.hpp"

namespace tactus::precompute {

// ---------------------------------------------------------------------------------------
// OnlineScheduler

OnlineScheduler::OnlineScheduler(const Grid& grid, std::size_t start, OnlineSettings settings)
    : grid_(grid),
      start_(start),
      settings_(settings),
      rule_(grid, start, std::vector<PointStatus>(grid.size(), PointStatus::pending)),
      status_(grid.size(), PointStatus::pending),
      busy_(grid.size(), 0),
      tried_(grid.size(), 0),
      source_(grid.size(), -1) {}

double OnlineScheduler::priority(std::size_t point, const Vec3& position, const Vec3& velocity) const {
  const Vec3 g = grid_.point(point);
  const Vec3 ahead = velocity * settings_.lookahead;
  const double len2 = ahead.squaredNorm();
  double s = 0.0;
  if (len2 > 1e-18) s = std::clamp((g - position).dot(ahead) / len2, 0.0, 1.0);
  const Vec3 nearest = position + s * ahead;
  return (g - nearest).norm() + settings_.along_weight * s * std::sqrt(len2);
}

/// The grid points one step along each axis from `point` (at most six), in a fixed order.
template <class Visit>
void OnlineScheduler::for_each_neighbour(std::size_t point, Visit&& visit) const {
  const auto c = grid_.cell(point);
  for (int a = 0; a < 3; ++a)
    for (int d : {-1, 1}) {
      auto n = c;
      n[static_cast<std::size_t>(a)] += d;
      if (grid_.contains(n[0], n[1], n[2])) visit(grid_.index(n[0], n[1], n[2]));
    }
}

std::uint8_t OnlineScheduler::direction_bit(std::size_t point, std::size_t q) const {
  const auto c = grid_.cell(point), n = grid_.cell(q);
  for (std::size_t a = 0; a < 3; ++a)
    if (n[a] != c[a]) return static_cast<std::uint8_t>(1u << (2 * a + (n[a] > c[a] ? 1 : 0)));
  return 0;
}

std::int64_t OnlineScheduler::source_for(std::size_t point) const {
  auto usable = [&](std::size_t q) {
    return status_[q] == PointStatus::solved && !(tried_[point] & direction_bit(point, q));
  };
  for (auto q : rule_.candidates(point))
    if (usable(q)) return static_cast<std::int64_t>(q);
  std::int64_t found = -1;
  for_each_neighbour(point, [&](std::size_t q) {
    if (found < 0 && usable(q)) found = static_cast<std::int64_t>(q);
  });
  return found;
}

std::optional<Task> OnlineScheduler::next(const Vec3& position, const Vec3& velocity) {
  if (!start_handed_out_) {
    start_handed_out_ = true;
    busy_[start_] = 1;
    ++in_flight_;
    return Task{start_, -1};
  }
  if (frontier_.empty()) return std::nullopt;
  std::size_t best = 0;
  double best_priority = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < frontier_.size(); ++i) {
    const double pr = priority(frontier_[i], position, velocity);
    // Ties go to the lower point index: the pick does not depend on the frontier's order.
    if (pr < best_priority || (pr == best_priority && frontier_[i] < frontier_[best])) {
      best_priority = pr;
      best = i;
    }
  }
  const std::size_t p = frontier_[best];
  frontier_[best] = frontier_.back();
  frontier_.pop_back();
  ++in_flight_;
  source_[p] = source_for(p);
  return Task{p, source_[p]};
}

void OnlineScheduler::add_neighbours_to_frontier(std::size_t point) {
  for_each_neighbour(point, [&](std::size_t q) {
    if (status_[q] != PointStatus::pending || busy_[q]) return;
    busy_[q] = 1;
    frontier_.push_back(q);
  });
}

bool OnlineScheduler::complete(std::size_t point, PointStatus outcome) {
  if (in_flight_ > 0) --in_flight_;
  if (outcome == PointStatus::failed && point != start_ && source_[point] >= 0) {
    tried_[point] |= direction_bit(point, static_cast<std::size_t>(source_[point]));
    if (source_for(point) >= 0) {
      frontier_.push_back(point);  // still busy: tried again from another neighbour
      return false;
    }
  }
  status_[point] = outcome;
  // A point that failed from every solved neighbour stays a hole: the points beyond it are
  // reached around it.
  if (outcome == PointStatus::solved) add_neighbours_to_frontier(point);
  return true;
}

// ---------------------------------------------------------------------------------------
// Rendering

OnlineQuery render_step(const CellLookup& lookup, Vec3& last, double max_step) noexcept {
  OnlineQuery q;
  q.complete = lookup.complete;
  q.fallback = !lookup.complete;
  Vec3 target = lookup.found ? lookup.force : last;
  if (!target.allFinite()) target = last;
  Vec3 delta = target - last;
  const double n = delta.norm();
  if (n > max_step) {
    delta *= max_step / n;
    q.limited = true;
  }
  last += delta;
  q.force = last;
  return q;
}

// ---------------------------------------------------------------------------------------
// OnlineBuilder

OnlineBuilder::OnlineBuilder(Space space, TransitionFactory factory, unsigned workers, OnlineSettings settings)
    : grid_(space.grid),
      settings_(settings),
      factory_(std::move(factory)),
      space_(std::move(space)),
      scheduler_(space_.grid, space_.start, settings),
      solve_counts_(space_.grid.size(), 0),
      published_(new std::atomic<std::uint8_t>[space_.grid.size()]),
      forces_(space_.grid.size(), Vec3::Zero()) {
  for (std::size_t p = 0; p < grid_.size(); ++p) published_[p].store(0, std::memory_order_relaxed);
  const Vec3 start = space_.grid.point(space_.start);
  for (int a = 0; a < 3; ++a) {
    position_[a].store(start[a], std::memory_order_relaxed);
    velocity_[a].store(0.0, std::memory_order_relaxed);
  }
  last_position_ = start;
  for (unsigned i = 0; i < std::max(1u, workers); ++i) threads_.emplace_back([this, i] { work(i); });
}

OnlineBuilder::~OnlineBuilder() { stop(); }

void OnlineBuilder::stop() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  for (auto& t : threads_)
    if (t.joinable()) t.join();
}

void OnlineBuilder::check() const {
  std::lock_guard lock(mutex_);
  if (error_) std::rethrow_exception(error_);
}

void OnlineBuilder::work(unsigned) {
  try {
    TransitionFn solve = factory_();
    VecX source_displacement;
    for (;;) {
      Task task;
      {
        std::unique_lock lock(mutex_);
        std::optional<Task> next;
        changed_.wait(lock, [&] {
          if (stop_) return true;
          Vec3 position = Vec3::Zero(), velocity = Vec3::Zero();
          for (int a = 0; a < 3; ++a) {
            position[a] = position_[a].load(std::memory_order_relaxed);
            velocity[a] = velocity_[a].load(std::memory_order_relaxed);
          }
          next = scheduler_.next(position, velocity);
          return next.has_value();
        });
        if (!next) return;  // stopped
        task = *next;
        ++solve_counts_[task.point];
        if (task.source >= 0) source_displacement = space_.displacement.col(static_cast<Eigen::Index>(task.source));
      }
      PointResult r = solve(task.point, task.source, source_displacement);
      r.point = task.point;
      if (r.status == PointStatus::solved && !r.force.allFinite()) {
        r.status = PointStatus::failed;
        r.reason = "non-finite reaction force";
        r.force.setZero();
      }
      {
        std::lock_guard lock(mutex_);
        if (!scheduler_.complete(r.point, r.status)) {
          changed_.notify_all();  // tried again from another neighbour: nothing to publish
          continue;
        }
        space_.store(r);
        if (r.status == PointStatus::solved) {
          forces_[r.point] = r.force;
          published_[r.point].store(1, std::memory_order_release);
          solved_count_.fetch_add(1, std::memory_order_release);
        } else {
          published_[r.point].store(2, std::memory_order_release);
        }
      }
      changed_.notify_all();
    }
  } catch (...) {
    {
      std::lock_guard lock(mutex_);
      if (!error_) error_ = std::current_exception();
      stop_ = true;
    }
    changed_.notify_all();
  }
}

void OnlineBuilder::observe(const Vec3& position, double t) noexcept {
  if (!position.allFinite()) return;
  if (observed_ && t > last_time_) {
    const double dt = t - last_time_;
    const Vec3 instant = (position - last_position_) / dt;
    const double alpha = dt / (settings_.velocity_smoothing + dt);
    velocity_estimate_ += alpha * (instant - velocity_estimate_);
  }
  if (!observed_ || t > last_time_) {
    last_position_ = position;
    last_time_ = t;
  }
  observed_ = true;
  for (int a = 0; a < 3; ++a) {
    position_[a].store(position[a], std::memory_order_relaxed);
    velocity_[a].store(velocity_estimate_[a], std::memory_order_relaxed);
  }
}

CellLookup OnlineBuilder::lookup(const Vec3& p) const noexcept {
  return lookup_cell(
      grid_, p, [&](std::size_t q) { return static_cast<int>(published_[q].load(std::memory_order_acquire)); },
      [&](std::size_t q) -> const Vec3& { return forces_[q]; });
}

bool OnlineBuilder::shape(const Vec3& p, VecX& u) const {
  std::lock_guard lock(mutex_);
  u.setZero(space_.displacement.rows());
  double sum_w = 0.0;
  for_each_cell_corner(grid_, p, [&](std::size_t q, double w) {
    if (!space_.solved(q)) return;
    u += w * space_.displacement.col(static_cast<Eigen::Index>(q));
    sum_w += w;
  });
  if (sum_w > 0.0 && sum_w != 1.0) u /= sum_w;
  return sum_w > 0.0;
}

OnlineQuery OnlineBuilder::render(const Vec3& p) noexcept {
  return render_step(lookup(p), last_force_, settings_.max_force_step);
}

std::vector<int> OnlineBuilder::solve_counts() const {
  std::lock_guard lock(mutex_);
  return solve_counts_;
}

Space OnlineBuilder::snapshot() const {
  std::lock_guard lock(mutex_);
  return space_;
}

TransitionFactory solver_transitions(const physics::Body& body, const SpaceSettings& settings, const Grid& grid) {
  return [body, settings, grid]() -> TransitionFn {
    auto solver = std::make_shared<ConfigurationSolver>(body, settings);
    return [solver, grid](std::size_t point, std::int64_t source, const VecX& from) {
      if (source < 0) return solver->solve_start(point, solver->contact_rest());
      return solver->transition(point, source, from, grid.point(static_cast<std::size_t>(source)), grid.point(point));
    };
  };
}

// ---------------------------------------------------------------------------------------
// Tool paths and the speed search

double ToolPath::length() const {
  double sum = 0.0;
  for (std::size_t i = 1; i < waypoints.size(); ++i) sum += (waypoints[i] - waypoints[i - 1]).norm();
  return sum;
}

Vec3 ToolPath::at(double t) const {
  Vec3 out = Vec3::Zero();
  if (waypoints.empty()) return out;
  out = waypoints.back();
  double s = std::max(0.0, t - dwell) * speed;
  for (std::size_t i = 1; i < waypoints.size(); ++i) {
    const Vec3 segment = waypoints[i] - waypoints[i - 1];
    const double l = segment.norm();
    if (s <= l && l > 0.0) {
      out = waypoints[i - 1] + (s / l) * segment;
      break;
    }
    s -= l;
  }
  return out;
}

ToolPath scripted_path(const Grid& grid, std::size_t start) {
  // Off the grid lines, so that every query weighs all 8 corners of its cell.
  const double h = grid.spacing;
  const Vec3 lo = grid.lower() + Vec3::Constant(0.3 * h);
  const Vec3 hi = grid.upper() - Vec3::Constant(0.3 * h);
  auto clamp = [&](Vec3 p) {
    for (int a = 0; a < 3; ++a) p[a] = lo[a] <= hi[a] ? std::clamp(p[a], lo[a], hi[a]) : grid.origin[a];
    return p;
  };
  const Vec3 s = grid.point(start);
  ToolPath path;
  const Vec3 pressed = clamp(s + h * Vec3(0.3, 0.2, -0.6));
  path.waypoints = {s, pressed, clamp(Vec3(hi.x(), pressed.y(), pressed.z())), clamp(Vec3(hi.x(), hi.y(), pressed.z())),
                    clamp(Vec3(lo.x(), hi.y(), pressed.z()))};
  return path;
}

namespace {

void count_query(DriveResult& out, const OnlineQuery& q, const Vec3& before, bool moving) {
  out.finite = out.finite && q.force.allFinite();
  out.max_step = std::max(out.max_step, (q.force - before).norm());
  if (!moving) return;
  ++out.queries;
  out.complete += q.complete;
}

}  // namespace

std::vector<std::size_t> neighbourhood(const Grid& grid, std::size_t point) {
  std::vector<std::size_t> out;
  const auto c = grid.cell(point);
  for (int k = -1; k <= 1; ++k)
    for (int j = -1; j <= 1; ++j)
      for (int i = -1; i <= 1; ++i)
        if (grid.contains(c[0] + i, c[1] + j, c[2] + k)) out.push_back(grid.index(c[0] + i, c[1] + j, c[2] + k));
  return out;
}

DriveResult simulate_online(const Grid& grid, std::size_t start, const ToolPath& path, unsigned workers,
                            const std::function<double(std::size_t)>& cost, OnlineSettings settings, double rate) {
  DriveResult out;
  out.speed = path.speed;
  OnlineScheduler scheduler(grid, start, settings);
  std::vector<std::uint8_t> solved(grid.size(), 0);
  const std::vector<std::size_t> around = neighbourhood(grid, start);
  const double dt = 1.0 / rate;
  double extra = -1.0;  // the dwell's lengthening, once known
  // Path time: held at the start until the neighbourhood is solved.
  auto path_time = [&](double t) { return extra < 0.0 ? std::min(t, path.dwell) : t - extra; };
  auto velocity = [&](double t) -> Vec3 {
    const Vec3 ahead = path.at(path_time(t + 0.5 * dt));
    const Vec3 behind = path.at(path_time(t - 0.5 * dt));
    return (ahead - behind) / dt;
  };
  // (finish time, worker, point): the earliest finish first, ties by worker.
  using Event = std::tuple<double, unsigned, std::size_t>;
  std::priority_queue<Event, std::vector<Event>, std::greater<>> running;
  std::vector<unsigned> idle;
  for (unsigned w = std::max(1u, workers); w-- > 0;) idle.push_back(w);
  auto assign = [&](double t) {
    while (!idle.empty()) {
      const auto task = scheduler.next(path.at(path_time(t)), velocity(t));
      if (!task) return;
      running.emplace(t + cost(task->point), idle.back(), task->point);
      idle.pop_back();
    }
  };
  assign(0.0);
  Vec3 last = Vec3::Zero();
  for (long k = 0;; ++k) {
    const double t = static_cast<double>(k) * dt;
    while (!running.empty() && std::get<0>(running.top()) <= t) {
      const auto [finish, worker, point] = running.top();
      running.pop();
      solved[point] = 1;
      scheduler.complete(point, PointStatus::solved);
      idle.push_back(worker);
      assign(finish);
    }
    if (extra < 0.0 && t >= path.dwell &&
        std::all_of(around.begin(), around.end(), [&](std::size_t q) { return solved[q] != 0; })) {
      extra = t - path.dwell;
      out.wait = t;
    }
    if (extra < 0.0 && running.empty()) break;  // nothing left to solve: cannot start
    const double tau = path_time(t);
    if (tau > path.duration()) break;
    const Vec3 p = path.at(tau);
    const Vec3 before = last;
    const CellLookup c = lookup_cell(
        grid, p, [&](std::size_t q) { return static_cast<int>(solved[q]); },
        [&](std::size_t) { return Vec3::Zero().eval(); });
    // Only completeness matters here; the step bound is checked on real forces by
    // drive_online.
    count_query(out, render_step(c, last, settings.max_force_step), before, extra >= 0.0 && tau >= path.dwell);
  }
  out.solved = static_cast<std::size_t>(std::count(solved.begin(), solved.end(), 1));
  return out;
}

DriveResult drive_online(OnlineBuilder& builder, const ToolPath& path, double max_wait) {
  DriveResult out;
  out.speed = path.speed;
  const std::vector<std::size_t> around = neighbourhood(builder.grid(), builder.grid().nearest(path.at(0.0)));
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  Vec3 last = Vec3::Zero();
  double extra = -1.0;
  for (long k = 0;; ++k) {
    std::this_thread::sleep_until(t0 + std::chrono::milliseconds(k));
    // The tool's position is that of the tick's nominal time: a late tick queries where the
    // tool should be, as a device running behind would.
    const double t = static_cast<double>(k) * 1e-3;
    if (extra < 0.0 && t >= path.dwell &&
        std::all_of(around.begin(), around.end(), [&](std::size_t q) { return builder.resolved(q); })) {
      extra = t - path.dwell;
      out.wait = t;
    }
    if (extra < 0.0 && t > max_wait) break;
    const double tau = extra < 0.0 ? std::min(t, path.dwell) : t - extra;
    if (tau > path.duration()) break;
    const Vec3 p = path.at(tau);
    builder.observe(p, t);
    const OnlineQuery q = builder.render(p);
    count_query(out, q, last, extra >= 0.0 && tau >= path.dwell);
    last = q.force;
  }
  builder.check();
  out.solved = builder.solved_count();
  return out;
}

SpeedSearch search_speed(const std::function<DriveResult(double)>& trial, double first, double criterion,
                         int bisections, double ceiling) {
  SpeedSearch out;
  auto passes = [&](double speed) {
    out.trials.push_back(trial(speed));
    return out.trials.back().fraction() >= criterion;
  };
  double pass = 0.0, fail = 0.0;
  for (double speed = first; speed <= ceiling; speed *= 2.0) {
    if (!passes(speed)) {
      fail = speed;
      break;
    }
    pass = speed;
  }
  // The first speed failed: halve it (at most 4 times) until one passes.
  for (int i = 0; pass == 0.0 && i < 4; ++i) {
    const double speed = 0.5 * fail;
    (passes(speed) ? pass : fail) = speed;
  }
  if (pass > 0.0 && fail > 0.0)
    for (int i = 0; i < bisections; ++i) {
      const double mid = 0.5 * (pass + fail);
      (passes(mid) ? pass : fail) = mid;
    }
  out.max_speed = pass;
  out.bounded = fail > 0.0;
  return out;
}

SpeedSearch online_speed(const physics::Body& body, const SpaceSettings& settings, const OnlineSpeedOptions& o) {
  const Space layout = make_space(body, settings, "");
  const TransitionFactory factory = solver_transitions(body, settings, layout.grid);
  ToolPath path = scripted_path(layout.grid, layout.start);
  path.dwell = o.dwell;
  auto trial = [&](double speed) {
    path.speed = speed;
    OnlineBuilder builder(layout, factory, o.workers, o.settings);
    DriveResult r = drive_online(builder, path);
    builder.stop();
    if (o.on_trial) o.on_trial(r, builder.snapshot());
    return r;
  };
  return search_speed(trial, o.first, o.criterion, o.bisections);
}

}  // namespace tactus::precompute
