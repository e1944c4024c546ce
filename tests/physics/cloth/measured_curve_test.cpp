// The measured curve: through its points, monotone between them, its slope and integral the
// derivative and antiderivative of its value, and bad data refused by point.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "physics/cloth/measured_curve.hpp"

namespace tactus::physics {
namespace {

MeasuredCurve stepped() {
  // A curve with a plateau, where an unconstrained cubic spline overshoots.
  return MeasuredCurve({0.0, 0.01, 0.02, 0.03, 0.05}, {0.0, 1.0, 1.0, 20.0, 100.0}, MeasuredCurve::BelowZero::linear,
                       5.0, "test curve");
}

TEST(MeasuredCurve, PassesThroughItsPointsAndNeverDecreases) {
  const auto c = stepped();
  for (std::size_t k = 0; k < c.xs().size(); ++k) EXPECT_DOUBLE_EQ(c.value(c.xs()[k]), c.ys()[k]);
  double previous = c.value(0.0);
  for (int k = 1; k <= 1000; ++k) {
    const double x = 0.06 * k / 1000.0, y = c.value(x);
    EXPECT_GE(y, previous - 1e-12) << "at x = " << x;
    previous = y;
  }
  // On the plateau it stays flat: no overshoot above 1 between 0.01 and 0.02.
  for (double x = 0.01; x <= 0.02; x += 1e-4) EXPECT_LE(c.value(x), 1.0 + 1e-12);
}

TEST(MeasuredCurve, SlopeAndIntegralMatchDifferencesAndQuadrature) {
  const auto c = stepped();
  for (double x : {-0.004, 0.003, 0.015, 0.027, 0.041, 0.07}) {
    const double h = 1e-7;
    EXPECT_NEAR(c.slope(x), (c.value(x + h) - c.value(x - h)) / (2 * h), 1e-5 * (1.0 + std::abs(c.slope(x)))) << x;
    // Simpson's rule on a fine grid, against the closed form.
    const int n = 2000;
    double sum = c.value(0.0) + c.value(x);
    for (int k = 1; k < n; ++k) sum += (k % 2 ? 4.0 : 2.0) * c.value(x * k / n);
    EXPECT_NEAR(c.integral(x), sum * x / (3.0 * n), 1e-9 * (1.0 + std::abs(c.integral(x)))) << x;
  }
}

TEST(MeasuredCurve, ContinuesAlongItsEndTangentAndBelowZeroAsAsked) {
  const auto c = stepped();
  const double end = c.xs().back(), slope = c.slope(end);
  EXPECT_NEAR(c.value(end + 0.01), c.ys().back() + 0.01 * slope, 1e-9);
  EXPECT_DOUBLE_EQ(c.value(-0.01), -0.05);  // linear, slope 5
  const auto m = MeasuredCurve({0.0, 1.0, 2.0}, {0.0, 1.0, 3.0}, MeasuredCurve::BelowZero::mirror, 0.0, "mirrored");
  EXPECT_DOUBLE_EQ(m.value(-1.5), -m.value(1.5));
  EXPECT_DOUBLE_EQ(m.integral(-1.5), m.integral(1.5));
}

TEST(MeasuredCurve, RefusesCurvesThatAreNotMonotoneNamingThePoint) {
  try {
    MeasuredCurve({0.0, 0.01, 0.02}, {0.0, 2.0, 1.5}, MeasuredCurve::BelowZero::linear, 0.0, "fabric 'denim' warp");
    FAIL() << "accepted a decreasing curve";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'denim' warp: not monotone: point 3"), std::string::npos) << e.what();
  }
  EXPECT_THROW(MeasuredCurve({0.0, 0.0}, {0.0, 1.0}, MeasuredCurve::BelowZero::linear, 0.0, "x"), InputError);
  EXPECT_THROW(MeasuredCurve({0.1, 0.2}, {0.0, 1.0}, MeasuredCurve::BelowZero::linear, 0.0, "x"), InputError);
  EXPECT_THROW(MeasuredCurve({0.0, 0.2}, {0.0, NAN}, MeasuredCurve::BelowZero::linear, 0.0, "x"), InputError);
  EXPECT_THROW(MeasuredCurve({0.0}, {0.0}, MeasuredCurve::BelowZero::linear, 0.0, "x"), InputError);
}

}  // namespace
}  // namespace tactus::physics
