// The time-left estimate of a build: the cost of the pending points from the solved ones'
// cost against their distance from the start, at the build's measured throughput.
#include "precompute/time_left.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace tactus::precompute {
namespace {

Grid line_grid(int points) {
  Grid g;
  g.spacing = 0.001;
  g.counts = {points, 1, 1};
  return g;
}

PointResult solved(std::size_t point, double seconds) {
  PointResult r;
  r.point = point;
  r.status = PointStatus::solved;
  r.seconds = seconds;
  return r;
}

TEST(TimeLeft, UnknownUntilTwoSolves) {
  const Grid g = line_grid(4);
  TimeLeftEstimate e(g, 0);
  std::vector<PointStatus> status(4, PointStatus::pending);
  EXPECT_LT(e.seconds_left(status, 1.0), 0.0);
  e.record(solved(0, 1.0));
  status[0] = PointStatus::solved;
  EXPECT_LT(e.seconds_left(status, 1.0), 0.0);
}

TEST(TimeLeft, PendingPointsCostWhatTheirDistanceFromTheStartPredicts) {
  // Cost 1 + 0.5 d seconds at d spacings from the start; points 0-4 solved on two fully busy
  // workers (elapsed = half their solver time), 5-9 pending.
  const Grid g = line_grid(10);
  TimeLeftEstimate e(g, 0);
  std::vector<PointStatus> status(10, PointStatus::pending);
  double solver = 0.0;
  for (std::size_t p = 0; p < 5; ++p) {
    const double c = 1.0 + 0.5 * static_cast<double>(p);
    e.record(solved(p, c));
    status[p] = PointStatus::solved;
    solver += c;
  }
  EXPECT_NEAR(e.cost_at(7.0), 4.5, 1e-12);
  double pending = 0.0;
  for (int d = 5; d < 10; ++d) pending += 1.0 + 0.5 * d;
  EXPECT_NEAR(e.pending_cost(status), pending, 1e-9);
  EXPECT_NEAR(e.seconds_left(status, solver / 2.0), pending / 2.0, 1e-9);
  // The mean rate of the first points (5 points in solver/2 s) promises an earlier end.
  const double by_mean_rate = 5.0 / (5.0 / (solver / 2.0));
  EXPECT_LT(by_mean_rate, e.seconds_left(status, solver / 2.0));
}

TEST(TimeLeft, UnreachableAndResumedPointsAreNoSolves) {
  const Grid g = line_grid(3);
  TimeLeftEstimate e(g, 1);
  PointResult u;
  u.point = 0;
  u.status = PointStatus::unreachable;
  e.record(u);
  e.record(solved(1, 2.0));
  e.record(solved(2, 2.0));
  const std::vector<PointStatus> status = {PointStatus::pending, PointStatus::solved, PointStatus::solved};
  // Both solves lie one spacing or none from the start, at equal cost: a pending point costs 2 s.
  EXPECT_NEAR(e.pending_cost(status), 2.0, 1e-9);
}

}  // namespace
}  // namespace tactus::precompute
