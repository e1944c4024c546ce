#include "physics/mass_spring/angle_term.hpp"

#include <cmath>

namespace tactus::physics {

double angle_between(const Vec3& u, const Vec3& w) { return std::atan2(u.cross(w).norm(), u.dot(w)); }

AngleDerivatives angle_derivatives(const Vec3& u, const Vec3& w, bool with_hessian) {
  AngleDerivatives out;
  const double lu = u.norm(), lw = w.norm();
  out.theta = angle_between(u, w);
  if (!(lu > 0.0 && lw > 0.0)) return out;
  const Vec3 uh = u / lu, wh = w / lw;
  const double c = uh.dot(wh);
  const double s = uh.cross(wh).norm();
  if (s < 1e-9) return out;  // straight or folded: θ = acos(c) has no gradient there
  out.valid = true;
  // c = û·ŵ; dc/du = (ŵ − c û)/|u|, dc/dw = (û − c ŵ)/|w|; θ = acos(c) ⇒ ∇θ = −∇c / s.
  const Vec3 au = (wh - c * uh) / lu, aw = (uh - c * wh) / lw;
  Vec6 a;
  a << au, aw;
  out.grad = -a / s;
  if (!with_hessian) return out;
  // ∇²θ = −∇²c / s − (c / s³) ∇c ∇cᵀ, with the blocks of ∇²c:
  //   uu = −(û a_uᵀ + a_u ûᵀ)/|u| − c (I − ûûᵀ)/|u|²   (and likewise ww)
  //   uw = (I − ûûᵀ − ŵŵᵀ + c û ŵᵀ) / (|u| |w|)
  const Mat3 I = Mat3::Identity();
  Mat6 hc;
  hc.topLeftCorner<3, 3>() = -(uh * au.transpose() + au * uh.transpose()) / lu - c * (I - uh * uh.transpose()) / (lu * lu);
  hc.bottomRightCorner<3, 3>() =
      -(wh * aw.transpose() + aw * wh.transpose()) / lw - c * (I - wh * wh.transpose()) / (lw * lw);
  const Mat3 uw = (I - uh * uh.transpose() - wh * wh.transpose() + c * uh * wh.transpose()) / (lu * lw);
  hc.topRightCorner<3, 3>() = uw;
  hc.bottomLeftCorner<3, 3>() = uw.transpose();
  out.hess = -hc / s - (c / (s * s * s)) * (a * a.transpose());
  return out;
}

}  // namespace tactus::physics
