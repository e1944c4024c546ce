// Each law's first Piola-Kirchhoff stress against its textbook closed form under a
// prescribed homogeneous deformation, and its tangent against finite differences.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "fem_test_util.hpp"
#include "physics/fem/constitutive.hpp"
#include "physics/fem/polar.hpp"

namespace tactus::physics {
namespace {

using fem_test::material;

// Axial P11 under F = diag(a, b, b), written out per law from its energy, independently of
// the invariant machinery in constitutive.cpp.
double axial_stress(const LawParams& p, double a, double b) {
  const double la = p.lambda, mu = p.mu, J = a * b * b;
  switch (p.law) {
    case FemLaw::linear:
    case FemLaw::corotational: return (la + 2 * mu) * (a - 1) + 2 * la * (b - 1);
    case FemLaw::stvk: {
      const double e1 = 0.5 * (a * a - 1), e2 = 0.5 * (b * b - 1);
      return a * (la * (e1 + 2 * e2) + 2 * mu * e1);  // P = F S
    }
    case FemLaw::neo_hookean: return mu * (a - 1 / a) + la * std::log(J) / a;  // mu (F - F^-T) + la ln J F^-T
    case FemLaw::mooney_rivlin: {
      const double I1 = a * a + 2 * b * b, I2 = 2 * a * a * b * b + b * b * b * b;
      const double dJ = b * b;  // dJ/da
      return p.c10 * (std::pow(J, -2.0 / 3) * 2 * a - 2.0 / 3 * std::pow(J, -5.0 / 3) * dJ * I1) +
             p.c01 * (std::pow(J, -4.0 / 3) * 4 * a * b * b - 4.0 / 3 * std::pow(J, -7.0 / 3) * dJ * I2) +
             p.kappa * (J - 1) * dJ;
    }
  }
  return 0.0;
}

TEST(FemConstitutive, UniaxialStretchMatchesClosedFormOfEachLaw) {
  for (FemLaw law : fem_test::all_laws()) {
    FemMaterial m = material(law, 1e6, 0.3);
    if (law == FemLaw::mooney_rivlin) {
      m.c10 = 1.5e5;
      m.c01 = 0.4e5;
    }
    const LawParams p = LawParams::from(m);
    for (double a : {0.7, 1.0, 1.05, 1.6}) {
      const double b = 1.0 - 0.2 * (a - 1.0);
      const Mat3 P = first_piola_stress(p, Vec3(a, b, b).asDiagonal());
      // Same arithmetic, different order: agreement to a few ulps of the stress scale E.
      EXPECT_NEAR(P(0, 0), axial_stress(p, a, b), 1e-9 * m.young_modulus) << to_string(law) << " a=" << a;
      EXPECT_NEAR(P(0, 1), 0.0, 1e-9 * m.young_modulus);
    }
  }
}

TEST(FemConstitutive, StVenantKirchhoffStressIsFTimesS) {
  const LawParams p = LawParams::from(material(FemLaw::stvk, 2e5, 0.35));
  Mat3 F;
  F << 1.2, 0.3, -0.1, 0.05, 0.8, 0.2, -0.2, 0.1, 1.1;
  const Mat3 E = 0.5 * (F.transpose() * F - Mat3::Identity());
  const Mat3 S = p.lambda * E.trace() * Mat3::Identity() + 2 * p.mu * E;
  EXPECT_LT((first_piola_stress(p, F) - F * S).norm(), 1e-9 * (F * S).norm());
}

TEST(FemConstitutive, RestStateIsStressFreeAndRotationInvariant) {
  const Mat3 R = fem_test::rotation(2.3, Vec3(1, -2, 0.5));
  for (FemLaw law : fem_test::all_laws()) {
    const LawParams p = LawParams::from(material(law));
    EXPECT_LT(first_piola_stress(p, Mat3::Identity()).norm(), 1e-9) << to_string(law);
    const double rotated = first_piola_stress(p, R).norm();
    if (law == FemLaw::linear)
      EXPECT_GT(rotated, 0.1 * p.mu) << "the linear law must not be rotation invariant";
    else
      EXPECT_LT(rotated, 1e-9 * p.mu) << to_string(law);  // round-off of a unit-size R
  }
}

TEST(FemConstitutive, HyperelasticTangentMatchesFiniteDifferences) {
  Mat3 mild, strong, inverted;
  mild << 1.02, 0.01, 0.0, -0.01, 0.98, 0.02, 0.0, 0.01, 1.01;
  strong << 1.7, 0.4, -0.2, 0.1, 0.6, 0.3, -0.3, 0.2, 1.3;
  inverted = strong;
  inverted.col(2) *= -1.0;  // det < 0: below the inversion threshold, in the extended energy
  for (FemLaw law : {FemLaw::stvk, FemLaw::neo_hookean, FemLaw::mooney_rivlin}) {
    FemMaterial m = material(law, 1e6, 0.4);
    if (law == FemLaw::mooney_rivlin) m.c01 = 0.5e5;
    const LawParams p = LawParams::from(m);
    for (const Mat3* F : {&mild, &strong, &inverted}) {
      Mat3 P;
      Mat9 A;
      hyperelastic_stress_tangent(p, *F, P, &A);
      const double h = 1e-6;
      for (int c = 0; c < 9; ++c) {
        Mat3 dF = Mat3::Zero();
        dF(c % 3, c / 3) = h;
        const Vec9 fd = (vec9(first_piola_stress(p, *F + dF)) - vec9(first_piola_stress(p, *F - dF))) / (2 * h);
        // Central differences: truncation ~h^2 |P'''|, round-off ~1e-16 |P| / h; 1e-6 of
        // the tangent's scale holds both with a margin.
        EXPECT_LT((A.col(c) - fd).norm(), 1e-6 * A.norm()) << to_string(law) << " col " << c << " det " << F->determinant();
      }
      // P is the derivative of the energy density.
      for (int c = 0; c < 9; ++c) {
        Mat3 dF = Mat3::Zero();
        dF(c % 3, c / 3) = h;
        const double fd = (strain_energy_density(p, *F + dF) - strain_energy_density(p, *F - dF)) / (2 * h);
        EXPECT_NEAR(P(c % 3, c / 3), fd, 1e-6 * P.norm() + 1e-6) << to_string(law);
      }
    }
  }
}

TEST(FemConstitutive, ProjectedTangentIsPositiveSemiDefinite) {
  Mat3 inverted;
  inverted << 0.3, 0.1, 0.0, 0.0, 0.9, 0.1, 0.1, 0.0, -0.4;
  for (FemLaw law : {FemLaw::stvk, FemLaw::neo_hookean, FemLaw::mooney_rivlin}) {
    const LawParams p = LawParams::from(material(law, 1e6, 0.45));
    Mat3 P;
    Mat9 A;
    hyperelastic_stress_tangent(p, inverted, P, &A);
    Eigen::SelfAdjointEigenSolver<Mat9> before(0.5 * (A + A.transpose()));
    project_psd(A);
    Eigen::SelfAdjointEigenSolver<Mat9> after(A);
    EXPECT_LT(before.eigenvalues().minCoeff(), 0.0) << to_string(law) << ": the test needs an indefinite tangent";
    EXPECT_GT(after.eigenvalues().minCoeff(), -1e-9 * after.eigenvalues().maxCoeff()) << to_string(law);
  }
}

TEST(FemConstitutive, InvertedElementsArePushedBackTowardPositiveVolume) {
  // d psi/dF : cof(F) = d psi / dJ < 0 means increasing J lowers the energy.
  Mat3 F = Vec3(1.0, 1.0, -0.5).asDiagonal();
  for (FemLaw law : {FemLaw::neo_hookean, FemLaw::mooney_rivlin}) {
    const LawParams p = LawParams::from(material(law));
    const double h = 1e-6;
    Mat3 up = F, down = F;
    up(2, 2) += h;
    down(2, 2) -= h;
    EXPECT_LT(strain_energy_density(p, up), strain_energy_density(p, down)) << to_string(law);
    EXPECT_TRUE(first_piola_stress(p, F).allFinite());
  }
}

TEST(FemPolar, RotationIsProperEvenForInvertedOrFlatGradients) {
  const Mat3 R0 = fem_test::rotation(1.1, Vec3(0.3, 1, -0.4));
  Mat3 S;
  S << 1.3, 0.2, 0.0, 0.2, 0.8, 0.1, 0.0, 0.1, 1.1;
  const Mat3 R = polar_rotation(R0 * S);
  EXPECT_LT((R - R0).norm(), 1e-12);
  Mat3 flat = R0;
  flat.col(2).setZero();
  Mat3 inverted = R0 * Vec3(1.0, 0.9, -0.3).asDiagonal();
  for (const Mat3& F : {flat, inverted}) {
    const Mat3 Q = polar_rotation(F);
    EXPECT_LT((Q.transpose() * Q - Mat3::Identity()).norm(), 1e-12);
    EXPECT_NEAR(Q.determinant(), 1.0, 1e-12);
    const Mat3 Sym = Q.transpose() * F;
    EXPECT_LT((Sym - Sym.transpose()).norm(), 1e-12);  // F = Q S with S symmetric
  }
}

}  // namespace
}  // namespace tactus::physics
