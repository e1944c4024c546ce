#pragma once
// How long a build has left, from what its solved points cost. Points farther from the start
// point press the tissue further and take more Newton iterations, so a build's first points
// are its cheapest and their mean rate promises too early an end (3 min 53 s predicted at 8
// of 72 points of the liver's space, which took 6 min 20 s). The cost of a point is fitted as
// a straight line in its distance from the start, summed over the points still pending, and
// turned into wall time by the build's own throughput so far (solver seconds per wall second).
#include <array>
#include <cstddef>
#include <span>

#include "precompute/grid.hpp"
#include "precompute/space.hpp"

namespace tactus::precompute {

class TimeLeftEstimate {
 public:
  TimeLeftEstimate(const Grid& grid, std::size_t start);

  /// A solve that ran (solved or failed, `seconds` of its worker's wall time); others are
  /// ignored.
  void record(const PointResult& result);

  /// Solver seconds the pending points of `status` are expected to take; negative until two
  /// solves are recorded.
  [[nodiscard]] double pending_cost(std::span<const PointStatus> status) const;

  /// Wall seconds left after `elapsed` wall seconds of this build; negative when unknown.
  [[nodiscard]] double seconds_left(std::span<const PointStatus> status, double elapsed) const;

  /// The fitted cost of a point at `distance` grid spacings from the start [s].
  [[nodiscard]] double cost_at(double distance) const;

 private:
  [[nodiscard]] double distance(std::size_t point) const;

  Grid grid_;
  std::array<int, 3> start_{};
  double count_ = 0.0, sum_d_ = 0.0, sum_dd_ = 0.0, sum_c_ = 0.0, sum_dc_ = 0.0;
};

}  // namespace tactus::precompute
