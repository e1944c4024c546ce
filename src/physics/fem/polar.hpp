#pragma once
// Rotation part of a deformation gradient.
#include "core/math.hpp"

namespace tactus::physics {

/// The proper rotation R of the polar decomposition F = R S. For det F clearly positive,
/// Higham's Newton iteration R <- (R + R^-T) / 2 (quadratic convergence, a few iterations at
/// moderate strain); for nearly degenerate or inverted F, the SVD F = U Sigma V^T with the
/// sign of the smallest singular value flipped when det(U V^T) < 0, so R = U V^T is a
/// rotation (Irving et al. 2004) and S = R^T F carries the inversion as a negative stretch.
Mat3 polar_rotation(const Mat3& F);

}  // namespace tactus::physics
