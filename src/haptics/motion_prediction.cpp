#include "haptics/motion_prediction.hpp"

#include <Eigen/Dense>
#include <cmath>

#include "core/error.hpp"

namespace tactus::haptics {

MotionPredictor::MotionPredictor(Extrapolation kind, double window) : kind_(kind), window_(window) {
  if (!(window > 0.0 && std::isfinite(window))) throw InputError("motion prediction: the window must be positive");
}

void MotionPredictor::add(double t, const Vec3& position) noexcept {
  if (!std::isfinite(t) || !position.allFinite()) return;
  if (count_ > 0 && !(t > t_[static_cast<std::size_t>((head_ + kMaxSamples - 1) % kMaxSamples)])) return;
  t_[static_cast<std::size_t>(head_)] = t;
  p_[static_cast<std::size_t>(head_)] = position;
  head_ = (head_ + 1) % kMaxSamples;
  if (count_ < kMaxSamples) ++count_;
}

Vec3 MotionPredictor::predict(double horizon) const noexcept {
  if (count_ == 0) return Vec3::Zero();
  const auto at = [&](int back) { return static_cast<std::size_t>((head_ - 1 - back + 2 * kMaxSamples) % kMaxSamples); };
  const double newest = t_[at(0)];
  const Vec3& last = p_[at(0)];
  if (!std::isfinite(horizon)) return last;
  int used = 1;
  while (used < count_ && newest - t_[at(used)] <= window_ * (1.0 + 1e-9)) ++used;
  const int degree = kind_ == Extrapolation::quadratic ? 2 : 1;
  if (used < degree + 1) return last;
  // Least squares in τ = (t − newest)/window, well scaled whatever the window.
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d rhs = Eigen::Matrix3d::Zero();  // columns: x, y, z
  for (int k = 0; k < used; ++k) {
    const double tau = (t_[at(k)] - newest) / window_;
    const Eigen::Vector3d basis(1.0, tau, tau * tau);
    normal += basis * basis.transpose();
    rhs += basis * p_[at(k)].transpose();
  }
  const int n = degree + 1;
  // At most 3 × 3: fixed storage, no heap.
  using Coefficients = Eigen::Matrix<double, Eigen::Dynamic, 3, 0, 3, 3>;
  const Coefficients coefficients = normal.topLeftCorner(n, n).ldlt().solve(rhs.topRows(n));
  const double tau = horizon / window_;
  Vec3 out = coefficients.row(0).transpose() + tau * coefficients.row(1).transpose();
  if (degree == 2) out += tau * tau * coefficients.row(2).transpose();
  return out.allFinite() ? out : last;
}

}  // namespace tactus::haptics
