#include "physics/fem/polar.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace tactus::physics {

namespace {

Mat3 svd_rotation(const Mat3& F) {
  Eigen::JacobiSVD<Mat3> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 U = svd.matrixU();
  const Mat3& V = svd.matrixV();
  // Singular values come sorted descending: flipping the last column moves the reflection
  // onto the smallest stretch, the least energetic way to undo it.
  if (U.determinant() * V.determinant() < 0.0) U.col(2) = -U.col(2);
  return U * V.transpose();
}

/// One Newton step R <- (R + R^-T) / 2 on a column-major 3x3 array; returns max |change|.
inline double newton_step(double* r) {
  // R^-T = cof(R) / det R; the cofactor columns are cross products of R's columns.
  const double* a = r;
  const double* b = r + 3;
  const double* c = r + 6;
  const double cof[9] = {b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0],
                         c[1] * a[2] - c[2] * a[1], c[2] * a[0] - c[0] * a[2], c[0] * a[1] - c[1] * a[0],
                         a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  const double h = 0.5 / (a[0] * cof[0] + a[1] * cof[1] + a[2] * cof[2]);
  double change = 0.0;
  for (int i = 0; i < 9; ++i) {
    const double next = 0.5 * r[i] + h * cof[i];
    change = std::max(change, std::abs(next - r[i]));
    r[i] = next;
  }
  return change;
}

}  // namespace

Mat3 polar_rotation(const Mat3& F) {
  const double scale = F.squaredNorm() / 3.0;  // mean squared stretch
  const double det = F.determinant();
  // The Newton iteration maps each singular value s to (s + 1/s)/2; it is fast and exact
  // when no singular value is tiny. J below 1e-3 of the typical stretch cubed goes to SVD.
  if (!(scale > 0.0) || !(det > 1e-3 * scale * std::sqrt(scale))) return svd_rotation(F);
  Mat3 R = F / std::sqrt(scale);
  for (int it = 0; it < 30; ++it) {
    // Quadratic convergence: the error left is about change^2 / 2. Below 1e-3, one more
    // step leaves ~1e-13, so take it and stop without measuring.
    if (newton_step(R.data()) < 1e-3) {
      newton_step(R.data());
      return R;
    }
  }
  return svd_rotation(F);
}

}  // namespace tactus::physics
