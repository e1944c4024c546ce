#pragma once
// A material curve known at measured points (a fabric's tension against strain, shear force
// against shear angle, bending moment against curvature): a monotone cubic through the
// points (Fritsch–Carlson), so it never wiggles between measurements and its slope, which
// the implicit solver needs, is continuous. Beyond the last point it goes on along its
// end tangent; below zero it is mirrored (shear and bending act alike both ways) or
// continues along a given slope (a fabric's feeble resistance to compression).
#include <string>
#include <vector>

namespace tactus::physics {

class MeasuredCurve {
 public:
  enum class BelowZero { mirror, linear };

  /// An empty curve: zero everywhere.
  MeasuredCurve() = default;
  /// x strictly increasing from 0, y non-decreasing from 0 (at least two points). Below zero:
  /// mirror (value(−x) = −value(x)) or linear with `below_slope` (≥ 0). Throws InputError
  /// naming `what` and the offending point.
  MeasuredCurve(std::vector<double> x, std::vector<double> y, BelowZero below, double below_slope,
                const std::string& what);
  /// The straight line value = slope·x (mirrored below zero).
  static MeasuredCurve line(double slope, const std::string& what);

  [[nodiscard]] double value(double x) const;
  [[nodiscard]] double slope(double x) const;
  /// ∫0^x value: the energy density of the curve's law.
  [[nodiscard]] double integral(double x) const;

  [[nodiscard]] const std::vector<double>& xs() const { return x_; }
  [[nodiscard]] const std::vector<double>& ys() const { return y_; }
  [[nodiscard]] bool empty() const { return x_.empty(); }

 private:
  struct Piece {
    double value, slope, integral;
  };
  [[nodiscard]] Piece at(double x) const;  // x ≥ 0

  std::vector<double> x_, y_, tangent_, cumulative_;  // cumulative_[k] = ∫0^x_k
  BelowZero below_ = BelowZero::mirror;
  double below_slope_ = 0.0;
};

}  // namespace tactus::physics
