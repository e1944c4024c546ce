#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <random>

#include "precompute/wavefront.hpp"

namespace tactus::precompute {
namespace {

Grid cube(int n) {
  Grid g;
  g.spacing = 1.0;
  g.counts = {n, n, n};
  return g;
}

/// A transition that fails: to `point` from `source`, or from any source when it is -2.
struct Failure {
  std::size_t point;
  std::int64_t source = -2;
};

/// Runs the wavefront to the end, taking ready tasks in a random order and failing the
/// transitions in `fail`; returns each point's last source and status.
std::pair<std::vector<std::int64_t>, std::vector<PointStatus>> run(const Grid& g, std::size_t start,
                                                                   const std::vector<Failure>& fail, unsigned seed,
                                                                   std::vector<int>* final_outcomes = nullptr) {
  Wavefront w(g, start, std::vector<PointStatus>(g.size(), PointStatus::pending));
  if (final_outcomes) final_outcomes->assign(g.size(), 0);
  std::vector<std::int64_t> source(g.size(), -2);
  std::vector<Task> running;
  std::mt19937 rng(seed);
  while (!w.finished()) {
    while (auto t = w.next()) running.push_back(*t);
    if (running.empty()) break;
    const std::size_t pick = std::uniform_int_distribution<std::size_t>(0, running.size() - 1)(rng);
    const Task t = running[pick];
    running.erase(running.begin() + static_cast<std::ptrdiff_t>(pick));
    source[t.point] = t.source;
    const bool failed = std::any_of(fail.begin(), fail.end(), [&](const Failure& f) {
      return f.point == t.point && (f.source == -2 || f.source == t.source);
    });
    const bool final = w.complete(t.point, failed ? PointStatus::failed : PointStatus::solved);
    if (final_outcomes) (*final_outcomes)[t.point] += final ? 1 : 0;
  }
  return {source, w.status()};
}

TEST(Wavefront, ReachesEveryPointFromANeighbourOneStepCloser) {
  const Grid g = cube(4);
  const std::size_t start = g.index(1, 2, 3);
  const auto [source, status] = run(g, start, {}, 1);
  for (std::size_t p = 0; p < g.size(); ++p) {
    EXPECT_EQ(status[p], PointStatus::solved);
    if (p == start) {
      EXPECT_EQ(source[p], -1);
      continue;
    }
    ASSERT_GE(source[p], 0);
    const auto a = g.cell(p), b = g.cell(static_cast<std::size_t>(source[p])), s = g.cell(start);
    EXPECT_EQ(std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2]), 1);
    auto dist = [&](const std::array<int, 3>& c) {
      return std::abs(c[0] - s[0]) + std::abs(c[1] - s[1]) + std::abs(c[2] - s[2]);
    };
    EXPECT_EQ(dist(b) + 1, dist(a));
  }
}

TEST(Wavefront, SourcesDoNotDependOnCompletionOrder) {
  const Grid g = cube(5);
  const std::size_t start = g.index(2, 2, 4);
  const std::vector<Failure> fail = {{g.index(2, 2, 3)}, {g.index(1, 2, 4)}};
  const auto first = run(g, start, fail, 1);
  for (unsigned seed = 2; seed < 6; ++seed) {
    const auto other = run(g, start, fail, seed);
    EXPECT_EQ(other.first, first.first);
    EXPECT_EQ(other.second, first.second);
  }
  // The point right below the failed one is reached around it, from a solved neighbour.
  const std::size_t below = g.index(2, 2, 2);
  EXPECT_EQ(first.second[below], PointStatus::unreachable);  // its only candidate failed
  EXPECT_EQ(first.second[g.index(3, 2, 3)], PointStatus::solved);
}

TEST(Wavefront, FailedStartMakesEverythingUnreachable) {
  const Grid g = cube(3);
  const auto [source, status] = run(g, 0, {{0}}, 1);
  EXPECT_EQ(status[0], PointStatus::failed);
  for (std::size_t p = 1; p < g.size(); ++p) EXPECT_EQ(status[p], PointStatus::unreachable);
}

TEST(Wavefront, AFailedTransitionIsTriedAgainFromTheNextNeighbour) {
  const Grid g = cube(4);
  const std::size_t start = g.index(0, 0, 0);
  // (2, 1, 0) is reached from (1, 1, 0) first (x has the larger offset), then (2, 0, 0).
  const std::size_t p = g.index(2, 1, 0);
  const std::vector<std::size_t> from = Wavefront(g, start, {}).candidates(p);
  ASSERT_EQ(from.size(), 2u);
  EXPECT_EQ(from[0], g.index(1, 1, 0));
  EXPECT_EQ(from[1], g.index(2, 0, 0));
  const std::vector<Failure> fail = {{p, static_cast<std::int64_t>(from[0])}};
  std::vector<int> finals;
  const auto first = run(g, start, fail, 1, &finals);
  EXPECT_EQ(first.second[p], PointStatus::solved);
  EXPECT_EQ(first.first[p], static_cast<std::int64_t>(from[1]));
  for (std::size_t q = 0; q < g.size(); ++q) {
    EXPECT_EQ(first.second[q], PointStatus::solved) << q;
    EXPECT_EQ(finals[q], 1) << q;  // each point's outcome is final exactly once
  }
  // The same space in any completion order.
  for (unsigned seed = 2; seed < 8; ++seed) {
    const auto other = run(g, start, fail, seed);
    EXPECT_EQ(other.first, first.first);
    EXPECT_EQ(other.second, first.second);
  }
}

TEST(Wavefront, AFailedPointWaitingForItsNextCandidateHasNoTaskOut) {
  const Grid g = cube(3);
  Wavefront w(g, 0, std::vector<PointStatus>(g.size(), PointStatus::pending));
  const std::size_t p = g.index(1, 1, 0), first = g.index(0, 1, 0), second = g.index(1, 0, 0);
  ASSERT_EQ(w.candidates(p), (std::vector<std::size_t>{first, second}));
  std::vector<Task> out;
  auto take_all = [&] {
    while (auto t = w.next()) out.push_back(*t);
  };
  take_all();
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(w.complete(0, PointStatus::solved));
  take_all();
  EXPECT_TRUE(w.complete(first, PointStatus::solved));
  take_all();
  EXPECT_EQ(w.source_of(p), static_cast<std::int64_t>(first));
  // Failed from the first candidate while the second is still being solved: it waits, and an
  // answer for the failed task (a late copy under MPI) matches no task out.
  EXPECT_FALSE(w.complete(p, PointStatus::failed));
  EXPECT_EQ(w.status()[p], PointStatus::pending);
  EXPECT_EQ(w.source_of(p), -2);
  EXPECT_TRUE(w.complete(second, PointStatus::solved));
  EXPECT_EQ(w.source_of(p), static_cast<std::int64_t>(second));
  EXPECT_EQ(w.failed_tries(p), 1);
}

TEST(Wavefront, APointFailsOnlyWhenEveryNeighbourItWasTriedFromFailedIt) {
  const Grid g = cube(3);
  const std::size_t start = g.index(0, 0, 0);
  const std::size_t p = g.index(1, 1, 1);  // three candidates
  std::vector<int> finals;
  const auto [source, status] = run(g, start, {{p}}, 3, &finals);
  EXPECT_EQ(status[p], PointStatus::failed);
  EXPECT_EQ(finals[p], 1);
  Wavefront w(g, start, std::vector<PointStatus>(g.size(), PointStatus::pending));
  int tries = 0;
  while (!w.finished()) {
    const auto t = w.next();
    ASSERT_TRUE(t.has_value());
    if (t->point == p) ++tries;
    w.complete(t->point, t->point == p ? PointStatus::failed : PointStatus::solved);
  }
  EXPECT_EQ(tries, 3);
  EXPECT_EQ(w.failed_tries(p), 3);
  EXPECT_EQ(w.status()[p], PointStatus::failed);
  // The point beyond it along the diagonal is reached around it.
  EXPECT_EQ(w.status()[g.index(2, 2, 2)], PointStatus::solved);
}

TEST(Wavefront, ResumesFromKnownOutcomes) {
  const Grid g = cube(3);
  std::vector<PointStatus> known(g.size(), PointStatus::pending);
  known[0] = PointStatus::solved;
  known[1] = PointStatus::solved;
  Wavefront w(g, 0, known);
  EXPECT_EQ(w.resolved(), 2u);
  std::vector<std::size_t> handed;
  while (auto t = w.next()) {
    handed.push_back(t->point);
    EXPECT_GE(t->source, 0);
  }
  EXPECT_EQ(std::count(handed.begin(), handed.end(), 0u), 0);
  EXPECT_EQ(std::count(handed.begin(), handed.end(), 1u), 0);
  EXPECT_FALSE(handed.empty());
}

}  // namespace
}  // namespace tactus::precompute
