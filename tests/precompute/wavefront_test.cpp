#include <gtest/gtest.h>

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

/// Runs the wavefront to the end, taking ready tasks in a random order and failing the points
/// in `fail`; returns each point's source and status.
std::pair<std::vector<std::int64_t>, std::vector<PointStatus>> run(const Grid& g, std::size_t start,
                                                                   const std::vector<std::size_t>& fail,
                                                                   unsigned seed) {
  Wavefront w(g, start, std::vector<PointStatus>(g.size(), PointStatus::pending));
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
    const bool failed = std::find(fail.begin(), fail.end(), t.point) != fail.end();
    w.complete(t.point, failed ? PointStatus::failed : PointStatus::solved);
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
  const std::vector<std::size_t> fail = {g.index(2, 2, 3), g.index(1, 2, 4)};
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
  const auto [source, status] = run(g, 0, {0}, 1);
  EXPECT_EQ(status[0], PointStatus::failed);
  for (std::size_t p = 1; p < g.size(); ++p) EXPECT_EQ(status[p], PointStatus::unreachable);
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
