#pragma once
// Synthetic indentation experiments for the fitting tests: a block pressed by the forward
// model at known parameters, 2 % Gaussian noise (σ = 2 % of the curve's largest value,
// fixed seed), then fitted from the analytic initial guess.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "fitting/fit.hpp"

namespace tactus::fitting::test {

using physics::FemLaw;

inline Experiment block(IndenterShape shape, double radius, FemLaw law, double thickness, std::array<int, 3> cells) {
  Experiment e;
  e.file = "synthetic";
  e.indenter = {shape, radius};
  e.specimen.size = Vec2(0.03, 0.03);
  e.specimen.thickness = thickness;
  e.specimen.cells = cells;
  e.law = law;
  return e;
}

inline void add(Experiment& e, const std::string& name, std::optional<double> value, bool free) {
  e.parameters.push_back({name, value, free});
}

inline std::vector<double> steps(double last, int count) {
  std::vector<double> x;
  for (int i = 1; i <= count; ++i) x.push_back(last * i / count);
  return x;
}

/// Replaces the curve by the forward model's at `truth` plus noise; returns the fit.
inline FitResult recover(Experiment& e, const std::vector<double>& truth, unsigned seed = 28) {
  const IndentationModel model(e);
  const std::vector<double> clean = model.curve(make_material(e, truth));
  double peak = 0.0;
  for (double y : clean) peak = std::max(peak, std::abs(y));
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.02 * peak);
  e.y.clear();
  for (double y : clean) e.y.push_back(y + noise(rng));
  const FitResult r = fit(e, model);
  std::printf("%s", summary(e, r).c_str());
  return r;
}

/// Each free parameter within 3 reported σ of the truth and within `percent` of it.
inline void expect_recovered(const Experiment& e, const FitResult& r, const std::vector<double>& truth, double percent) {
  EXPECT_TRUE(r.converged) << r.status;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (!e.parameters[i].free) continue;
    SCOPED_TRACE(r.names[i]);
    EXPECT_GT(r.sigma[i], 0.0);
    EXPECT_LE(std::abs(r.values[i] - truth[i]), 3.0 * r.sigma[i]) << r.values[i] << " vs " << truth[i];
    EXPECT_LE(std::abs(r.values[i] - truth[i]), percent / 100.0 * std::abs(truth[i]));
  }
  // With noise of 2 % of the peak the relative RMS residual is about 2 % (a dozen points
  // estimate it to about ±0.4 %).
  EXPECT_GT(r.relative_rms, 0.008);
  EXPECT_LT(r.relative_rms, 0.035);
}

}  // namespace tactus::fitting::test
