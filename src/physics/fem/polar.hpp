#pragma once
// Rotation part of a deformation gradient.
#include <span>

#include "core/math.hpp"

namespace tactus::physics {

/// The proper rotation R of the polar decomposition F = R S. For det F clearly positive,
/// Higham's Newton iteration R <- (R + R^-T) / 2 (quadratic convergence, a few iterations at
/// moderate strain); for nearly degenerate or inverted F, the SVD F = U Sigma V^T with the
/// sign of the smallest singular value flipped when det(U V^T) < 0, so R = U V^T is a
/// rotation (Irving et al. 2004) and S = R^T F carries the inversion as a negative stretch.
Mat3 polar_rotation(const Mat3& F);
/// R[i] = polar_rotation(F[i]) for each i (R as long as F), several side by side: about twice
/// as fast as one after the other, and each result exactly polar_rotation's.
void polar_rotations(std::span<const Mat3> F, std::span<Mat3> R);

}  // namespace tactus::physics
