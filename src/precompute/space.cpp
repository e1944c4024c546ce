#include "precompute/space.hpp"

#include <algorithm>

namespace tactus::precompute {

const char* to_string(PointStatus s) {
  switch (s) {
    case PointStatus::pending: return "pending";
    case PointStatus::solved: return "solved";
    case PointStatus::failed: return "failed";
    case PointStatus::unreachable: return "unreachable";
  }
  return "?";
}

void Space::allocate(std::size_t node_count) {
  const std::size_t n = grid.size();
  status.assign(n, PointStatus::pending);
  force.assign(n, Vec3::Zero());
  source.assign(n, -1);
  iterations.assign(n, 0);
  residual.assign(n, 0.0);
  seconds.assign(n, 0.0);
  reason.assign(n, std::string());
  displacement = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(3 * node_count), static_cast<Eigen::Index>(n));
  force_gradient.assign(n, Mat3::Zero());
  displacement_gradient =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(3 * node_count), static_cast<Eigen::Index>(3 * n));
}

void Space::store(const PointResult& r) {
  status[r.point] = r.status;
  force[r.point] = r.force;
  source[r.point] = r.source;
  iterations[r.point] = r.iterations;
  residual[r.point] = r.residual;
  seconds[r.point] = r.seconds;
  reason[r.point] = r.reason;
  const auto p = static_cast<Eigen::Index>(r.point);
  if (r.status == PointStatus::solved && r.displacement.size() == displacement.rows())
    displacement.col(p) = r.displacement;
  else
    displacement.col(p).setZero();
  const bool with_gradient = r.status == PointStatus::solved && r.displacement_gradient.rows() == displacement.rows() &&
                             r.displacement_gradient.cols() == 3;
  force_gradient[r.point] = with_gradient ? r.force_gradient : Mat3::Zero();
  if (with_gradient)
    displacement_gradient.middleCols<3>(3 * p) = r.displacement_gradient;
  else
    displacement_gradient.middleCols<3>(3 * p).setZero();
}

std::size_t Space::count(PointStatus s) const {
  return static_cast<std::size_t>(std::count(status.begin(), status.end(), s));
}

}  // namespace tactus::precompute
