#include "precompute/time_left.hpp"

#include <algorithm>
#include <cmath>

namespace tactus::precompute {

TimeLeftEstimate::TimeLeftEstimate(const Grid& grid, std::size_t start) : grid_(grid), start_(grid.cell(start)) {}

double TimeLeftEstimate::distance(std::size_t point) const {
  const std::array<int, 3> c = grid_.cell(point);
  double d2 = 0.0;
  for (std::size_t a = 0; a < 3; ++a) d2 += static_cast<double>((c[a] - start_[a]) * (c[a] - start_[a]));
  return std::sqrt(d2);
}

void TimeLeftEstimate::record(const PointResult& r) {
  if (r.status != PointStatus::solved && r.status != PointStatus::failed) return;
  if (!(r.seconds >= 0.0) || !std::isfinite(r.seconds) || r.point >= grid_.size()) return;
  const double d = distance(r.point);
  count_ += 1.0;
  sum_d_ += d;
  sum_dd_ += d * d;
  sum_c_ += r.seconds;
  sum_dc_ += d * r.seconds;
}

double TimeLeftEstimate::cost_at(double d) const {
  if (count_ < 1.0) return 0.0;
  const double mean = sum_c_ / count_;
  const double spread = count_ * sum_dd_ - sum_d_ * sum_d_;
  // Least squares c = a + b·d; one distance only (or one point): the mean.
  const double slope = spread > 1e-12 * std::max(1.0, count_ * sum_dd_) ? (count_ * sum_dc_ - sum_d_ * sum_c_) / spread : 0.0;
  const double intercept = (sum_c_ - slope * sum_d_) / count_;
  // A line fitted to few points may dip below zero far out: no point costs less than a
  // tenth of the mean.
  return std::max(intercept + slope * d, 0.1 * mean);
}

double TimeLeftEstimate::pending_cost(std::span<const PointStatus> status) const {
  if (count_ < 2.0) return -1.0;
  double total = 0.0;
  for (std::size_t p = 0; p < status.size() && p < grid_.size(); ++p)
    if (status[p] == PointStatus::pending) total += cost_at(distance(p));
  return total;
}

double TimeLeftEstimate::seconds_left(std::span<const PointStatus> status, double elapsed) const {
  const double pending = pending_cost(status);
  if (pending < 0.0 || !(elapsed > 0.0) || !(sum_c_ > 0.0)) return -1.0;
  // Solver seconds per wall second so far: the workers times their efficiency.
  return pending * elapsed / sum_c_;
}

}  // namespace tactus::precompute
