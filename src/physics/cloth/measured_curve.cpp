#include "physics/cloth/measured_curve.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::physics {

MeasuredCurve::MeasuredCurve(std::vector<double> x, std::vector<double> y, BelowZero below, double below_slope,
                             const std::string& what)
    : x_(std::move(x)), y_(std::move(y)), below_(below), below_slope_(below_slope) {
  if (x_.size() != y_.size()) throw InputError(what + ": " + std::to_string(x_.size()) + " abscissae but " +
                                               std::to_string(y_.size()) + " values");
  if (x_.size() < 2) throw InputError(what + ": needs at least two points");
  for (std::size_t k = 0; k < x_.size(); ++k)
    if (!std::isfinite(x_[k]) || !std::isfinite(y_[k]))
      throw InputError(what + ": point " + std::to_string(k + 1) + " is not finite");
  if (x_[0] != 0.0 || y_[0] != 0.0) throw InputError(what + ": the first point must be (0, 0)");
  for (std::size_t k = 1; k < x_.size(); ++k) {
    if (!(x_[k] > x_[k - 1]))
      throw InputError(fmt::format("{}: abscissa of point {} ({:g}) does not increase", what, k + 1, x_[k]));
    if (y_[k] < y_[k - 1])
      throw InputError(fmt::format("{}: not monotone: point {} ({:g}) is below point {} ({:g})", what, k + 1, y_[k], k,
                                   y_[k - 1]));
  }
  if (!(below_slope_ >= 0.0 && std::isfinite(below_slope_)))
    throw InputError(what + ": the slope below zero must be finite and >= 0");

  // Fritsch–Carlson tangents: the mean of the neighbouring secants, zero at a flat segment or
  // a local extremum, scaled so that no cubic overshoots.
  const std::size_t n = x_.size();
  std::vector<double> secant(n - 1);
  for (std::size_t k = 0; k + 1 < n; ++k) secant[k] = (y_[k + 1] - y_[k]) / (x_[k + 1] - x_[k]);
  tangent_.assign(n, 0.0);
  tangent_[0] = secant[0];
  tangent_[n - 1] = secant[n - 2];
  for (std::size_t k = 1; k + 1 < n; ++k)
    tangent_[k] = secant[k - 1] * secant[k] <= 0.0 ? 0.0 : 0.5 * (secant[k - 1] + secant[k]);
  for (std::size_t k = 0; k + 1 < n; ++k) {
    if (secant[k] == 0.0) {
      tangent_[k] = tangent_[k + 1] = 0.0;
      continue;
    }
    const double a = tangent_[k] / secant[k], b = tangent_[k + 1] / secant[k];
    const double r = a * a + b * b;
    if (r > 9.0) {
      const double tau = 3.0 / std::sqrt(r);
      tangent_[k] = tau * a * secant[k];
      tangent_[k + 1] = tau * b * secant[k];
    }
  }
  cumulative_.assign(n, 0.0);
  for (std::size_t k = 0; k + 1 < n; ++k) {
    // ∫ of the Hermite cubic over its whole segment.
    const double h = x_[k + 1] - x_[k];
    cumulative_[k + 1] = cumulative_[k] + h * (0.5 * (y_[k] + y_[k + 1]) + h * (tangent_[k] - tangent_[k + 1]) / 12.0);
  }
}

MeasuredCurve MeasuredCurve::line(double slope, const std::string& what) {
  if (!(slope >= 0.0 && std::isfinite(slope))) throw InputError(what + ": the slope must be finite and >= 0");
  return MeasuredCurve({0.0, 1.0}, {0.0, slope}, BelowZero::mirror, 0.0, what);
}

MeasuredCurve::Piece MeasuredCurve::at(double x) const {
  const std::size_t n = x_.size();
  if (x >= x_[n - 1]) {
    const double d = x - x_[n - 1];
    return {y_[n - 1] + tangent_[n - 1] * d, tangent_[n - 1], cumulative_[n - 1] + d * (y_[n - 1] + 0.5 * tangent_[n - 1] * d)};
  }
  const auto k = static_cast<std::size_t>(std::upper_bound(x_.begin(), x_.end(), x) - x_.begin()) - 1;
  const double h = x_[k + 1] - x_[k], t = (x - x_[k]) / h;
  const double y0 = y_[k], y1 = y_[k + 1], m0 = h * tangent_[k], m1 = h * tangent_[k + 1];
  const double t2 = t * t, t3 = t2 * t, t4 = t3 * t;
  const double value = (2 * t3 - 3 * t2 + 1) * y0 + (t3 - 2 * t2 + t) * m0 + (-2 * t3 + 3 * t2) * y1 + (t3 - t2) * m1;
  const double slope = ((6 * t2 - 6 * t) * y0 + (3 * t2 - 4 * t + 1) * m0 + (-6 * t2 + 6 * t) * y1 + (3 * t2 - 2 * t) * m1) / h;
  const double integral = h * ((0.5 * t4 - t3 + t) * y0 + (0.25 * t4 - 2.0 / 3.0 * t3 + 0.5 * t2) * m0 +
                               (-0.5 * t4 + t3) * y1 + (0.25 * t4 - t3 / 3.0) * m1);
  return {value, slope, cumulative_[k] + integral};
}

double MeasuredCurve::value(double x) const {
  if (x_.empty()) return 0.0;
  if (x >= 0.0) return at(x).value;
  return below_ == BelowZero::mirror ? -at(-x).value : below_slope_ * x;
}

double MeasuredCurve::slope(double x) const {
  if (x_.empty()) return 0.0;
  if (x >= 0.0) return at(x).slope;
  return below_ == BelowZero::mirror ? at(-x).slope : below_slope_;
}

double MeasuredCurve::integral(double x) const {
  if (x_.empty()) return 0.0;
  if (x >= 0.0) return at(x).integral;
  return below_ == BelowZero::mirror ? at(-x).integral : 0.5 * below_slope_ * x * x;
}

}  // namespace tactus::physics
