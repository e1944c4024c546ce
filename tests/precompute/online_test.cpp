#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <thread>

#include "precompute/builder.hpp"
#include "precompute/online.hpp"
#include "test_body.hpp"

namespace tactus::precompute {
namespace {

/// A grid of 1 m with nx × ny × nz points, centred on the origin.
Grid unit_grid(int nx, int ny, int nz) {
  Grid g;
  g.origin = -0.5 * Vec3(nx - 1, ny - 1, nz - 1);
  g.spacing = 1.0;
  g.counts = {nx, ny, nz};
  return g;
}

/// A 21 x 5 x 5 grid of 1 m, the start in its middle.
Grid long_grid() { return unit_grid(21, 5, 5); }

TEST(OnlineScheduler, WorksAheadAlongTheMotion) {
  const Grid g = long_grid();
  const std::size_t start = g.index(10, 2, 2);
  OnlineScheduler s(g, start);
  const Vec3 at = g.point(start);
  int ahead = 0, behind = 0;
  for (int i = 0; i < 40; ++i) {
    // Moving along +x at 4 m/s: with 1 s of lookahead the path runs 4 cells ahead.
    const auto task = s.next(at, Vec3(4, 0, 0));
    ASSERT_TRUE(task);
    const auto c = g.cell(task->point);
    ahead = std::max(ahead, c[0] - 10);
    behind = std::max(behind, 10 - c[0]);
    s.complete(task->point, PointStatus::solved);
  }
  EXPECT_GE(ahead, 4);
  EXPECT_LE(behind, 1);
  // Turning round: the next picks run the other way.
  int back = 0;
  for (int i = 0; i < 20; ++i) {
    const auto task = s.next(at, Vec3(-4, 0, 0));
    ASSERT_TRUE(task);
    back = std::max(back, 10 - g.cell(task->point)[0]);
    EXPECT_LE(g.cell(task->point)[0], 11) << "pick " << i << " ran ahead of the reversed motion";
    s.complete(task->point, PointStatus::solved);
  }
  EXPECT_GE(back, 3);
}

TEST(OnlineScheduler, TransitionsStartFromSolvedNeighboursAndNoPointTwice) {
  const Grid g = long_grid();
  const std::size_t start = g.index(10, 2, 2);
  OnlineScheduler s(g, start);
  const Wavefront rule(g, start, std::vector<PointStatus>(g.size(), PointStatus::pending));
  std::vector<int> handed(g.size(), 0);
  std::size_t count = 0;
  // Two tasks in flight at a time, completed in turn, while the tool wanders.
  std::vector<Task> flight;
  for (int step = 0; step < 1000; ++step) {
    const double a = 0.01 * step;
    const Vec3 tool(8 * std::sin(a), 2 * std::cos(3 * a), std::sin(5 * a));
    const Vec3 velocity(8 * std::cos(a), -6 * std::sin(3 * a), 5 * std::cos(5 * a));
    while (flight.size() < 2) {
      const auto t = s.next(tool, velocity);
      if (!t) break;
      ++handed[t->point];
      if (t->point == start) {
        EXPECT_EQ(t->source, -1);
      } else {
        ASSERT_GE(t->source, 0);
        const std::size_t src = static_cast<std::size_t>(t->source);
        EXPECT_EQ(s.status()[src], PointStatus::solved);
        const auto c = g.cell(t->point), d = g.cell(src);
        EXPECT_EQ(std::abs(c[0] - d[0]) + std::abs(c[1] - d[1]) + std::abs(c[2] - d[2]), 1);
        // The wavefront's own choice whenever one of its candidates is solved.
        for (auto q : rule.candidates(t->point))
          if (s.status()[q] == PointStatus::solved) {
            EXPECT_EQ(t->source, static_cast<std::int64_t>(q));
            break;
          }
      }
      flight.push_back(*t);
    }
    if (flight.empty()) break;
    s.complete(flight.front().point, PointStatus::solved);
    flight.erase(flight.begin());
    ++count;
  }
  EXPECT_EQ(count, g.size());
  for (std::size_t p = 0; p < g.size(); ++p) EXPECT_EQ(handed[p], 1) << "point " << p;
}

/// Runs the scheduler one task at a time with the tool at rest at the start; `fails(point,
/// source)` says which transitions fail. Returns the sources each point was handed out with.
std::vector<std::vector<std::int64_t>> run_one_at_a_time(OnlineScheduler& s,
                                                         const std::function<bool(std::size_t, std::int64_t)>& fails) {
  std::vector<std::vector<std::int64_t>> sources(s.grid().size());
  while (const auto t = s.next(Vec3::Zero(), Vec3::Zero())) {
    sources[t->point].push_back(t->source);
    s.complete(t->point, fails(t->point, t->source) ? PointStatus::failed : PointStatus::solved);
  }
  return sources;
}

TEST(OnlineScheduler, AFailedTransitionIsTriedAgainFromAnotherSolvedNeighbour) {
  const Grid g = unit_grid(3, 3, 3);
  const std::size_t start = g.index(1, 1, 1);
  const std::size_t p = g.index(2, 2, 1);
  OnlineScheduler s(g, start);
  std::int64_t first = -2;
  const auto sources = run_one_at_a_time(s, [&](std::size_t point, std::int64_t source) {
    if (point != p) return false;
    if (first == -2) first = source;
    return source == first;  // only the first path fails
  });
  ASSERT_EQ(sources[p].size(), 2u);
  EXPECT_NE(sources[p][1], sources[p][0]);
  EXPECT_EQ(s.status()[sources[p][1]], PointStatus::solved);
  EXPECT_EQ(s.status()[p], PointStatus::solved);
  for (std::size_t q = 0; q < g.size(); ++q) EXPECT_EQ(s.status()[q], PointStatus::solved) << q;
  EXPECT_EQ(s.in_flight(), 0u);
}

TEST(OnlineScheduler, APointFailingFromEveryNeighbourStaysAHole) {
  const Grid g = unit_grid(3, 3, 3);
  const std::size_t start = g.index(1, 1, 1);
  const std::size_t p = g.index(2, 1, 1);  // beside the start: every other point is solved first or after
  OnlineScheduler s(g, start);
  const auto sources = run_one_at_a_time(s, [&](std::size_t point, std::int64_t) { return point == p; });
  EXPECT_EQ(s.status()[p], PointStatus::failed);
  // Tried once from each neighbour solved while it was being tried, never twice from one.
  ASSERT_GE(sources[p].size(), 1u);
  std::vector<std::int64_t> distinct = sources[p];
  std::sort(distinct.begin(), distinct.end());
  EXPECT_EQ(std::unique(distinct.begin(), distinct.end()), distinct.end());
  for (std::int64_t q : sources[p]) EXPECT_EQ(s.status()[static_cast<std::size_t>(q)], PointStatus::solved);
  for (std::size_t q = 0; q < g.size(); ++q) {
    if (q == p) continue;
    EXPECT_EQ(s.status()[q], PointStatus::solved) << q;
  }
}

TEST(OnlineRender, FallsBackWithABoundedStepAndNeverNaN) {
  Vec3 last = Vec3::Zero();
  CellLookup none;  // nothing solved near the tool: hold the last force
  OnlineQuery q = render_step(none, last, 0.1);
  EXPECT_FALSE(q.complete);
  EXPECT_TRUE(q.fallback);
  EXPECT_EQ(q.force, Vec3::Zero());
  CellLookup partial;  // the nearest solved corner, reached in steps of at most 0.1 N
  partial.found = true;
  partial.force = Vec3(0.25, 0, 0);
  q = render_step(partial, last, 0.1);
  EXPECT_TRUE(q.limited);
  EXPECT_NEAR(q.force.x(), 0.1, 1e-15);
  q = render_step(partial, last, 0.1);
  q = render_step(partial, last, 0.1);
  EXPECT_EQ(q.force, Vec3(0.25, 0, 0));
  EXPECT_FALSE(q.limited);
  CellLookup bad;
  bad.found = bad.complete = true;
  bad.force = Vec3(std::nan(""), 0, 0);
  q = render_step(bad, last, 0.1);
  EXPECT_TRUE(q.force.allFinite());
  EXPECT_EQ(q.force, Vec3(0.25, 0, 0));
}

TEST(OnlineRender, LookupIsCompleteOnlyWhenEveryWeightedCornerIsSolved) {
  const Grid g = long_grid();
  std::vector<std::uint8_t> solved(g.size(), 0);
  auto force = [&](std::size_t q) { return Vec3(static_cast<double>(q), 1.0, 2.0); };
  auto is_solved = [&](std::size_t q) { return static_cast<int>(solved[q]); };
  const std::size_t p = g.index(3, 1, 1);
  solved[p] = 1;
  // At a grid point only that point weighs: its value exactly.
  CellLookup c = lookup_cell(g, g.point(p), is_solved, force);
  EXPECT_TRUE(c.complete);
  EXPECT_EQ(c.force, force(p));
  // Inside the cell the other corners are missing: not complete, the nearest solved corner.
  c = lookup_cell(g, g.point(p) + Vec3(0.2, 0.1, 0.3), is_solved, force);
  EXPECT_FALSE(c.complete);
  EXPECT_TRUE(c.found);
  EXPECT_EQ(c.force, force(p));
  for (int k = 1; k <= 2; ++k)
    for (int j = 1; j <= 2; ++j)
      for (int i = 3; i <= 4; ++i) solved[g.index(i, j, k)] = 1;
  c = lookup_cell(g, g.point(p) + Vec3(0.5, 0.5, 0.5), is_solved, force);
  EXPECT_TRUE(c.complete);
  // Trilinear of a function linear in the index: its value at the centre.
  EXPECT_NEAR(c.force.x(), (static_cast<double>(p) + static_cast<double>(g.index(4, 2, 2))) / 2, 1e-9);
  // A failed corner is resolved: the cell is as complete as it will get, and the solved
  // corners share its weight, as Interpolator does on the finished space.
  solved[g.index(4, 2, 2)] = 2;
  c = lookup_cell(g, g.point(p) + Vec3(0.5, 0.5, 0.5), is_solved, force);
  EXPECT_TRUE(c.complete);
  double expected = 0.0;
  for (int k = 1; k <= 2; ++k)
    for (int j = 1; j <= 2; ++j)
      for (int i = 3; i <= 4; ++i)
        if (g.index(i, j, k) != g.index(4, 2, 2)) expected += static_cast<double>(g.index(i, j, k)) / 7.0;
  EXPECT_NEAR(c.force.x(), expected, 1e-9);
}

TEST(OnlineSimulation, KeepsUpAtLowSpeedNotAtHighAndIsDeterministic) {
  const Grid g = long_grid();
  const std::size_t start = g.index(10, 2, 2);
  ToolPath path;
  path.waypoints = {g.point(start), g.point(start) + Vec3(0.3, 0.2, -0.4), Vec3(9.5, -0.8, -0.4)};
  path.dwell = 0.2;
  auto cost = [](std::size_t) { return 0.05; };  // 20 solves per second per worker
  auto at = [&](double speed, unsigned workers, OnlineSettings settings = {}) {
    path.speed = speed;
    return simulate_online(g, start, path, workers, cost, settings);
  };
  // Crossing a cell of 1 m along x needs 4 new points: 2 workers keep up near 10 m/s.
  EXPECT_GE(at(1.0, 2).fraction(), 0.99);
  EXPECT_LT(at(40.0, 2).fraction(), 0.9);
  const DriveResult a = at(6.0, 2), b = at(6.0, 2);
  EXPECT_EQ(a.complete, b.complete);
  EXPECT_EQ(a.solved, b.solved);
  // More workers sustain a higher speed.
  auto search = [&](unsigned workers, OnlineSettings settings = {}) {
    return search_speed([&](double v) { return at(v, workers, settings); }, 0.5, 0.99, 4, 1000.0).max_speed;
  };
  const double two = search(2), eight = search(8);
  EXPECT_GT(two, 0.0);
  EXPECT_GT(eight, 2.0 * two);
  // Working ahead along the motion beats solving around the present position only.
  OnlineSettings here;
  here.lookahead = 0.0;
  const double two_here = search(2, here), eight_here = search(8, here);
  EXPECT_GE(two, two_here) << two << " " << two_here;
  EXPECT_GT(eight, eight_here) << eight << " " << eight_here;
}

TEST(OnlineSearch, FindsTheLargestPassingSpeed) {
  auto trial = [](double v) {
    DriveResult r;
    r.speed = v;
    r.queries = 100;
    r.complete = v <= 0.0123 ? 100 : 50;
    return r;
  };
  const SpeedSearch s = search_speed(trial, 0.001, 0.99, 5);
  EXPECT_LE(s.max_speed, 0.0123);
  EXPECT_GT(s.max_speed, 0.0123 * (1 - 1.0 / 32));
  EXPECT_EQ(s.trials.size(), 5u + 5u);  // 1, 2, 4, 8 mm/s pass, 16 fails, 5 bisections
  EXPECT_TRUE(s.bounded);
  // Nothing fails below the ceiling: a speed that passed, not a maximum.
  const SpeedSearch unbounded = search_speed(trial, 0.001, 0.99, 5, 0.01);
  EXPECT_FALSE(unbounded.bounded);
  EXPECT_EQ(unbounded.max_speed, 0.008);
  // Starting too fast: 40 and 20 mm/s fail, 10 passes, then bisections between 10 and 20.
  const SpeedSearch down = search_speed(trial, 0.04, 0.99, 5);
  EXPECT_LE(down.max_speed, 0.0123);
  EXPECT_GT(down.max_speed, 0.0123 - 0.01 / 32);
  EXPECT_EQ(down.trials.size(), 3u + 5u);
  EXPECT_EQ(search_speed(trial, 1.0, 0.99, 5).max_speed, 0.0);  // 1 m/s down to 62.5 mm/s: none passes
}

TEST(OnlineBuilder, FakeSolverEveryPointOnceExactValues) {
  Grid g;
  g.origin = Vec3::Zero();
  g.spacing = 0.01;
  g.counts = {5, 4, 3};
  Space space;
  space.grid = g;
  space.start = g.index(2, 1, 1);
  space.allocate(2);
  auto value = [&](std::size_t p) { return Vec3(1.0 + static_cast<double>(p), -0.5, 0.25); };
  TransitionFactory factory = [&]() -> TransitionFn {
    return [&](std::size_t point, std::int64_t source, const VecX& from) {
      std::this_thread::sleep_for(std::chrono::microseconds(300));  // a fixed cost
      PointResult r;
      r.point = point;
      r.source = source;
      r.status = PointStatus::solved;
      r.force = value(point);
      r.displacement = VecX::Constant(6, static_cast<double>(point));
      if (source >= 0) {
        EXPECT_EQ(from[0], static_cast<double>(source));  // the source's displacement
      }
      return r;
    };
  };
  OnlineBuilder builder(space, factory, 3);
  const auto t0 = std::chrono::steady_clock::now();
  while (builder.solved_count() < g.size() && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(20)) {
    builder.observe(g.point(space.start), 0.0);
    const OnlineQuery q = builder.render(g.point(space.start) + Vec3(0.004, 0.003, 0.002));
    EXPECT_TRUE(q.force.allFinite());
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  builder.stop();
  builder.check();
  ASSERT_EQ(builder.solved_count(), g.size());
  for (int n : builder.solve_counts()) EXPECT_EQ(n, 1);
  for (std::size_t p = 0; p < g.size(); ++p) {
    const CellLookup c = builder.lookup(g.point(p));
    EXPECT_TRUE(c.complete);
    EXPECT_EQ(c.force, value(p)) << "point " << p;
  }
  const Space s = builder.snapshot();
  EXPECT_EQ(s.count(PointStatus::solved), g.size());
}

TEST(OnlineBuilder, RealSolvesMatchTheOfflineSpace) {
  const physics::Body body = testing::block_body();
  const SpaceSettings s = testing::block_settings(body);
  Space offline = make_space(body, s, "");
  BuildOptions o;
  build_local(offline, [&] { return std::make_unique<ConfigurationSolver>(body, s); }, o);

  const Space empty = make_space(body, s, "");
  OnlineBuilder builder(empty, solver_transitions(body, s, empty.grid), 2);
  // The tool sweeps along x while the space fills in.
  const auto t0 = std::chrono::steady_clock::now();
  double t = 0.0;
  double max_step = 0.0;
  Vec3 last = Vec3::Zero();
  while (builder.solved_count() < empty.grid.size() &&
         std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60)) {
    const Vec3 p = empty.grid.point(empty.start) + Vec3(0.002 * std::sin(5 * t), 0.0005, -0.002);
    builder.observe(p, t);
    const OnlineQuery q = builder.render(p);
    ASSERT_TRUE(q.force.allFinite());
    max_step = std::max(max_step, (q.force - last).norm());
    last = q.force;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    t += 1e-3;
  }
  builder.stop();
  builder.check();
  EXPECT_LE(max_step, OnlineSettings{}.max_force_step + 1e-12);
  ASSERT_EQ(builder.solved_count(), empty.grid.size());
  for (int n : builder.solve_counts()) EXPECT_EQ(n, 1);
  const Space online = builder.snapshot();
  // Reached along the offline path all the way from the start.
  std::function<bool(std::size_t)> same_chain = [&](std::size_t p) {
    return online.source[p] == offline.source[p] &&
           (online.source[p] < 0 || same_chain(static_cast<std::size_t>(online.source[p])));
  };
  std::size_t same = 0;
  for (std::size_t p = 0; p < offline.grid.size(); ++p) {
    ASSERT_EQ(offline.status[p], PointStatus::solved);
    // A query at a grid point returns that point's configuration; reached along another
    // path it is the same equilibrium to the solver's tolerance, and the same bits when the
    // path is the same.
    const CellLookup c = builder.lookup(offline.grid.point(p));
    ASSERT_TRUE(c.complete);
    EXPECT_LT((c.force - offline.force[p]).norm(), 1e-6 * std::max(1e-3, offline.force[p].norm())) << "point " << p;
    if (same_chain(p)) {
      ++same;
      EXPECT_EQ(c.force, offline.force[p]) << "point " << p;
    }
  }
  EXPECT_GE(same, 1u);
}

}  // namespace
}  // namespace tactus::precompute
