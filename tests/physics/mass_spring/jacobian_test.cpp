// Derivatives of the spring network against finite differences of its own forces and
// energy, and the three linear-algebra views (products, triplets, diagonal) against each other.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>

#include "ms_test_util.hpp"
#include "physics/mass_spring/tet_builder.hpp"

namespace tactus::physics {
namespace {

using test::random_vector;

/// A 2×2×2 tet block with Kelvin–Voigt dashpots, two Maxwell arms, nodal damping and angle
/// terms on the corners of some tets, in a deformed state with springs both stretched and
/// compressed.
struct Fixture {
  std::shared_ptr<SpringNetwork> net;
  VecX x, v, q;
};

Fixture make_fixture(SpringNetworkOptions options) {
  TetSpringParams p;
  p.youngs_modulus = 5e3;
  p.density = 1000.0;
  p.damping_per_mass = 3.0;
  p.viscoelastic.kelvin_voigt_tau = 0.02;
  p.viscoelastic.arms = {{0.8, 0.5}, {0.3, 4.0}};
  p.options = options;
  const auto m = mesh::box_volume(Vec3(0.02, 0.02, 0.02), 2, 2, 2);
  Fixture f;
  f.net = tet_mass_spring(m, p);
  for (std::size_t t = 0; t < m.tets.size(); t += 5) f.net->add_angle(m.tets[t][1], m.tets[t][0], m.tets[t][2], 2e-3);
  const auto n = f.net->rest_positions().size();
  f.x = f.net->rest_positions() + random_vector(n, 1, 1.5e-3);  // ±15% of the 10 mm edge
  f.v = random_vector(n, 2, 0.05);
  f.q = random_vector(static_cast<Eigen::Index>(f.net->internal_size()), 3, 5e-4);
  return f;
}

VecX forces(const Fixture& f, const VecX& x, const VecX& v) {
  auto s = f.net->make_scratch();
  VecX out;
  f.net->forces(x, v, f.q, out, *s);
  return out;
}

TEST(SpringJacobian, StiffnessProductEqualsCentralDifferencesOfForces) {
  // Exact Hessians (no projection). v = 0: the dashpot's dependence on x through the spring
  // direction is left out of K by design and vanishes at v = 0.
  const Fixture f = make_fixture({false, AngleHessian::exact});
  const VecX v0 = VecX::Zero(f.x.size());
  auto s = f.net->make_scratch();
  f.net->linearize(f.x, v0, f.q, *s);
  for (unsigned seed = 10; seed < 13; ++seed) {
    const VecX dx = random_vector(f.x.size(), seed);
    VecX kdx = VecX::Zero(f.x.size());
    f.net->add_stiffness_product(dx, kdx, *s);
    // Central differences: truncation O(h²·|f'''|) and round-off O(ε|f|/h); h = 1e-7 m
    // (1e-5 of the edge) puts both near 1e-8 relative, so 1e-6 leaves room and still
    // catches any wrong term (those are O(1) relative).
    const double h = 1e-7;
    const VecX fd = -(forces(f, f.x + h * dx, v0) - forces(f, f.x - h * dx, v0)) / (2 * h);
    EXPECT_LT((kdx - fd).norm(), 1e-6 * fd.norm()) << "seed " << seed;
  }
}

TEST(SpringJacobian, DampingProductEqualsDifferencesInVelocity) {
  // Forces are affine in v at fixed x, so central differences are exact up to round-off.
  const Fixture f = make_fixture({});
  auto s = f.net->make_scratch();
  f.net->linearize(f.x, f.v, f.q, *s);
  const VecX dv = random_vector(f.x.size(), 20);
  VecX ddv = VecX::Zero(f.x.size());
  f.net->add_damping_product(dv, ddv, *s);
  const double h = 1e-3;
  const VecX fd = -(forces(f, f.x, f.v + h * dv) - forces(f, f.x, f.v - h * dv)) / (2 * h);
  EXPECT_LT((ddv - fd).norm(), 1e-9 * fd.norm());
}

TEST(SpringJacobian, ForcesAreMinusTheEnergyGradient) {
  // Elastic forces only (v = 0) against central differences of elastic_energy, which checks
  // the angle gradient and the arms' share; same step-size reasoning as above.
  const Fixture f = make_fixture({});
  const VecX v0 = VecX::Zero(f.x.size());
  const VecX force = forces(f, f.x, v0);
  const VecX dx = random_vector(f.x.size(), 30);
  const double h = 1e-7;
  const double fd = (f.net->elastic_energy(f.x + h * dx, f.q) - f.net->elastic_energy(f.x - h * dx, f.q)) / (2 * h);
  EXPECT_NEAR(-force.dot(dx), fd, 1e-6 * std::abs(fd));
}

TEST(SpringJacobian, TripletsEqualProductsAndDiagonal) {
  for (auto mode : {AngleHessian::gauss_newton, AngleHessian::projected, AngleHessian::exact}) {
    const Fixture f = make_fixture({true, mode});
    auto s = f.net->make_scratch();
    f.net->linearize(f.x, f.v, f.q, *s);
    const double a = 0.7, b = 0.3;
    std::vector<Triplet> t;
    f.net->add_triplets(a, b, t, *s);
    const auto n = f.x.size();
    SparseMatrix m(n, n);
    m.setFromTriplets(t.begin(), t.end());
    const VecX y = random_vector(n, 40);
    VecX expected = VecX::Zero(n), tmp = VecX::Zero(n);
    f.net->add_stiffness_product(y, expected, *s);
    expected *= a;
    f.net->add_damping_product(y, tmp, *s);
    expected += b * tmp;
    // Same sums in another order: agreement to round-off.
    EXPECT_LT((m * y - expected).norm(), 1e-12 * expected.norm());
    VecX diag = VecX::Zero(n);
    f.net->add_diagonal(a, b, diag, *s);
    EXPECT_LT((diag - VecX(m.diagonal())).norm(), 1e-12 * diag.norm());
    EXPECT_LT((SparseMatrix(m.transpose()) * y - m * y).norm(), 1e-12 * expected.norm()) << "K must be symmetric";
  }
}

TEST(SpringJacobian, ProjectedStiffnessIsPositiveSemidefinite) {
  // With compressed springs and angles away from rest, the exact Hessian is indefinite; the
  // projected one must not be. Tolerance: round-off of a dense eigen-solve, 1e-10 of the
  // largest eigenvalue.
  for (bool project : {true, false}) {
    const Fixture f = make_fixture({project, project ? AngleHessian::projected : AngleHessian::exact});
    auto s = f.net->make_scratch();
    f.net->linearize(f.x, f.v, f.q, *s);
    std::vector<Triplet> t;
    f.net->add_triplets(1.0, 0.0, t, *s);
    SparseMatrix m(f.x.size(), f.x.size());
    m.setFromTriplets(t.begin(), t.end());
    const VecX ev = Eigen::SelfAdjointEigenSolver<MatX>(MatX(m)).eigenvalues();
    if (project)
      EXPECT_GT(ev.minCoeff(), -1e-10 * ev.maxCoeff());
    else
      EXPECT_LT(ev.minCoeff(), -1e-6 * ev.maxCoeff()) << "the fixture should have compressed springs";
  }
}

}  // namespace
}  // namespace tactus::physics
