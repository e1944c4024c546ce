#include "fitting/fit.hpp"

#include <fmt/format.h>

#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <numeric>
#include <span>
#include <stdexcept>
#include <unsupported/Eigen/NonLinearOptimization>

#include "contact/hertz.hpp"
#include "core/error.hpp"

namespace tactus::fitting {
namespace {

/// How a parameter maps to the unconstrained coordinate the optimizer moves.
enum class Transform { log, logit, poisson };

Transform transform_of(const std::string& name) {
  if (name == "poisson_ratio") return Transform::poisson;
  if (name.front() == 'g') return Transform::logit;
  return Transform::log;
}

double to_free(Transform t, double v) {
  switch (t) {
    case Transform::log: return std::log(v);
    case Transform::logit: return std::log(v / (1.0 - v));
    case Transform::poisson: {
      const double s = (v + 1.0) / 1.5;  // ν in (−1, 0.5) ↔ s in (0, 1)
      return std::log(s / (1.0 - s));
    }
  }
  return v;
}

double from_free(Transform t, double p) {
  const double s = 1.0 / (1.0 + std::exp(-p));
  switch (t) {
    case Transform::log: return std::exp(p);
    case Transform::logit: return s;
    case Transform::poisson: return -1.0 + 1.5 * s;
  }
  return p;
}

/// dθ/dp at the coordinate p: the delta method's factor for the uncertainty.
double slope(Transform t, double p) {
  const double s = 1.0 / (1.0 + std::exp(-p));
  switch (t) {
    case Transform::log: return std::exp(p);
    case Transform::logit: return s * (1.0 - s);
    case Transform::poisson: return 1.5 * s * (1.0 - s);
  }
  return 1.0;
}

/// The misfit for Eigen's Levenberg–Marquardt: the residuals (model − data) / max |data| of
/// every experiment, one after the other, as functions of the free coordinates (shared by
/// the experiments), and their forward-difference Jacobian.
class Misfit {
 public:
  Misfit(std::span<const Experiment* const> experiments, std::span<const IndentationModel* const> models,
         std::vector<double> start)
      : experiments_(experiments.begin(), experiments.end()),
        models_(models.begin(), models.end()),
        e_(*experiments.front()),
        values_(std::move(start)) {
    for (std::size_t i = 0; i < e_.parameters.size(); ++i)
      if (e_.parameters[i].free) free_.push_back(i);
    for (const Experiment* x : experiments_) {
      double scale = 0.0;
      for (double y : x->y) scale = std::max(scale, std::abs(y));
      scales_.push_back(scale == 0.0 ? 1.0 : scale);
      count_ += x->y.size();
    }
  }

  [[nodiscard]] int values() const { return static_cast<int>(count_); }
  [[nodiscard]] int inputs() const { return static_cast<int>(free_.size()); }

  [[nodiscard]] Eigen::VectorXd coordinates() const {
    Eigen::VectorXd p(inputs());
    for (std::size_t k = 0; k < free_.size(); ++k)
      p[static_cast<Eigen::Index>(k)] = to_free(transform_of(e_.parameters[free_[k]].name), values_[free_[k]]);
    return p;
  }
  [[nodiscard]] std::vector<double> parameters(const Eigen::VectorXd& p) const {
    std::vector<double> v = values_;
    for (std::size_t k = 0; k < free_.size(); ++k)
      v[free_[k]] = from_free(transform_of(e_.parameters[free_[k]].name), p[static_cast<Eigen::Index>(k)]);
    return v;
  }
  [[nodiscard]] const std::vector<std::size_t>& free() const { return free_; }
  [[nodiscard]] double scale(std::size_t experiment) const { return scales_[experiment]; }
  [[nodiscard]] int evaluations() const { return evaluations_; }

  /// Experiment k's forward-model curve at p; empty where the solve fails (an unreachable
  /// material).
  std::vector<double> curve(const Eigen::VectorXd& p, std::size_t k) const {
    ++evaluations_;
    try {
      const physics::FemMaterial m = make_material(*experiments_[k], parameters(p));
      m.validate();
      return models_[k]->curve(m);
    } catch (const std::exception&) {
      return {};
    }
  }

  int operator()(const Eigen::VectorXd& p, Eigen::VectorXd& r) const {
    // The optimizer asks for the Jacobian where it has just evaluated the residuals.
    if (last_p_.size() == p.size() && last_p_ == p) {
      r = last_r_;
      return 0;
    }
    r.resize(values());
    Eigen::Index row = 0;
    for (std::size_t k = 0; k < experiments_.size(); ++k) {
      const auto c = curve(p, k);
      const std::vector<double>& y = experiments_[k]->y;
      for (std::size_t i = 0; i < y.size(); ++i, ++row) r[row] = c.empty() ? 1e3 : (c[i] - y[i]) / scales_[k];
    }
    last_p_ = p;
    last_r_ = r;
    return 0;
  }

  int df(const Eigen::VectorXd& p, Eigen::MatrixXd& j) const {
    Eigen::VectorXd r0, r1;
    (*this)(p, r0);
    j.resize(values(), inputs());
    for (Eigen::Index k = 0; k < p.size(); ++k) {
      Eigen::VectorXd q = p;
      const double h = kJacobianStep * std::max(1.0, std::abs(p[k]));
      q[k] += h;
      (*this)(q, r1);
      j.col(k) = (r1 - r0) / h;
    }
    return 0;
  }

 private:
  std::vector<const Experiment*> experiments_;
  std::vector<const IndentationModel*> models_;
  const Experiment& e_;  ///< the first: its parameters are every experiment's
  std::vector<double> values_;  ///< every parameter; the free ones are overwritten from p
  std::vector<std::size_t> free_;
  std::vector<double> scales_;  ///< per experiment: max |data|
  std::size_t count_ = 0;
  mutable int evaluations_ = 0;
  mutable Eigen::VectorXd last_p_, last_r_;
};

std::string status_text(int status) {
  switch (status) {
    case 1: return "relative reduction of the misfit below ftol";
    case 2: return "relative change of the parameters below xtol";
    case 3: return "misfit and parameters both converged";
    case 4: return "residuals orthogonal to the Jacobian's columns";
    case 5: return "too many evaluations (fit.max_iterations)";
    case 6: return "ftol too small: no further reduction possible";
    case 7: return "xtol too small: no further improvement possible";
    case 8: return "gtol too small";
    default: return fmt::format("stopped (status {})", status);
  }
}

}  // namespace

std::vector<double> initial_guess(const Experiment& e, std::string& method) {
  std::vector<double> v;
  for (const auto& p : e.parameters) v.push_back(p.value.value_or(std::numeric_limits<double>::quiet_NaN()));
  auto at = [&](const char* name) -> double& {
    for (std::size_t i = 0; i < e.parameters.size(); ++i)
      if (e.parameters[i].name == name) return v[i];
    throw std::logic_error(name);
  };
  auto unset = [&](const char* name) { return e.find(name) && !e.find(name)->value; };

  // The plane-strain modulus E* = E / (1 − ν²) from the loading curve: least squares of
  // F = E*·shape(d). On the generated block (a layer of thickness h on a rigid base): for a
  // sphere Hertz's (4/3)√R d^{3/2} times Dimitriadis's stiffening (bonded or sliding base);
  // for a flat punch Sneddon's 2 a d times Hayes's κ(ν, a/h) on a bonded base, Sneddon's
  // alone on a sliding one (κ is computed for a bonded base only). On a specimen mesh, the
  // half-space laws. A relaxation uses its peak force at the held depth, a creep the held
  // force at its first depth after the ramp.
  const double nu = e.mass_spring ? 0.25  // a spring network's, at best (Cauchy's relation)
                   : e.find("poisson_ratio") && e.find("poisson_ratio")->value ? *e.find("poisson_ratio")->value
                                                                                : 0.45;
  const double r = e.indenter.radius;
  const bool sphere = e.indenter.round();
  const bool bonded = e.specimen.bottom == Support::fixed;
  const bool block = e.specimen.mesh.empty() && e.specimen.thickness > 0.0;
  const bool layer = block && (sphere || bonded);
  // κ is tabulated up to a/h = 20; a thinner layer's guess is still far closer than Sneddon's.
  const double punch_factor =
      layer && !sphere ? contact::punch_layer_factor(nu, std::min(r / e.specimen.thickness, 20.0)) : 1.0;
  auto shape = [&](double d) {
    if (!sphere) return 2.0 * r * d * punch_factor;
    const double chi = std::sqrt(r * d) / e.specimen.thickness;
    return contact::hertz_force(1.0, r, d) * (layer ? contact::layer_stiffening(nu, chi, bonded) : 1.0);
  };
  // A fingerpad takes its share of each depth first (in series: its compression at the
  // measured force); a finger's compliance is taken off the fitted one after (Hertz's two
  // bodies add compliances).
  const Indenter& finger = e.indenter;
  const contact::FingerpadLaw pad(finger.pad);
  auto tissue_depth = [&](std::size_t i) {
    if (finger.shape != IndenterShape::fingerpad) return e.x[i];
    return std::max(e.x[i] - pad.depth(e.y[i]), 1e-3 * e.x[i]);
  };
  double e_star = 0.0;
  if (e.kind == CurveKind::depth_force) {
    double num = 0.0, den = 0.0;
    for (std::size_t i = 0; i < e.x.size(); ++i) {
      num += e.y[i] * shape(tissue_depth(i));
      den += shape(tissue_depth(i)) * shape(tissue_depth(i));
    }
    e_star = num / den;
    if (finger.shape == IndenterShape::finger) {
      const double c_finger = contact::contact_compliance(finger.finger);
      // A curve stiffer than the finger itself leaves nothing for the tissue: keep the
      // rigid-sphere guess and let the optimizer walk.
      if (1.0 / e_star > c_finger) e_star = 1.0 / (1.0 / e_star - c_finger);
    }
  } else if (e.kind == CurveKind::time_force) {
    e_star = *std::max_element(e.y.begin(), e.y.end()) / shape(e.hold.value);
  } else {
    const auto first = std::lower_bound(e.x.begin(), e.x.end(), e.hold.ramp_time);
    const double d0 = e.y[static_cast<std::size_t>(std::min(first, e.x.end() - 1) - e.x.begin())];
    e_star = e.hold.value / shape(d0);
  }
  const char* finger_note = finger.shape == IndenterShape::finger      ? ", less the finger's compliance"
                            : finger.shape == IndenterShape::fingerpad ? ", less the fingerpad's compression"
                                                                       : "";
  method = !layer   ? (sphere  ? "Hertz (sphere on a half-space)"
                       : block ? "Sneddon (flat punch on a half-space; no layer factor for a sliding base)"
                               : "Sneddon (flat punch on a half-space)")
           : sphere ? fmt::format("Hertz with Dimitriadis's layer stiffening (sphere on a {:g} mm layer {} its base)",
                                  1e3 * e.specimen.thickness, bonded ? "bonded to" : "sliding on")
                    : fmt::format("Sneddon with Hayes's layer factor {:.3f} (flat punch, a/h = {:.3g}, on a {:g} mm "
                                  "layer bonded to its base)",
                                  punch_factor, r / e.specimen.thickness, 1e3 * e.specimen.thickness);
  method += finger_note;
  const double young = e_star * (1.0 - nu * nu);
  if (unset("young_modulus")) at("young_modulus") = young;
  const double mu = young / (2.0 * (1.0 + nu)), kappa = young / (3.0 * (1.0 - 2.0 * nu));
  if (unset("mu")) at("mu") = mu;
  if (unset("kappa")) at("kappa") = kappa;
  if (e.find("c10")) {
    const bool c01_free = e.find("c01")->free;
    if (unset("c10")) at("c10") = c01_free ? 0.25 * mu : std::max(0.5 * mu - at("c01"), 0.05 * mu);
    if (c01_free && at("c01") <= 0.0) at("c01") = 0.25 * mu;
  }
  if (e.prony_terms > 0) {
    // One exponential through the hold. Relaxation: g = 1 − F_end / F_peak, τ where the force
    // has fallen by 1 − 1/e of its drop. Creep: the elastic force F_e ∝ d^n (n = 1.5 sphere,
    // 1 punch) rises by 1/g_inf, so g = 1 − (d_0 / d_end)^n, and the creep's time constant
    // is τ / g_inf. Several terms share g and spread τ by decades.
    double g_total = 0.0, tau = 0.0;
    if (e.kind == CurveKind::time_force) {
      const auto peak = std::max_element(e.y.begin(), e.y.end());
      const double f_peak = *peak, f_end = e.y.back();
      g_total = std::clamp(1.0 - f_end / f_peak, 0.05, 0.9);
      const double target = f_end + (f_peak - f_end) / std::exp(1.0);
      auto i = static_cast<std::size_t>(peak - e.y.begin());
      while (i + 1 < e.y.size() && e.y[i] > target) ++i;
      const double t_peak = e.x[static_cast<std::size_t>(peak - e.y.begin())];
      tau = std::max(e.x[i] - t_peak, 1e-3 * (e.x.back() - e.x.front()));
    } else {
      const auto first = static_cast<std::size_t>(
          std::min(std::lower_bound(e.x.begin(), e.x.end(), e.hold.ramp_time), e.x.end() - 1) - e.x.begin());
      const double d0 = e.y[first], d_end = e.y.back();
      const double power = e.indenter.round() ? 1.5 : 1.0;
      g_total = std::clamp(1.0 - std::pow(d0 / d_end, power), 0.05, 0.9);
      const double target = d_end - (d_end - d0) / std::exp(1.0);
      std::size_t i = first;
      while (i + 1 < e.y.size() && e.y[i] < target) ++i;
      tau = std::max(e.x[i] - e.x[first], 1e-3 * (e.x.back() - e.x.front())) * (1.0 - g_total);
    }
    for (std::size_t t = 0; t < e.prony_terms; ++t) {
      const std::string n = std::to_string(t + 1);
      const double spread = std::pow(10.0, static_cast<double>(t) - 0.5 * static_cast<double>(e.prony_terms - 1));
      if (unset(("g" + n).c_str())) at(("g" + n).c_str()) = g_total / static_cast<double>(e.prony_terms);
      if (unset(("tau" + n).c_str())) at(("tau" + n).c_str()) = tau * spread;
    }
    method += ", one exponential through the hold";
  }
  return v;
}

FitResult fit(const Experiment& e, const IndentationModel& model) {
  const Experiment* experiments[] = {&e};
  const IndentationModel* models[] = {&model};
  return fit(experiments, models);
}

FitResult fit(std::span<const Experiment* const> experiments, std::span<const IndentationModel* const> models) {
  if (experiments.empty() || experiments.size() != models.size())
    throw std::invalid_argument("fit: one model per experiment, at least one");
  const Experiment& e = *experiments.front();
  // One material for every experiment: the same law, parameters and free set.
  for (const Experiment* x : experiments.subspan(1)) {
    const SourceLocation where{x->file.string(), {}, {}, {}};
    if (x->model_name() != e.model_name())
      throw InputError(where, fmt::format("a joint fit needs one law: this experiment's is {}, {}'s is {}",
                                          x->model_name(), e.file.string(), e.model_name()));
    bool same = x->parameters.size() == e.parameters.size();
    for (std::size_t i = 0; same && i < e.parameters.size(); ++i)
      same = x->parameters[i].name == e.parameters[i].name && x->parameters[i].free == e.parameters[i].free &&
             (x->parameters[i].free || x->parameters[i].value == e.parameters[i].value);
    if (!same)
      throw InputError(where, fmt::format("a joint fit needs the same parameters, free and fixed alike, in every "
                                          "experiment: these differ from {}'s",
                                          e.file.string()));
  }
  FitResult out;
  out.initial = initial_guess(e, out.guess_method);
  for (const auto& p : e.parameters) {
    out.names.push_back(p.name);
    out.free.push_back(p.free);
  }
  Misfit misfit(experiments, models, out.initial);
  if (misfit.values() < misfit.inputs())
    throw InputError(SourceLocation{e.data_file.string(), {}, {}, {}},
                     fmt::format("{} data points cannot determine {} free parameters", misfit.values(), misfit.inputs()));

  Eigen::VectorXd p = misfit.coordinates();
  Eigen::LevenbergMarquardt<Misfit> lm(misfit);
  lm.parameters.maxfev = e.max_iterations;
  lm.parameters.ftol = 1e-10;
  lm.parameters.xtol = 1e-8;
  const int status = lm.minimize(p);
  out.iterations = static_cast<int>(lm.iter);
  out.status = status_text(status);
  out.converged = status >= 1 && status <= 4;
  out.values = misfit.parameters(p);

  // Residual and covariance at the optimum: σ² = SSR / (n − p), cov = σ² (JᵀJ)⁻¹ in the
  // free coordinates, carried to the parameters by the transforms' slopes (delta method).
  Eigen::VectorXd r;
  misfit(p, r);
  Eigen::MatrixXd j;
  misfit.df(p, j);
  const auto n = static_cast<double>(r.size()), k = static_cast<double>(p.size());
  const double ssr = r.squaredNorm();
  const double sigma2 = n > k ? ssr / (n - k) : 0.0;
  const Eigen::MatrixXd jtj = j.transpose() * j;
  const Eigen::MatrixXd cov = sigma2 * jtj.completeOrthogonalDecomposition().pseudoInverse();
  out.sigma.assign(e.parameters.size(), 0.0);
  for (std::size_t f = 0; f < misfit.free().size(); ++f) {
    const std::size_t i = misfit.free()[f];
    const auto fi = static_cast<Eigen::Index>(f);
    out.sigma[i] = std::abs(slope(transform_of(e.parameters[i].name), p[fi])) * std::sqrt(std::max(cov(fi, fi), 0.0));
  }
  // Data that fix only a combination of the free parameters (one straight loading line for E
  // and ν) leave J's columns dependent: the pseudo-inverse would then report the spread along
  // the determined direction alone, a small σ for values the data cannot tell apart. Where J
  // is singular to the Jacobian's own accuracy, the parameters along its null directions get
  // an infinite σ and the result says which.
  if (p.size() > 1) {
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(j, Eigen::ComputeFullV);
    const Eigen::VectorXd& s = svd.singularValues();
    for (Eigen::Index c = 0; c < s.size(); ++c) {
      if (s[c] > kSingularRatio * s[0]) continue;
      std::string which;
      for (std::size_t f = 0; f < misfit.free().size(); ++f)
        if (std::abs(svd.matrixV()(static_cast<Eigen::Index>(f), c)) > 0.05) {
          const std::size_t i = misfit.free()[f];
          out.sigma[i] = std::numeric_limits<double>::infinity();
          which += (which.empty() ? "" : ", ") + e.parameters[i].name;
        }
      out.undetermined.push_back(which);
    }
  }
  // Per experiment: its curve at the optimum, its RMS (in its unit) and R²; the first
  // experiment's are the result's own fields.
  Eigen::Index row = 0;
  for (std::size_t x = 0; x < experiments.size(); ++x) {
    const std::vector<double>& y = experiments[x]->y;
    std::vector<double> curve = misfit.curve(p, x);
    if (curve.empty()) throw std::runtime_error("the forward model fails at the fitted parameters");
    const auto m = static_cast<Eigen::Index>(y.size());
    const double part = r.segment(row, m).squaredNorm();
    row += m;
    const double mean = std::accumulate(y.begin(), y.end(), 0.0) / static_cast<double>(m);
    double ss_tot = 0.0;
    for (double v : y) ss_tot += (v - mean) * (v - mean);
    const double s = misfit.scale(x);
    out.experiments.push_back({std::move(curve), std::sqrt(part / static_cast<double>(m)) * s,
                               std::sqrt(part / static_cast<double>(m)),
                               ss_tot > 0.0 ? 1.0 - part * s * s / ss_tot : 1.0});
  }
  out.model = out.experiments.front().model;
  out.rms = out.experiments.front().rms;
  out.relative_rms = std::sqrt(ssr / n);
  out.r_squared = out.experiments.front().r_squared;
  out.evaluations = misfit.evaluations();
  return out;
}

std::string material_toml(const Experiment& e, const FitResult& r, const std::string& name) {
  std::string s = fmt::format("[materials.{}]\nmodel = \"{}\"\n", name, e.model_name());
  auto line = [&](std::size_t i) {
    s += fmt::format("{} = {:.6g}", r.names[i], r.values[i]);
    if (r.free[i]) s += fmt::format("  # fitted, ± {:.3g} (1σ)", r.sigma[i]);
    s += "\n";
  };
  for (std::size_t i = 0; i < r.names.size(); ++i)
    if (r.names[i].front() != 'g' && r.names[i].rfind("tau", 0) != 0) line(i);
  s += fmt::format("density = {:.6g}\n", e.density);
  if (e.prony_terms > 0) {
    s += fmt::format("[materials.{}.viscoelastic]\nmodel = \"prony\"\nterms = [\n", name);
    for (std::size_t t = 0; t < e.prony_terms; ++t) {
      const std::size_t g = r.names.size() - 2 * e.prony_terms + 2 * t;
      s += fmt::format("  {{ g = {:.6g}, tau = {:.6g} }},  # ± {:.3g}, ± {:.3g} s\n", r.values[g], r.values[g + 1],
                       r.sigma[g], r.sigma[g + 1]);
    }
    s += "]\n";
  }
  return s;
}

std::string summary(const Experiment& e, const FitResult& r) {
  const Experiment* experiments[] = {&e};
  return summary(experiments, r);
}

std::string summary(std::span<const Experiment* const> experiments, const FitResult& r) {
  std::string s;
  for (std::size_t i = 0; i < r.names.size(); ++i) {
    if (r.free[i])
      s += fmt::format("  {:<14} {:>12.6g} ± {:<10.3g} ({:.2f} %)  start {:.6g}\n", r.names[i], r.values[i], r.sigma[i],
                       100.0 * r.sigma[i] / std::abs(r.values[i]), r.initial[i]);
    else
      s += fmt::format("  {:<14} {:>12.6g} (fixed)\n", r.names[i], r.values[i]);
  }
  for (std::size_t k = 0; k < experiments.size() && k < r.experiments.size(); ++k) {
    const ExperimentFit& x = r.experiments[k];
    const char* unit = experiments[k]->kind == CurveKind::time_depth ? "m" : "N";
    s += fmt::format("  residual{}: RMS {:.4g} {} ({:.3f} % of the largest value), R² {:.6f}\n",
                     experiments.size() > 1 ? fmt::format(" of {}", experiments[k]->file.string()) : std::string(),
                     x.rms, unit, 100.0 * x.relative_rms, x.r_squared);
  }
  s += fmt::format("  {} iterations, {} forward runs; {}; initial guess: {}\n", r.iterations, r.evaluations, r.status,
                   r.guess_method);
  for (const std::string& which : r.undetermined)
    s += fmt::format("  not determined by these data: {} (only a combination of them is; fix one, or fit several "
                     "experiments together)\n",
                     which);
  return s;
}

}  // namespace tactus::fitting
