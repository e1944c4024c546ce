#include "physics/fem/constitutive.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "physics/fem/polar.hpp"

namespace tactus::physics {

namespace {

/// A scalar function of J with its first two derivatives.
struct JFunction {
  double v = 0.0, d1 = 0.0, d2 = 0.0;
};

/// Below j_min, continue f by its second-order Taylor expansion at j_min: C2, defined for
/// J <= 0 (inverted elements), and for the laws here still pushing J back up.
template <class Fn>
JFunction extend_below(Fn f, double J, double j_min) {
  if (J >= j_min) return f(J);
  const JFunction a = f(j_min);
  const double t = J - j_min;
  return {a.v + a.d1 * t + 0.5 * a.d2 * t * t, a.d1 + a.d2 * t, a.d2};
}

/// psi as a function of the invariants (I1 = tr C, I2 = (I1^2 - tr C^2)/2, J = det F), with
/// its gradient and Hessian in those variables.
struct InvariantEnergy {
  double psi = 0.0;
  Vec3 d = Vec3::Zero();
  Mat3 h = Mat3::Zero();
};

InvariantEnergy invariant_energy(const LawParams& p, double I1, double I2, double J) {
  InvariantEnergy e;
  switch (p.law) {
    case FemLaw::stvk: {
      // psi = lambda/2 tr(E)^2 + mu tr(E^2), E = (C - I)/2, rewritten in I1, I2.
      e.psi = p.lambda / 8.0 * (I1 - 3.0) * (I1 - 3.0) + p.mu / 4.0 * (I1 * I1 - 2.0 * I2 - 2.0 * I1 + 3.0);
      e.d[0] = p.lambda / 4.0 * (I1 - 3.0) + p.mu / 2.0 * (I1 - 1.0);
      e.d[1] = -p.mu / 2.0;
      e.h(0, 0) = p.lambda / 4.0 + p.mu / 2.0;
      break;
    }
    case FemLaw::neo_hookean: {
      // psi = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2 (compressible; Bonet & Wood).
      const double mu = p.mu, la = p.lambda;
      const JFunction c = extend_below(
          [&](double j) {
            const double l = std::log(j);
            return JFunction{-mu * l + 0.5 * la * l * l, (-mu + la * l) / j, (mu + la - la * l) / (j * j)};
          },
          J, p.j_min);
      e.psi = 0.5 * mu * (I1 - 3.0) + c.v;
      e.d = Vec3(0.5 * mu, 0.0, c.d1);
      e.h(2, 2) = c.d2;
      break;
    }
    case FemLaw::mooney_rivlin: {
      // psi = C10 (J^-2/3 I1 - 3) + C01 (J^-4/3 I2 - 3) + kappa/2 (J - 1)^2.
      const JFunction a = extend_below(
          [&](double j) {
            const double q = std::cbrt(j);  // J^(1/3)
            const double m2 = 1.0 / (q * q);
            return JFunction{p.c10 * m2, -2.0 / 3.0 * p.c10 * m2 / j, 10.0 / 9.0 * p.c10 * m2 / (j * j)};
          },
          J, p.j_min);
      const JFunction b = extend_below(
          [&](double j) {
            const double q = std::cbrt(j);
            const double m4 = 1.0 / (q * q * q * q);
            return JFunction{p.c01 * m4, -4.0 / 3.0 * p.c01 * m4 / j, 28.0 / 9.0 * p.c01 * m4 / (j * j)};
          },
          J, p.j_min);
      e.psi = a.v * I1 + b.v * I2 - 3.0 * (p.c10 + p.c01) + 0.5 * p.kappa * (J - 1.0) * (J - 1.0);
      e.d = Vec3(a.v, b.v, a.d1 * I1 + b.d1 * I2 + p.kappa * (J - 1.0));
      e.h(0, 2) = e.h(2, 0) = a.d1;
      e.h(1, 2) = e.h(2, 1) = b.d1;
      e.h(2, 2) = a.d2 * I1 + b.d2 * I2 + p.kappa;
      break;
    }
    default: break;
  }
  return e;
}

/// cof(F) = dJ/dF: columns f1 x f2, f2 x f0, f0 x f1.
Mat3 cofactor(const Mat3& F) {
  Mat3 c;
  c.col(0) = F.col(1).cross(F.col(2));
  c.col(1) = F.col(2).cross(F.col(0));
  c.col(2) = F.col(0).cross(F.col(1));
  return c;
}

Mat3 skew(const Vec3& v) {
  Mat3 m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Mat3 corotated_strain(const Mat3& F, Mat3* R_out) {
  const Mat3 R = polar_rotation(F);
  if (R_out) *R_out = R;
  const Mat3 S = R.transpose() * F;
  return 0.5 * (S + S.transpose()) - Mat3::Identity();
}

}  // namespace

double strain_energy_density(const LawParams& p, const Mat3& F) {
  switch (p.law) {
    case FemLaw::linear:
    case FemLaw::corotational: {
      const Mat3 eps = p.law == FemLaw::linear ? Mat3(0.5 * (F + F.transpose()) - Mat3::Identity())
                                               : corotated_strain(F, nullptr);
      const double tr = eps.trace();
      return p.mu * eps.squaredNorm() + 0.5 * p.lambda * tr * tr;
    }
    default: {
      const Mat3 C = F.transpose() * F;
      const double I1 = C.trace();
      return invariant_energy(p, I1, 0.5 * (I1 * I1 - C.squaredNorm()), F.determinant()).psi;
    }
  }
}

Mat3 first_piola_stress(const LawParams& p, const Mat3& F) {
  switch (p.law) {
    case FemLaw::linear: return hooke(p.lambda, p.mu, 0.5 * (F + F.transpose()) - Mat3::Identity());
    case FemLaw::corotational: {
      Mat3 R;
      const Mat3 eps = corotated_strain(F, &R);
      return R * hooke(p.lambda, p.mu, eps);
    }
    default: {
      Mat3 P;
      hyperelastic_stress_tangent(p, F, P, nullptr);
      return P;
    }
  }
}

void hyperelastic_stress_tangent(const LawParams& p, const Mat3& F, Mat3& P, Mat9* A_out) {
  if (p.law == FemLaw::linear || p.law == FemLaw::corotational) {
    P = first_piola_stress(p, F);
    return;
  }
  if (p.law == FemLaw::stvk) {
    // P = F·S with S = λ tr(E) I + 2μ E, E = (FᵀF − I)/2, and dE = sym(Fᵀ dF), so entry by entry
    //   dP_ij/dF_kl = δ_ik S_lj + λ F_ij F_kl + μ F_il F_kj + μ (F Fᵀ)_ik δ_lj,
    // the same tangent as the invariant route below at a fraction of its cost.
    const Mat3 E = 0.5 * (F.transpose() * F - Mat3::Identity());
    Mat3 S = (2.0 * p.mu) * E;
    S.diagonal().array() += p.lambda * E.trace();
    P = F * S;
    if (!A_out) return;
    Mat9& A = *A_out;
    const Mat3 FFt = F * F.transpose();
    for (int l = 0; l < 3; ++l)
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
          for (int i = 0; i < 3; ++i) {
            double v = p.lambda * F(i, j) * F(k, l) + p.mu * F(i, l) * F(k, j);
            if (i == k) v += S(l, j);
            if (l == j) v += p.mu * FFt(i, k);
            A(i + 3 * j, k + 3 * l) = v;
          }
    return;
  }
  // P = sum_a psi_a dI_a/dF and dP/dF = sum_a psi_a d2I_a/dF2 + sum_ab psi_ab g_a g_b^T.
  const Mat3 C = F.transpose() * F;
  const double I1 = C.trace();
  const double I2 = 0.5 * (I1 * I1 - C.squaredNorm());
  const double J = F.determinant();
  const InvariantEnergy e = invariant_energy(p, I1, I2, J);
  const Mat3 g1 = 2.0 * F;
  const Mat3 g2 = 2.0 * (I1 * F - F * C);
  const Mat3 gJ = cofactor(F);
  P = e.d[0] * g1 + e.d[1] * g2 + e.d[2] * gJ;
  if (!A_out) return;
  Mat9& A = *A_out;

  Eigen::Matrix<double, 9, 3> G;
  G.col(0) = vec9(g1);
  G.col(1) = vec9(g2);
  G.col(2) = vec9(gJ);
  // G·h·Gᵀ as rank-one terms of h's nonzero entries only (neo-Hookean has one): a general
  // product of these shapes went through Eigen's blocked kernels at several times the cost.
  A.setZero();
  for (int b = 0; b < 3; ++b)
    for (int a = 0; a < 3; ++a)
      if (e.h(a, b) != 0.0) A.noalias() += (e.h(a, b) * G.col(a)) * G.col(b).transpose();
  A.diagonal().array() += 2.0 * e.d[0];  // d2 I1 / dF2 = 2 I
  if (e.d[1] != 0.0) {
    // d(g2)[dF] = 2 (dI1 F + I1 dF - dF C - F dF^T F - F F^T dF), dI1 = 2 F : dF.
    const Mat3 FFt = F * F.transpose();
    for (int c = 0; c < 9; ++c) {
      const int i = c % 3, j = c / 3;  // dF = e_i e_j^T
      Mat3 d = (4.0 * F(i, j)) * F;
      d(i, j) += 2.0 * I1;
      d.row(i) -= 2.0 * C.row(j);                        // dF C
      d -= 2.0 * F.col(j) * F.row(i);                    // F dF^T F = F e_j e_i^T F
      d.col(j) -= 2.0 * FFt.col(i);                      // F F^T dF
      A.col(c) += e.d[1] * vec9(d);
    }
  }
  if (e.d[2] != 0.0) {
    // d cof(F): d(f1 x f2) = -[f2]x df1 + [f1]x df2, and cyclically.
    const Mat3 s0 = e.d[2] * skew(F.col(0)), s1 = e.d[2] * skew(F.col(1)), s2 = e.d[2] * skew(F.col(2));
    A.block<3, 3>(0, 3) -= s2;
    A.block<3, 3>(0, 6) += s1;
    A.block<3, 3>(3, 0) += s2;
    A.block<3, 3>(3, 6) -= s0;
    A.block<3, 3>(6, 0) -= s1;
    A.block<3, 3>(6, 3) += s0;
  }
}

void project_psd(Mat9& A) {
  A = (0.5 * (A + A.transpose())).eval();  // eval: in place, A's transpose would read entries already averaged
  Eigen::LLT<Mat9> llt(A);
  if (llt.info() == Eigen::Success) return;
  Eigen::SelfAdjointEigenSolver<Mat9> eig(A);
  const Vec9 lam = eig.eigenvalues().cwiseMax(0.0);
  A = eig.eigenvectors() * lam.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace tactus::physics
