#pragma once
// Constitutive laws as functions of the deformation gradient F: strain energy density psi,
// first Piola-Kirchhoff stress P = d psi / dF and, for the hyperelastic laws, the tangent
// dP/dF. No element or mesh knowledge here.
#include <Eigen/Core>

#include "core/math.hpp"
#include "physics/fem/material.hpp"

namespace tactus::physics {

using Mat9 = Eigen::Matrix<double, 9, 9>;
using Vec9 = Eigen::Matrix<double, 9, 1>;

/// Column-major vec(F): entry (i, j) at i + 3 j.
inline Vec9 vec9(const Mat3& m) { return Eigen::Map<const Vec9>(m.data()); }

/// Small-strain Cauchy stress of strain eps: lambda tr(eps) I + 2 mu eps.
inline Mat3 hooke(double lambda, double mu, const Mat3& eps) {
  Mat3 s = 2.0 * mu * eps;
  s.diagonal().array() += lambda * eps.trace();
  return s;
}

/// Energy density [J/m^3] of any law (corotational: mu |S - I|^2 + lambda/2 tr(S - I)^2
/// with S = R^T F from the polar decomposition).
double strain_energy_density(const LawParams& p, const Mat3& F);
/// First Piola-Kirchhoff stress of any law (corotational: R hooke(S - I)).
Mat3 first_piola_stress(const LawParams& p, const Mat3& F);
/// P and, when A is given, the exact dP/dF (column-major vec on both sides) of the
/// hyperelastic laws (stvk, neo_hookean, mooney_rivlin); A is left untouched for the others.
void hyperelastic_stress_tangent(const LawParams& p, const Mat3& F, Mat3& P, Mat9* A);
/// Replaces A by its nearest positive semi-definite matrix (eigenvalues clamped at zero);
/// a cheap Cholesky test skips the eigen-decomposition when A is already definite.
void project_psd(Mat9& A);

}  // namespace tactus::physics
