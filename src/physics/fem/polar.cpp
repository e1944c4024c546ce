#include "physics/fem/polar.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <functional>

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

/// Four doubles, one lane per matrix: the Newton iterations of four decompositions run side by
/// side (a GCC/Clang vector extension, SSE or AVX registers), independent dependency chains
/// instead of one. Each lane's arithmetic is exactly what it would be alone.
constexpr int kLanes = 4;
#if defined(__GNUC__)
using Lanes = double __attribute__((vector_size(8 * kLanes)));
#else
struct Lanes {
  double lane[kLanes];
  double& operator[](int l) { return lane[l]; }
  double operator[](int l) const { return lane[l]; }
};
template <class Op>
inline Lanes lanewise(const Lanes& a, const Lanes& b, Op op) {
  Lanes out;
  for (int l = 0; l < kLanes; ++l) out[l] = op(a[l], b[l]);
  return out;
}
inline Lanes operator+(const Lanes& a, const Lanes& b) { return lanewise(a, b, std::plus<>()); }
inline Lanes operator-(const Lanes& a, const Lanes& b) { return lanewise(a, b, std::minus<>()); }
inline Lanes operator*(const Lanes& a, const Lanes& b) { return lanewise(a, b, std::multiplies<>()); }
inline Lanes operator/(const Lanes& a, const Lanes& b) { return lanewise(a, b, std::divides<>()); }
#endif

/// One Newton step R <- (R + R^-T) / 2 on kLanes column-major 3x3 matrices (r[i] holds entry i
/// of each); writes each lane's det R before the step (out parameters: vectors wider than the
/// target's registers are not passed by value).
inline void newton_step(Lanes* r, Lanes& det) {
  // R^-T = cof(R) / det R; the cofactor columns are cross products of R's columns.
  const Lanes* a = r;
  const Lanes* b = r + 3;
  const Lanes* c = r + 6;
  const Lanes cof[9] = {b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0],
                        c[1] * a[2] - c[2] * a[1], c[2] * a[0] - c[0] * a[2], c[0] * a[1] - c[1] * a[0],
                        a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  det = a[0] * cof[0] + a[1] * cof[1] + a[2] * cof[2];
  Lanes half;
  for (int l = 0; l < kLanes; ++l) half[l] = 0.5;
  const Lanes h = half / det;
  for (int i = 0; i < 9; ++i) r[i] = half * r[i] + h * cof[i];
}

/// Up to kLanes decompositions at once; spare lanes iterate on the identity.
void polar_group(const Mat3* F, Mat3* R, int count) {
  int left[kLanes];  // Newton steps still to take once converging; 0 = done
  Lanes X[9];
  for (int l = 0; l < kLanes; ++l) {
    const double scale = l < count ? F[l].squaredNorm() / 3.0 : 0.0;  // mean squared stretch
    const double det = l < count ? F[l].determinant() : 0.0;
    // The Newton iteration maps each singular value s to (s + 1/s)/2; it is fast and exact
    // when no singular value is tiny. J below 1e-3 of the typical stretch cubed goes to SVD.
    const bool newton = scale > 0.0 && det > 1e-3 * scale * std::sqrt(scale);
    const Mat3 start = newton ? Mat3(F[l] / std::sqrt(scale)) : Mat3::Identity();
    for (int i = 0; i < 9; ++i) X[i][l] = start.data()[i];
    left[l] = newton ? -1 : 0;
    if (!newton && l < count) R[l] = svd_rotation(F[l]);
  }
  for (int it = 0; it <= 31; ++it) {
    Lanes det;
    newton_step(X, det);
    bool done = true;
    for (int l = 0; l < kLanes; ++l) {
      // After the first step every singular value s is at least 1, so det - 1 >= max(s - 1),
      // the distance to the rotation. Below 1e-3 this step leaves ~5e-7 and one more ~1e-13.
      if (left[l] < 0 && it >= 1 && det[l] - 1.0 < 1e-3) {
        left[l] = 1;  // this step and the next
      } else if (left[l] > 0 && --left[l] == 0) {
        for (int i = 0; i < 9; ++i) R[l].data()[i] = X[i][l];
      } else if (left[l] < 0 && it == 30) {
        R[l] = svd_rotation(F[l]);
        left[l] = 0;
      }
      done = done && left[l] == 0;
    }
    if (done) return;
  }
}

}  // namespace

void polar_rotations(std::span<const Mat3> F, std::span<Mat3> R) {
  for (std::size_t i = 0; i < F.size(); i += kLanes)
    polar_group(F.data() + i, R.data() + i, static_cast<int>(std::min<std::size_t>(kLanes, F.size() - i)));
}

Mat3 polar_rotation(const Mat3& F) {
  Mat3 R;
  polar_group(&F, &R, 1);
  return R;
}

}  // namespace tactus::physics
