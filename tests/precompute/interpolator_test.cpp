#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <random>

#include "precompute/interpolator.hpp"

// Counts heap allocations, to check that force queries make none (not under the
// sanitizers, which own the allocator).
#ifndef TACTUS_SANITIZED
namespace {
std::atomic<long> g_allocations{0};
}
void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#endif

namespace tactus::precompute {
namespace {

Vec3 smooth_field(const Vec3& x) {
  return Vec3(std::sin(20 * x.x()) + x.y(), std::exp(5 * x.y()) * x.z(), 10 * x.x() * x.z() - 3 * x.y() * x.y());
}

Vec3 quadratic_field(const Vec3& x) {
  return Vec3(1 + 2 * x.x() - x.z() + 30 * x.x() * x.x(), 5 * x.x() * x.y() - 7 * x.z() * x.z(), x.y() * x.z());
}

/// A 6 x 6 x 6 space with spacing 1 cm whose forces sample `field` and whose two-node
/// "displacements" repeat the force.
template <class Field>
std::shared_ptr<Space> synthetic(Field field) {
  auto s = std::make_shared<Space>();
  s->grid.spacing = 0.01;
  s->grid.origin = Vec3(-0.02, -0.03, 0.0);
  s->grid.counts = {6, 6, 6};
  s->allocate(2);
  for (std::size_t p = 0; p < s->grid.size(); ++p) {
    s->status[p] = PointStatus::solved;
    s->force[p] = field(s->grid.point(p));
    s->displacement.col(static_cast<Eigen::Index>(p)) << s->force[p], 2.0 * s->force[p];
  }
  return s;
}

constexpr Interpolation kAll[] = {Interpolation::trilinear, Interpolation::rbf_cubic, Interpolation::rbf_thin_plate,
                                  Interpolation::polynomial};
constexpr Interpolation kInterpolating[] = {Interpolation::trilinear, Interpolation::rbf_cubic,
                                            Interpolation::rbf_thin_plate};

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
  double error[4] = {0, 0, 0, 0};
  for (int i = 0; i < 300; ++i) {
    // The interior, where every method has its full stencil.
    const Vec3 p = space->grid.origin + Vec3::Constant(0.01) + 0.03 * Vec3(u(rng), u(rng), u(rng));
    for (int k = 0; k < 4; ++k) {
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
  // Continuity: inside a cell every method is smooth; across a cell face trilinear is
  // continuous and the others (a new stencil on each side) jump by at most their error.
  for (auto m : kAll) {
    const Interpolator in(space, m);
    const Vec3 inside(0.0042, -0.0057, 0.0153);
    const Vec3 face(0.0, -0.0057, 0.0153);  // x = 0 is a grid plane
    const Vec3 d(1e-9, 0, 0);
    EXPECT_LT((in.force(inside + d).force - in.force(inside - d).force).norm(), 1e-6) << to_string(m);
    const double jump = (in.force(face + d).force - in.force(face - d).force).norm();
    EXPECT_LT(jump, m == Interpolation::trilinear ? 1e-6 : 0.05) << to_string(m);
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

#ifndef TACTUS_SANITIZED
TEST(Interpolator, ForceQueriesDoNotAllocate) {
  const auto space = synthetic(smooth_field);
  auto partial = synthetic(smooth_field);
  partial->status[partial->grid.index(3, 3, 3)] = PointStatus::failed;  // forces the small solve
  for (auto m : kAll) {
    const Interpolator a(space, m), b(partial, m);
    VecX shape(static_cast<Eigen::Index>(space->displacement.rows()));
    const long before = g_allocations.load();
    double sum = 0.0;
    for (int i = 0; i < 100; ++i) {
      const Vec3 p(0.001 * i - 0.03, 0.0004 * i, 0.035);
      sum += a.force(p).force.norm() + b.force(p).force.norm() + b.force(Vec3(0.015, 0.005, 0.035)).force.norm();
      sum += a.shape(p, shape).force.norm();
    }
    EXPECT_EQ(g_allocations.load(), before) << to_string(m);
    EXPECT_TRUE(std::isfinite(sum));
  }
}
#endif

}  // namespace
}  // namespace tactus::precompute
