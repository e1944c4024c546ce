#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/counting_allocator.hpp"  // tests/core
#include "core/error.hpp"
#include "precompute/interpolator.hpp"

namespace tactus::precompute {
namespace {

/// Test fields with their Jacobians (column k: ∂/∂x_k), the derivatives a space stores.
struct SmoothField {
  Vec3 operator()(const Vec3& x) const {
    return Vec3(std::sin(20 * x.x()) + x.y(), std::exp(5 * x.y()) * x.z(), 10 * x.x() * x.z() - 3 * x.y() * x.y());
  }
  Mat3 jacobian(const Vec3& x) const {
    Mat3 j;
    j << 20 * std::cos(20 * x.x()), 1, 0, 0, 5 * std::exp(5 * x.y()) * x.z(), std::exp(5 * x.y()), 10 * x.z(),
        -6 * x.y(), 10 * x.x();
    return j;
  }
};
const SmoothField smooth_field;

struct QuadraticField {
  Vec3 operator()(const Vec3& x) const {
    return Vec3(1 + 2 * x.x() - x.z() + 30 * x.x() * x.x(), 5 * x.x() * x.y() - 7 * x.z() * x.z(), x.y() * x.z());
  }
  Mat3 jacobian(const Vec3& x) const {
    Mat3 j;
    j << 2 + 60 * x.x(), 0, -1, 5 * x.y(), 5 * x.x(), -14 * x.z(), 0, x.z(), x.y();
    return j;
  }
};
const QuadraticField quadratic_field;

/// A polynomial of total degree 3 in s = 30 x (so that it varies by about 1 over the grid).
struct CubicField {
  Vec3 operator()(const Vec3& x) const {
    const Vec3 s = 30.0 * x;
    return Vec3(s.x() * s.x() * s.x() + 2 * s.x() * s.x() * s.y() - s.y() * s.z() + 4 * s.x() * s.y() * s.z(),
                s.y() * s.y() * s.y() - 3 * s.x() * s.z() * s.z() + s.z(),
                s.z() * s.z() * s.z() + s.x() * s.y() * s.z() - s.x() * s.x());
  }
  Mat3 jacobian(const Vec3& x) const {
    const Vec3 s = 30.0 * x;
    Mat3 j;
    j << 3 * s.x() * s.x() + 4 * s.x() * s.y() + 4 * s.y() * s.z(), 2 * s.x() * s.x() - s.z() + 4 * s.x() * s.z(),
        -s.y() + 4 * s.x() * s.y(),  //
        -3 * s.z() * s.z(), 3 * s.y() * s.y(), -6 * s.x() * s.z() + 1,  //
        s.y() * s.z() - 2 * s.x(), s.x() * s.z(), 3 * s.z() * s.z() + s.x() * s.y();
    return 30.0 * j;
  }
};
const CubicField cubic_field;

/// A 6 x 6 x 6 space with spacing 1 cm (or `spacing`, over the same box's corner) whose forces
/// sample `field` and whose two-node "displacements" repeat the force, with their derivatives.
template <class Field>
std::shared_ptr<Space> synthetic(const Field& field, double spacing = 0.01, int count = 6) {
  auto s = std::make_shared<Space>();
  s->grid.spacing = spacing;
  s->grid.origin = Vec3(-0.02, -0.03, 0.0);
  s->grid.counts = {count, count, count};
  s->allocate(2);
  for (std::size_t p = 0; p < s->grid.size(); ++p) {
    const auto c = static_cast<Eigen::Index>(p);
    s->status[p] = PointStatus::solved;
    s->force[p] = field(s->grid.point(p));
    s->displacement.col(c) << s->force[p], 2.0 * s->force[p];
    s->force_gradient[p] = field.jacobian(s->grid.point(p));
    s->displacement_gradient.block<3, 3>(0, 3 * c) = s->force_gradient[p];
    s->displacement_gradient.block<3, 3>(3, 3 * c) = 2.0 * s->force_gradient[p];
  }
  return s;
}

constexpr Interpolation kAll[] = {Interpolation::trilinear,  Interpolation::rbf_cubic,
                                  Interpolation::rbf_thin_plate, Interpolation::polynomial,
                                  Interpolation::tricubic_hermite, Interpolation::rbf_hermite};
constexpr Interpolation kInterpolating[] = {Interpolation::trilinear, Interpolation::rbf_cubic,
                                            Interpolation::rbf_thin_plate, Interpolation::tricubic_hermite,
                                            Interpolation::rbf_hermite};
constexpr Interpolation kHermite[] = {Interpolation::tricubic_hermite, Interpolation::rbf_hermite};

TEST(Interpolator, ExactAtGridPoints) {
  const auto space = synthetic(smooth_field);
  for (auto m : kInterpolating) {
    const Interpolator in(space, m);
    VecX shape;
    for (std::size_t p = 0; p < space->grid.size(); ++p) {
      const Query q = in.shape(space->grid.point(p), shape);
      ASSERT_TRUE(q.valid);
      EXPECT_FALSE(q.outside);
      EXPECT_LT((q.force - space->force[p]).norm(), 1e-9 * (1.0 + space->force[p].norm()))
          << to_string(m) << " point " << p;
      EXPECT_LT((shape - space->displacement.col(static_cast<Eigen::Index>(p))).norm(), 1e-9 * (1.0 + shape.norm()));
    }
  }
}

TEST(Interpolator, PolynomialFitReproducesQuadratics) {
  const auto space = synthetic(quadratic_field);
  const Interpolator in(space, Interpolation::polynomial);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const Vec3 p = space->grid.origin + 0.05 * Vec3(u(rng), u(rng), u(rng));
    const Query q = in.force(p);
    ASSERT_TRUE(q.valid);
    EXPECT_LT((q.force - quadratic_field(p)).norm(), 1e-9);
  }
}

TEST(Interpolator, SmoothBetweenGridPoints) {
  const auto space = synthetic(smooth_field);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double error[6] = {0, 0, 0, 0, 0, 0};
  for (int i = 0; i < 300; ++i) {
    // The interior, where every method has its full stencil.
    const Vec3 p = space->grid.origin + Vec3::Constant(0.01) + 0.03 * Vec3(u(rng), u(rng), u(rng));
    for (int k = 0; k < 6; ++k) {
      const Query q = Interpolator(space, kAll[k]).force(p);
      ASSERT_TRUE(q.valid);
      EXPECT_FALSE(q.fallback);
      error[k] = std::max(error[k], (q.force - smooth_field(p)).norm());
    }
  }
  // The field varies by about 1 over the grid: every method follows it closely, and the
  // radial bases beat trilinear interpolation.
  for (double e : error) EXPECT_LT(e, 0.05);
  EXPECT_LT(error[1], error[0]);
  EXPECT_LT(error[2], error[0]);
  // With the derivatives, both Hermite methods beat every method without them.
  for (int k = 4; k < 6; ++k)
    for (int j = 0; j < 4; ++j) EXPECT_LT(error[k], error[j]) << to_string(kAll[k]) << " against " << to_string(kAll[j]);
  // Continuity: inside a cell every method is smooth; across a cell face trilinear is
  // continuous and the others (a new stencil on each side) jump by at most their error.
  for (auto m : kAll) {
    const Interpolator in(space, m);
    const Vec3 inside(0.0042, -0.0057, 0.0153);
    const Vec3 face(0.0, -0.0057, 0.0153);  // x = 0 is a grid plane
    const Vec3 d(1e-9, 0, 0);
    EXPECT_LT((in.force(inside + d).force - in.force(inside - d).force).norm(), 1e-6) << to_string(m);
    const double jump = (in.force(face + d).force - in.force(face - d).force).norm();
    const bool continuous = m == Interpolation::trilinear || m == Interpolation::tricubic_hermite;
    EXPECT_LT(jump, continuous ? 1e-6 : 0.05) << to_string(m);
  }
}

TEST(Interpolator, OutsideIsClampedAndReported) {
  const auto space = synthetic(smooth_field);
  for (auto m : kAll) {
    const Interpolator in(space, m);
    const Vec3 corner = space->grid.upper();
    const Query q = in.force(corner + Vec3(0.5, 0.0, 0.5));
    EXPECT_TRUE(q.valid);
    EXPECT_TRUE(q.outside);
    EXPECT_LT((q.force - in.force(corner).force).norm(), 1e-12);
    EXPECT_FALSE(in.force(corner).outside);
    EXPECT_TRUE(in.force(Vec3(std::nan(""), 0, 0)).outside);
  }
}

TEST(Interpolator, LeavesOutPointsNotSolved) {
  auto space = synthetic(smooth_field);
  const std::size_t hole = space->grid.index(2, 2, 2);
  space->status[hole] = PointStatus::failed;
  space->force[hole] = Vec3::Constant(1e6);  // must not leak into any result
  space->force_gradient[hole] = Mat3::Constant(1e9);
  for (auto m : kAll) {
    const Interpolator in(space, m);
    const Query q = in.force(space->grid.point(2, 2, 2) + Vec3::Constant(0.004));
    ASSERT_TRUE(q.valid);
    EXPECT_LT(q.force.norm(), 10.0) << to_string(m);
  }
  // A cell with no solved corner gives no value.
  auto empty = synthetic(smooth_field);
  for (auto& st : empty->status) st = PointStatus::unreachable;
  EXPECT_FALSE(Interpolator(empty, Interpolation::trilinear).force(Vec3::Zero()).valid);
  EXPECT_FALSE(Interpolator(empty, Interpolation::rbf_cubic).force(Vec3::Zero()).valid);
}

TEST(Interpolator, LocatedOnceTheForceIsThePlainQueryBitForBit) {
  // As a two-point space's levels are queried: p located on one space, the force taken from
  // another on the same grid, here with a hole and points outside the grid.
  auto space = synthetic(smooth_field);
  space->status[space->grid.index(2, 3, 2)] = PointStatus::failed;
  const auto other = synthetic(cubic_field);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.1, 1.1);
  const Vec3 lower = space->grid.origin, size = space->grid.upper() - lower;
  for (auto m : kAll) {
    const Interpolator in(space, m), on_same_grid(other, m);
    for (int i = 0; i < 300; ++i) {
      const Vec3 p = lower + size.cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
      const Interpolator::Located at = on_same_grid.locate(p);
      const Query plain = in.force(p), located = in.force(p, at);
      ASSERT_EQ(plain.force, located.force) << to_string(m) << " at " << p.transpose();
      EXPECT_EQ(plain.valid, located.valid);
      EXPECT_EQ(plain.outside, located.outside);
      EXPECT_EQ(plain.fallback, located.fallback);
    }
  }
}

TEST(Interpolator, TricubicHermiteReproducesCubicsWhereItsDifferencesAreCentral) {
  // Mixed derivatives come from central differences of the stored gradients in the interior,
  // exact for the gradients of a cubic (quadratics): the tricubic Hermite then reproduces any
  // polynomial of total degree 3, its value and its shape.
  const auto space = synthetic(cubic_field);
  const Interpolator in(space, Interpolation::tricubic_hermite);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  VecX shape;
  for (int i = 0; i < 200; ++i) {
    // Cells 1..3 of each axis: every corner has both neighbours.
    const Vec3 p = space->grid.origin + Vec3::Constant(0.01) + 0.03 * Vec3(u(rng), u(rng), u(rng));
    const Vec3 exact = cubic_field(p);
    const Query q = in.shape(p, shape);
    ASSERT_TRUE(q.valid);
    EXPECT_FALSE(q.fallback);
    EXPECT_LT((q.force - exact).norm(), 1e-9 * (1.0 + exact.norm())) << p.transpose();
    EXPECT_LT((shape.tail<3>() - 2.0 * exact).norm(), 2e-9 * (1.0 + exact.norm()));
    EXPECT_LT((in.force(p).force - q.force).norm(), 1e-12 * (1.0 + exact.norm()));
  }
  // At the grid's border the differences are one-sided: still exact for quadratics.
  const auto quadratic = synthetic(quadratic_field);
  const Interpolator border(quadratic, Interpolation::tricubic_hermite);
  for (int i = 0; i < 200; ++i) {
    const Vec3 p = space->grid.origin + 0.05 * Vec3(u(rng), u(rng), u(rng));
    EXPECT_LT((border.force(p).force - quadratic_field(p)).norm(), 1e-9 * (1.0 + quadratic_field(p).norm()));
  }
}

TEST(Interpolator, RbfHermiteReproducesLinearFieldsEverywhere) {
  struct Linear {
    Vec3 operator()(const Vec3& x) const { return Vec3(1.0 + 3 * x.x() - x.y(), 2 * x.z(), -x.x() + 5 * x.y() + x.z()); }
    Mat3 jacobian(const Vec3&) const {
      Mat3 j;
      j << 3, -1, 0, 0, 0, 2, -1, 5, 1;
      return j;
    }
  };
  auto space = synthetic(Linear{});
  space->status[space->grid.index(3, 2, 2)] = PointStatus::failed;  // a partial stencil too
  const Interpolator in(space, Interpolation::rbf_hermite);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const Vec3 p = space->grid.origin + 0.05 * Vec3(u(rng), u(rng), u(rng));
    const Query q = in.force(p);
    ASSERT_TRUE(q.valid);
    EXPECT_FALSE(q.fallback);
    EXPECT_LT((q.force - Linear{}(p)).norm(), 1e-9);
  }
}

TEST(Interpolator, HermiteMethodsFollowTheStoredGradients) {
  // The slope of the interpolated force at a grid point, by central differences of queries
  // 1 µm either side, is the stored Jacobian: both methods interpolate derivatives too.
  const auto space = synthetic(smooth_field);
  for (auto m : kHermite) {
    const Interpolator in(space, m);
    for (const std::array<int, 3> ijk : {std::array<int, 3>{2, 3, 2}, std::array<int, 3>{1, 1, 4},
                                          std::array<int, 3>{3, 2, 1}}) {
      const std::size_t p = space->grid.index(ijk[0], ijk[1], ijk[2]);
      const Vec3 x = space->grid.point(p);
      Mat3 slope;
      for (int k = 0; k < 3; ++k) {
        const Vec3 d = 1e-6 * Vec3::Unit(k);
        slope.col(k) = (in.force(x + d).force - in.force(x - d).force) / 2e-6;
      }
      EXPECT_LT((slope - space->force_gradient[p]).norm(), 1e-5 * space->force_gradient[p].norm())
          << to_string(m) << " at " << p << "\n" << slope << "\n" << space->force_gradient[p];
    }
  }
}

TEST(Interpolator, CellJumpIsWhatTheGradientsLeaveUnexplainedAlongAnEdge) {
  // Along an edge of length h the trapezoid rule on the stored gradients misses a cubic's
  // change by h³·f‴/12: f = c·x³ along x gives c·h³/2 in every cell, a quadratic nothing.
  struct CubicAlongX {
    double c = 2.0e4;
    Vec3 operator()(const Vec3& x) const { return Vec3(c * x.x() * x.x() * x.x(), 0.0, 0.0); }
    Mat3 jacobian(const Vec3& x) const {
      Mat3 j = Mat3::Zero();
      j(0, 0) = 3.0 * c * x.x() * x.x();
      return j;
    }
  };
  const double h = 0.01;
  const Interpolator cubic(synthetic(CubicAlongX{}), Interpolation::tricubic_hermite);
  const Interpolator quadratic(synthetic(quadratic_field), Interpolation::tricubic_hermite);
  for (const std::array<int, 3> ijk : {std::array<int, 3>{0, 0, 0}, std::array<int, 3>{2, 4, 1}}) {
    EXPECT_NEAR(cubic.cell_jump({0, ijk}), 0.5 * CubicAlongX{}.c * h * h * h, 1e-12);
    EXPECT_LT(quadratic.cell_jump({0, ijk}), 1e-12);
  }
  // A step in the force (two equilibria either side of x = 0.005 m, flat on each side): the
  // cells that straddle it report the step, the others nothing.
  struct Step {
    Vec3 operator()(const Vec3& x) const { return Vec3(0.0, 0.0, x.x() > 0.005 ? 2.0 : 3.0); }
    Mat3 jacobian(const Vec3&) const { return Mat3::Zero(); }
  };
  const auto stepped = synthetic(Step{});
  const Interpolator step(stepped, Interpolation::tricubic_hermite);
  for (int i = 0; i + 1 < stepped->grid.counts[0]; ++i) {
    const double x0 = stepped->grid.origin.x() + i * h;
    const bool straddles = x0 < 0.005 && x0 + h > 0.005;
    EXPECT_NEAR(step.cell_jump({0, {i, 1, 1}}), straddles ? 1.0 : 0.0, 1e-12) << i;
  }
  // A cell with a corner not solved has no jump to report.
  stepped->status[stepped->grid.index(1, 1, 1)] = PointStatus::failed;
  EXPECT_LT(Interpolator(stepped, Interpolation::tricubic_hermite).cell_jump({0, {1, 1, 1}}), 0.0);
}

TEST(Interpolator, TricubicHermiteErrorFallsAsTheFourthPowerOfTheSpacing) {
  // The same box at 1 cm and at 5 mm: trilinear's error falls about 4 times (h²), the
  // tricubic Hermite's about 16 times (h⁴); at least 10 here, on the interior.
  auto max_error = [](const std::shared_ptr<Space>& space, Interpolation m) {
    const Interpolator in(space, m);
    std::mt19937 rng(13);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    double e = 0.0;
    for (int i = 0; i < 400; ++i) {
      const Vec3 p = space->grid.origin + Vec3::Constant(0.01) + 0.03 * Vec3(u(rng), u(rng), u(rng));
      e = std::max(e, (in.force(p).force - smooth_field(p)).norm());
    }
    return e;
  };
  const auto coarse = synthetic(smooth_field, 0.01, 6), fine = synthetic(smooth_field, 0.005, 11);
  const double hermite = max_error(coarse, Interpolation::tricubic_hermite) /
                         max_error(fine, Interpolation::tricubic_hermite);
  const double trilinear = max_error(coarse, Interpolation::trilinear) / max_error(fine, Interpolation::trilinear);
  EXPECT_GT(hermite, 10.0);
  EXPECT_GT(trilinear, 3.0);
  EXPECT_LT(trilinear, 5.0);
}

TEST(Interpolator, HermiteMethodsRefuseASpaceWithoutDerivatives) {
  auto space = synthetic(smooth_field);
  space->has_gradients = false;  // as read from a version 1 file
  for (auto m : kHermite) {
    try {
      const Interpolator in(space, m);
      ADD_FAILURE() << to_string(m) << " accepted a space without derivatives";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("derivatives"), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW(Interpolator(space, Interpolation::rbf_cubic));
}

TEST(Interpolator, ForceQueriesDoNotAllocate) {
  const auto space = synthetic(smooth_field);
  auto partial = synthetic(smooth_field);
  partial->status[partial->grid.index(3, 3, 3)] = PointStatus::failed;  // forces the small solve
  for (auto m : kAll) {
    const Interpolator a(space, m), b(partial, m);
    VecX shape(static_cast<Eigen::Index>(space->displacement.rows()));
    const tactus::testing::AllocationCounter counter;
    double sum = 0.0;
    for (int i = 0; i < 100; ++i) {
      const Vec3 p(0.001 * i - 0.03, 0.0004 * i, 0.035);
      sum += a.force(p).force.norm() + b.force(p).force.norm() + b.force(Vec3(0.015, 0.005, 0.035)).force.norm();
      sum += a.shape(p, shape).force.norm();
    }
    EXPECT_EQ(counter.count(), 0u) << to_string(m);
    EXPECT_TRUE(std::isfinite(sum));
  }
}

}  // namespace
}  // namespace tactus::precompute
