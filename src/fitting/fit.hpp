#pragma once
// Fitting an experiment's free material parameters to its measured curve: Levenberg–
// Marquardt (Eigen's unsupported LevenbergMarquardt, MINPACK's lmder) on the misfit of the
// engine's forward model, in transformed coordinates that keep each parameter in its range
// (log for moduli and times, logit for Prony weights and ν), with a forward-difference
// Jacobian; the uncertainty from the covariance σ² (JᵀJ)⁻¹ at the optimum (docs/fitting.md).
#include <span>
#include <string>
#include <vector>

#include "fitting/experiment.hpp"
#include "fitting/indentation.hpp"

namespace tactus::fitting {

/// Relative step of the forward-difference Jacobian in the transformed coordinates (a
/// log-modulus moves by 1e-4, i.e. 0.01 %): far above the static solve's tolerance (1e-10
/// of the forces), small against the curvature of the misfit.
inline constexpr double kJacobianStep = 1e-4;
/// Singular values of the Jacobian below this share of the largest count as zero: the forward
/// differences carry errors of about the step (1e-4) times the misfit's curvature.
inline constexpr double kSingularRatio = 1e-3;

/// One experiment's share of a (joint) fit.
struct ExperimentFit {
  std::vector<double> model;  ///< the forward model at the optimum, at its data's abscissae
  double rms = 0.0;           ///< root-mean-square residual [its curve's unit]
  double relative_rms = 0.0;  ///< rms / max |its data|
  double r_squared = 0.0;
};

struct FitResult {
  std::vector<std::string> names;   ///< every parameter, in the experiment's order
  std::vector<double> initial;      ///< starting values (given or the analytic guess)
  std::vector<double> values;       ///< at the optimum (fixed ones as given)
  std::vector<double> sigma;        ///< one standard deviation; 0 for fixed parameters
  std::vector<bool> free;
  std::vector<double> model;        ///< the (first) experiment's forward model at the optimum
  double rms = 0.0;                 ///< root-mean-square residual [the (first) curve's unit]
  double relative_rms = 0.0;        ///< over every experiment: rms of the residuals / max |data|
  double r_squared = 0.0;           ///< the (first) experiment's 1 − SS_res / SS_tot
  std::vector<ExperimentFit> experiments;  ///< per experiment, in the order given
  /// Combinations the data do not determine: per null direction of the Jacobian, the free
  /// parameters along it (their σ is infinite). Empty when every free parameter is determined.
  std::vector<std::string> undetermined;
  int iterations = 0;
  int evaluations = 0;              ///< forward-model runs
  bool converged = false;
  std::string status;               ///< the optimizer's stopping reason
  std::string guess_method;         ///< how the initial guess was made
};

/// The analytic initial guess of the free parameters without a given value (Hertz for a
/// sphere, Sneddon for a flat punch on a half-space, an exponential for relaxation);
/// returns every parameter's starting value and says how in `method`.
std::vector<double> initial_guess(const Experiment& e, std::string& method);

FitResult fit(const Experiment& e, const IndentationModel& model);
/// A joint fit: one material for several experiments (the same law and parameters, free and
/// fixed alike; InputError naming the one that differs), each experiment's residuals scaled
/// by its own largest value; the initial guess from the first.
FitResult fit(std::span<const Experiment* const> experiments, std::span<const IndentationModel* const> models);

/// The fitted material as a scene's [materials.NAME] block (docs/scene-format.md).
std::string material_toml(const Experiment& e, const FitResult& r, const std::string& name);
/// A human-readable summary: each parameter with its uncertainty, the residual, the effort.
std::string summary(const Experiment& e, const FitResult& r);
/// The same for a joint fit: a residual line per experiment.
std::string summary(std::span<const Experiment* const> experiments, const FitResult& r);

}  // namespace tactus::fitting
