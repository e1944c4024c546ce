#pragma once
// The angle θ between two edge vectors u = x_a − x_b and w = x_c − x_b meeting at node b,
// with its gradient and Hessian in (u, w). Used by the "torsional" springs of seed 004 §4.2,
// which hold the in-plane angle between two springs at its rest value.
#include <Eigen/Core>

#include "core/math.hpp"

namespace tactus::physics {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

struct AngleDerivatives {
  double theta = 0.0;  ///< in [0, π]
  Vec6 grad = Vec6::Zero();  ///< dθ/d(u, w)
  Mat6 hess = Mat6::Zero();  ///< d²θ/d(u, w)², only when asked for
  bool valid = false;        ///< false when u ∥ w or an edge has zero length (θ not smooth)
};

AngleDerivatives angle_derivatives(const Vec3& u, const Vec3& w, bool with_hessian);

/// Angle between u and w, robust near 0 and π.
double angle_between(const Vec3& u, const Vec3& w);

}  // namespace tactus::physics
