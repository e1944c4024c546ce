// The element loop: input validation, rigid motions, and consistency of forces, stiffness
// products, triplets and diagonals.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <array>
#include <random>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "fem_test_util.hpp"

namespace tactus::physics {
namespace {

using fem_test::material;

VecX forces_at(const TetFem& fem, const VecX& x, const VecX& v) {
  auto s = fem.make_scratch();
  VecX f;
  fem.forces(x, v, VecX(), f, *s);
  return f;
}

VecX random_vector(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  VecX v(n);
  for (auto& c : v) c = u(rng);
  return v;
}

/// ||K dx + (f(x + h dx) - f(x - h dx)) / 2h|| / ||K dx||.
double stiffness_fd_error(const TetFem& fem, const VecX& x, const VecX& dx) {
  auto s = fem.make_scratch();
  const VecX zero = VecX::Zero(x.size());
  fem.linearize(x, zero, VecX(), *s);
  VecX Kdx = VecX::Zero(x.size());
  fem.add_stiffness_product(dx, Kdx, *s);
  const double h = 1e-7 * fem.rest_positions().cwiseAbs().maxCoeff() / dx.cwiseAbs().maxCoeff();
  const VecX fd = -(forces_at(fem, x + h * dx, zero) - forces_at(fem, x - h * dx, zero)) / (2 * h);
  return (Kdx - fd).norm() / Kdx.norm();
}

TEST(TetFem, RejectsInvertedAndFlatRestElementsNamingTheTet) {
  mesh::TetMesh m = mesh::box_volume(Vec3(1, 1, 1), 1, 1, 1);
  std::swap(m.tets[3][1], m.tets[3][2]);
  try {
    TetFem fem(m, material(FemLaw::linear));
    FAIL() << "an inverted tet must be rejected";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tet 3"), std::string::npos) << e.what();
  }
  mesh::TetMesh flat = fem_test::single_tet();
  flat.vertices[3] = Vec3(0.005, 0.005, 0.0);
  EXPECT_THROW(TetFem(flat, material(FemLaw::corotational)), InputError);
  FemMaterial bad = material(FemLaw::neo_hookean);
  bad.poisson_ratio = 0.5;
  EXPECT_THROW(TetFem(fem_test::single_tet(), bad), InputError);
}

TEST(TetFem, LumpedMassIsDensityTimesVolume) {
  const mesh::TetMesh m = mesh::box_volume(Vec3(0.02, 0.03, 0.04), 2, 3, 2);
  const TetFem fem(m, material(FemLaw::linear, 1e5, 0.3, 1100.0));
  EXPECT_NEAR(fem.lumped_mass().sum() / 3.0, 1100.0 * 0.02 * 0.03 * 0.04, 1e-12);
}

TEST(TetFem, RigidRotationGivesNoElasticForceExceptForTheLinearLaw) {
  const mesh::TetMesh m = mesh::box_volume(Vec3(0.02, 0.02, 0.02), 2, 2, 2);
  const double force_scale = 1e6 * 0.02 * 0.02;  // E times a face area [N]
  for (FemLaw law : fem_test::all_laws()) {
    const TetFem fem(m, material(law));
    double previous = 0.0;
    for (double angle : {0.1, 0.5, 1.5, 3.0}) {
      const VecX x = fem_test::deformed(fem.rest_positions(), fem_test::rotation(angle, Vec3(1, 2, 3)), Vec3(0.1, 0, 0));
      const double f = forces_at(fem, x, VecX::Zero(x.size())).norm();
      if (law == FemLaw::linear) {
        // Linear strain of a rotation is (cos(angle) - 1)(I - a a^T): it grows with the angle.
        EXPECT_GT(f, 1e-3 * force_scale) << angle;
        EXPECT_GT(f, previous) << angle;
        previous = f;
      } else {
        EXPECT_LT(f, 1e-10 * force_scale) << to_string(law) << " angle " << angle;  // round-off
      }
    }
  }
}

TEST(TetFem, StiffnessProductMatchesFiniteDifferencesOfForces) {
  // Mild, strong and inverted deformations of a single element and of a 2x2x2 block. The
  // hyperelastic laws use their exact tangent here (projection off); central differences
  // with h = 1e-7 of the size agree with it to ~1e-8, so 1e-5 is the requirement.
  Mat3 strong;
  strong << 1.6, 0.3, -0.2, 0.1, 0.7, 0.25, -0.2, 0.15, 1.3;
  for (FemLaw law : {FemLaw::linear, FemLaw::stvk, FemLaw::neo_hookean, FemLaw::mooney_rivlin}) {
    FemMaterial mat = material(law, 1e5, 0.4);
    mat.project_tangent = false;
    if (law == FemLaw::mooney_rivlin) mat.c01 = 1e4;
    for (const auto& m : {fem_test::single_tet(), mesh::box_volume(Vec3(0.02, 0.02, 0.02), 2, 2, 2)}) {
      const TetFem fem(m, mat);
      const VecX& X = fem.rest_positions();
      const VecX noise = 1e-3 * random_vector(X.size(), 7);
      const VecX dx = random_vector(X.size(), 11);
      EXPECT_LT(stiffness_fd_error(fem, X + noise, dx), 1e-5) << to_string(law) << " mild";
      EXPECT_LT(stiffness_fd_error(fem, fem_test::deformed(X, strong) + noise, dx), 1e-5) << to_string(law) << " strong";
      // Inverted: the last node pushed through the opposite face (single tet), or the block
      // mirrored through a plane (every element inverted).
      VecX inv = fem_test::deformed(X, Vec3(1.0, 1.0, -0.6).asDiagonal()) + noise;
      EXPECT_LT(stiffness_fd_error(fem, inv, dx), 1e-5) << to_string(law) << " inverted";
    }
  }
}

TEST(TetFem, CorotationalStiffnessIsExactAtRigidRotationsAndCloseUnderSmallStrain) {
  // R K0 R^T omits dR/dx; the omitted term is proportional to the stress, so it vanishes at
  // a rotated rest state (exact to FD accuracy) and stays of order the strain otherwise.
  const mesh::TetMesh m = mesh::box_volume(Vec3(0.02, 0.02, 0.02), 2, 2, 2);
  const TetFem fem(m, material(FemLaw::corotational, 1e5, 0.4));
  const Mat3 R = fem_test::rotation(1.2, Vec3(1, 1, 0));
  const VecX dx = random_vector(fem.rest_positions().size(), 3);
  EXPECT_LT(stiffness_fd_error(fem, fem_test::deformed(fem.rest_positions(), R), dx), 1e-5);
  const VecX strained = fem_test::deformed(fem.rest_positions(), R * Vec3(1.01, 0.995, 0.995).asDiagonal());
  EXPECT_LT(stiffness_fd_error(fem, strained, dx), 0.05);  // strain 1%: a few percent at most
}

TEST(TetFem, DampingProductIsMinusTheVelocityDerivative) {
  for (FemLaw law : fem_test::all_laws()) {
    FemMaterial mat = material(law, 1e5, 0.35);
    mat.rayleigh_mass = 2.0;
    mat.rayleigh_stiffness = 0.01;
    const TetFem fem(mesh::box_volume(Vec3(0.02, 0.02, 0.02), 2, 2, 2), mat);
    const VecX x = fem_test::deformed(fem.rest_positions(), fem_test::rotation(0.7, Vec3(0, 1, 1)) * Vec3(1.1, 1, 0.9).asDiagonal());
    const VecX v = random_vector(x.size(), 5), dv = random_vector(x.size(), 6);
    auto s = fem.make_scratch();
    fem.linearize(x, v, VecX(), *s);
    VecX Ddv = VecX::Zero(x.size());
    fem.add_damping_product(dv, Ddv, *s);
    // f is affine in v, so one-sided differences are exact up to round-off.
    const VecX fd = -(forces_at(fem, x, v + dv) - forces_at(fem, x, v));
    EXPECT_LT((Ddv - fd).norm(), 1e-8 * Ddv.norm()) << to_string(law);
  }
}

TEST(TetFem, TripletsAndDiagonalMatchTheProducts) {
  for (FemLaw law : fem_test::all_laws()) {
    FemMaterial mat = material(law, 1e5, 0.35);
    mat.rayleigh_mass = 1.5;
    mat.rayleigh_stiffness = 0.02;
    const TetFem fem(mesh::box_volume(Vec3(0.02, 0.03, 0.02), 2, 3, 2), mat);
    const VecX x = fem_test::deformed(fem.rest_positions(), fem_test::rotation(0.4, Vec3(1, 0, 1)) * Vec3(0.7, 1.2, 1.0).asDiagonal());
    auto s = fem.make_scratch();
    fem.linearize(x, VecX::Zero(x.size()), VecX(), *s);
    const double a = 0.3, b = 1.7;
    std::vector<Triplet> t;
    fem.add_triplets(a, b, t, *s);
    const auto n = x.size();
    SparseMatrix A(n, n);
    A.setFromTriplets(t.begin(), t.end());
    const VecX dx = random_vector(n, 9);
    VecX Kdx = VecX::Zero(n), Ddx = VecX::Zero(n);
    fem.add_stiffness_product(dx, Kdx, *s);
    fem.add_damping_product(dx, Ddx, *s);
    const VecX expected = a * Kdx + b * Ddx;
    // Same sums in another order: round-off only.
    EXPECT_LT((A * dx - expected).norm(), 1e-10 * expected.norm()) << to_string(law);
    VecX diag = VecX::Zero(n);
    fem.add_diagonal(a, b, diag, *s);
    EXPECT_LT((diag - VecX(A.diagonal())).norm(), 1e-10 * diag.norm()) << to_string(law);
    const MatX dense = MatX(A);
    EXPECT_LT((dense - dense.transpose()).norm(), 1e-10 * dense.norm()) << to_string(law) << ": K must be symmetric";
  }
}

TEST(TetFem, StvkExactTangentGivesTheSameProductsAsItsAssembledMatrix) {
  // StVK's exact linearization keeps F and S per element and builds the 9×9 tangents only
  // where a matrix is assembled; its products before that must be the matrix's, within
  // round-off, and stay so after it (the 9×9 route). Inverted and strongly stretched elements
  // included, where the tangent is indefinite.
  const TetFem fem(mesh::box_volume(Vec3(0.02, 0.03, 0.02), 2, 3, 2), material(FemLaw::stvk, 1e5, 0.35));
  const VecX X = fem.rest_positions();
  for (const VecX& x : {fem_test::deformed(X, fem_test::rotation(0.4, Vec3(1, 0, 1)) * Vec3(0.7, 1.2, 1.0).asDiagonal()),
                        VecX(fem_test::deformed(X, Vec3(1.3, 1.0, -0.6).asDiagonal()) + 1e-3 * random_vector(X.size(), 4))}) {
    auto s = fem.make_scratch();
    ASSERT_TRUE(fem.linearize_exact(x, VecX::Zero(x.size()), VecX(), *s));
    const auto n = x.size();
    const VecX dx = random_vector(n, 9);
    VecX deferred = VecX::Zero(n), diag = VecX::Zero(n), expanded = VecX::Zero(n);
    fem.add_stiffness_product(dx, deferred, *s);
    fem.add_diagonal(1.0, 0.0, diag, *s);  // builds the 9×9 tangents
    fem.add_stiffness_product(dx, expanded, *s);
    std::vector<Triplet> t;
    fem.add_triplets(1.0, 0.0, t, *s);
    SparseMatrix K(n, n);
    K.setFromTriplets(t.begin(), t.end());
    const VecX assembled = K * dx;
    EXPECT_LT((deferred - assembled).norm(), 1e-12 * assembled.norm());
    EXPECT_LT((expanded - assembled).norm(), 1e-12 * assembled.norm());
    EXPECT_LT((diag - VecX(K.diagonal())).norm(), 1e-12 * diag.norm());
  }
}

TEST(TetFem, ProjectedStiffnessOfAnInvertedBlockIsPositiveSemiDefinite) {
  for (FemLaw law : {FemLaw::corotational, FemLaw::stvk, FemLaw::neo_hookean, FemLaw::mooney_rivlin}) {
    const TetFem fem(mesh::box_volume(Vec3(0.02, 0.02, 0.02), 1, 1, 1), material(law, 1e5, 0.45));
    const VecX x = fem_test::deformed(fem.rest_positions(), Vec3(1.2, 0.5, -0.3).asDiagonal());
    auto s = fem.make_scratch();
    fem.linearize(x, VecX::Zero(x.size()), VecX(), *s);
    std::vector<Triplet> t;
    fem.add_triplets(1.0, 0.0, t, *s);
    SparseMatrix K(x.size(), x.size());
    K.setFromTriplets(t.begin(), t.end());
    Eigen::SelfAdjointEigenSolver<MatX> eig{MatX(K)};
    EXPECT_GT(eig.eigenvalues().minCoeff(), -1e-9 * eig.eigenvalues().maxCoeff()) << to_string(law);
  }
}

TEST(TetFem, ForcesOfInvertedAndFlatElementsAreFinite) {
  for (FemLaw law : fem_test::all_laws()) {
    const TetFem fem(mesh::box_volume(Vec3(0.02, 0.02, 0.02), 2, 2, 2), material(law));
    for (const Vec3& scale : {Vec3(1, 1, 0), Vec3(1, 1, -1), Vec3(0, 0, 0)}) {
      const VecX x = fem_test::deformed(fem.rest_positions(), scale.asDiagonal());
      EXPECT_TRUE(forces_at(fem, x, VecX::Zero(x.size())).allFinite()) << to_string(law);
      EXPECT_TRUE(std::isfinite(fem.elastic_energy(x, VecX())));
    }
  }
}

TEST(TetFem, SystemProductEqualsMassDampingAndStiffnessProducts) {
  // out += (a M + b D + c K) in in one element pass, for every law, with Rayleigh damping.
  const mesh::TetMesh m = mesh::box_volume(Vec3(0.02, 0.02, 0.02), 2, 2, 2);
  for (FemLaw law : fem_test::all_laws()) {
    FemMaterial mat = material(law, 1e4, 0.3);
    mat.rayleigh_mass = 3.0;
    mat.rayleigh_stiffness = 0.01;
    const TetFem fem(m, mat);
    auto s = fem.make_scratch();
    const VecX x = fem_test::deformed(fem.rest_positions(), fem_test::rotation(0.4, Vec3(1, 2, 3)) *
                                                                Vec3(1.1, 0.95, 1.02).asDiagonal());
    fem.linearize(x, VecX::Zero(x.size()), VecX(), *s);
    const VecX in = random_vector(x.size(), 7);
    VecX k = VecX::Zero(x.size()), d = VecX::Zero(x.size());
    fem.add_stiffness_product(in, k, *s);
    fem.add_damping_product(in, d, *s);
    for (const auto& [a, b, c] : {std::array<double, 3>{1.0, 0.01, 1e-4}, {0.0, 0.0, 1.0}, {0.0, 1.0, 0.0}, {2.0, 0.0, 0.0}}) {
      VecX out = VecX::Constant(x.size(), 0.5);
      fem.add_system_product(a, b, c, in, out, *s);
      const VecX expected = VecX::Constant(x.size(), 0.5) + a * fem.lumped_mass().cwiseProduct(in) + b * d + c * k;
      EXPECT_LT((out - expected).norm(), 1e-12 * expected.norm()) << to_string(law) << " a=" << a << " b=" << b;
    }
  }
}

TEST(TetFem, LinearizedForcesEqualForcesPlusStiffnessProduct) {
  // The one-pass right-hand side of implicit steps, with damping and relaxation branches.
  const mesh::TetMesh m = mesh::box_volume(Vec3(0.02, 0.02, 0.02), 2, 2, 2);
  for (FemLaw law : fem_test::all_laws()) {
    FemMaterial mat = material(law, 1e4, 0.45);
    mat.rayleigh_mass = 3.0;
    mat.rayleigh_stiffness = 0.01;
    if (law == FemLaw::linear || law == FemLaw::corotational) mat.prony = {{0.3, 0.05}};
    const TetFem fem(m, mat);
    const VecX x = fem_test::deformed(fem.rest_positions(), fem_test::rotation(0.4, Vec3(1, 2, 3)) *
                                                                Vec3(1.1, 0.95, 1.02).asDiagonal());
    const VecX v = 0.1 * random_vector(x.size(), 3), dx = 1e-3 * random_vector(x.size(), 5);
    const VecX q = random_vector(static_cast<Eigen::Index>(fem.internal_size()), 9);
    auto s = fem.make_scratch();
    VecX expected(x.size());
    fem.forces(x, v, q, expected, *s);
    fem.linearize(x, v, q, *s);
    fem.add_stiffness_product(dx, expected, *s);
    auto fresh = fem.make_scratch();  // rotations computed inside the pass
    VecX f = VecX::Constant(x.size(), 7.0);
    fem.linearized_forces(x, v, q, dx, f, *fresh);
    EXPECT_LT((f - expected).norm(), 1e-12 * expected.norm()) << to_string(law);
    VecX k = VecX::Zero(x.size()), k_expected = VecX::Zero(x.size());
    fem.add_stiffness_product(dx, k, *fresh);  // and it linearizes
    fem.add_stiffness_product(dx, k_expected, *s);
    EXPECT_LT((k - k_expected).norm(), 1e-12 * k_expected.norm()) << to_string(law);
  }
}

TEST(TetFem, AssembledSystemEqualsTheTriplets) {
  // The block matrix of a M + b D + c K holds the same entries as the triplets plus the mass.
  const mesh::TetMesh m = mesh::box_volume(Vec3(0.02, 0.02, 0.02), 2, 2, 2);
  for (FemLaw law : fem_test::all_laws()) {
    FemMaterial mat = material(law, 1e4, 0.45);
    mat.rayleigh_mass = 3.0;
    mat.rayleigh_stiffness = 0.01;
    const TetFem fem(m, mat);
    auto s = fem.make_scratch();
    const VecX x = fem_test::deformed(fem.rest_positions(), fem_test::rotation(0.4, Vec3(1, 2, 3)) *
                                                                Vec3(1.1, 0.95, 1.02).asDiagonal());
    fem.linearize(x, VecX::Zero(x.size()), VecX(), *s);
    const double a = 1.0, b = 0.01, c = 1e-4;
    const BlockMatrix* assembled = fem.assemble_system(a, b, c, *s);
    if (law != FemLaw::linear && law != FemLaw::corotational) {
      EXPECT_EQ(assembled, nullptr) << to_string(law);
      continue;
    }
    ASSERT_NE(assembled, nullptr) << to_string(law);
    const auto n = x.size();
    Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
    for (std::size_t i = 0; i < assembled->diagonal.size(); ++i)
      dense.block<3, 3>(3 * i, 3 * i) = assembled->diagonal[i];
    for (std::size_t i = 0; i + 1 < assembled->row_start.size(); ++i)
      for (auto k = assembled->row_start[i]; k < assembled->row_start[i + 1]; ++k) {
        const auto j = static_cast<Eigen::Index>(assembled->column[static_cast<std::size_t>(k)]);
        ASSERT_GT(j, static_cast<Eigen::Index>(i));
        dense.block<3, 3>(3 * i, 3 * j) = assembled->upper[static_cast<std::size_t>(k)];
        dense.block<3, 3>(3 * j, 3 * i) = assembled->upper[static_cast<std::size_t>(k)].transpose();
      }
    std::vector<Triplet> triplets;
    fem.add_triplets(c, b, triplets, *s);
    SparseMatrix expected(n, n);
    expected.setFromTriplets(triplets.begin(), triplets.end());
    const Eigen::MatrixXd reference = Eigen::MatrixXd(expected) + Eigen::MatrixXd(a * fem.lumped_mass().asDiagonal());
    EXPECT_LT((dense - reference).norm(), 1e-12 * reference.norm()) << to_string(law);
  }
}

TEST(TetFem, AssembledSystemIsBitForBitTheSameOnOneOrTwoThreads) {
  // 8,640 tets: above the size at which the assembly goes row by row on every thread.
  const mesh::TetMesh m = mesh::box_volume(Vec3(0.06, 0.06, 0.05), 12, 12, 10);
  for (FemMass mass : {FemMass::lumped, FemMass::consistent}) {
    FemMaterial mat = material(FemLaw::corotational, 1e4, 0.45, 1050.0);
    mat.rayleigh_mass = 2.0;
    mat.rayleigh_stiffness = 0.01;
    const TetFem fem(m, mat, mass);
    const VecX x = fem_test::deformed(fem.rest_positions(), fem_test::rotation(0.3, Vec3(1, -2, 1)) *
                                                                Vec3(1.05, 0.97, 1.01).asDiagonal());
    auto assemble = [&](unsigned threads) {
      set_thread_limit(threads);
      auto s = fem.make_scratch();
      fem.linearize(x, VecX::Zero(x.size()), VecX(), *s);
      BlockMatrix K = *fem.assemble_system(1.0, 0.01, 1e-4, *s);
      set_thread_limit(0);
      return K;
    };
    const BlockMatrix serial = assemble(1), parallel = assemble(2);
    ASSERT_EQ(serial.diagonal.size(), parallel.diagonal.size());
    ASSERT_EQ(serial.upper.size(), parallel.upper.size());
    for (std::size_t i = 0; i < serial.diagonal.size(); ++i) ASSERT_TRUE(serial.diagonal[i] == parallel.diagonal[i]) << i;
    for (std::size_t k = 0; k < serial.upper.size(); ++k) ASSERT_TRUE(serial.upper[k] == parallel.upper[k]) << k;
  }
}

/// Positions after a few implicit steps of a sagging block, on `threads` threads.
VecX run_block(FemLaw law, unsigned threads) {
  set_thread_limit(threads);
  // 8,640 tets: above the size at which element and node loops split across threads.
  const mesh::TetMesh m = mesh::box_volume(Vec3(0.06, 0.06, 0.05), 12, 12, 10);
  FemMaterial mat = material(law, 1e4, 0.45, 1050.0);
  mat.rayleigh_mass = 1.0;
  mat.rayleigh_stiffness = 0.005;
  if (law == FemLaw::corotational) mat.prony = {{0.3, 0.05}};
  Body b;
  b.model = std::make_shared<TetFem>(m, mat);
  b.fix_nodes(fem_test::nodes_at(m, 2, -0.025));
  b.gravity = Vec3(9.81, 0, -9.81);
  b.settings.newton_iterations = 2;
  BodyState s = make_state(b);
#ifdef TACTUS_SANITIZED
  const int steps = 2;  // memory and UB checks need the loops, not a long trajectory
#else
  const int steps = 10;
#endif
  for (int i = 0; i < steps; ++i) step(b, s, 0.01);
  set_thread_limit(0);
  return s.x;
}

TEST(TetFem, ResultsAreBitForBitIndependentOfTheThreadCount) {
  // Lockstep replay needs identical states whatever the thread count: each element writes
  // its own columns and nodes sum them in element order.
  for (FemLaw law : {FemLaw::corotational, FemLaw::neo_hookean, FemLaw::linear}) {
    const VecX serial = run_block(law, 1), parallel = run_block(law, 2);
    ASSERT_TRUE(serial.allFinite());
    EXPECT_TRUE(serial == parallel) << to_string(law) << ": max difference "
                                    << (serial - parallel).cwiseAbs().maxCoeff();
  }
}

}  // namespace
}  // namespace tactus::physics
