#include "contact/hertz.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Dense>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::contact {
namespace {

bool positive_finite(double x) { return std::isfinite(x) && x > 0.0; }

/// Gauss–Legendre nodes and weights on [0, 1] (Golub–Welsch: the eigenvalues of the Jacobi
/// matrix and the squares of its eigenvectors' first components).
struct GaussLegendre {
  Eigen::VectorXd nodes, weights;
};
GaussLegendre gauss_legendre(int n) {
  Eigen::MatrixXd jacobi = Eigen::MatrixXd::Zero(n, n);
  for (int i = 1; i < n; ++i) jacobi(i, i - 1) = jacobi(i - 1, i) = i / std::sqrt(4.0 * i * i - 1.0);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(jacobi);
  return {0.5 * (eig.eigenvalues().array() + 1.0), eig.eigenvectors().row(0).transpose().array().square()};
}

}  // namespace

void validate(const ElasticMaterial& material, const char* who) {
  if (!positive_finite(material.youngs_modulus))
    throw InputError(fmt::format("{}: Young's modulus must be positive and finite, got {} Pa", who,
                                 material.youngs_modulus));
  // ν ≤ 0.5 keeps the bulk modulus non-negative; ν → −1 makes 1 − ν² vanish.
  if (!(material.poisson_ratio > -1.0 && material.poisson_ratio <= 0.5))
    throw InputError(fmt::format("{}: Poisson's ratio must be in (-1, 0.5], got {}", who, material.poisson_ratio));
}

double contact_compliance(const ElasticMaterial& material) noexcept {
  return (1.0 - material.poisson_ratio * material.poisson_ratio) / material.youngs_modulus;
}

double effective_modulus(const ElasticMaterial& a, const ElasticMaterial& b) noexcept {
  return 1.0 / (contact_compliance(a) + contact_compliance(b));
}

double layer_stiffening(double nu, double chi, bool bonded) noexcept {
  constexpr double pi = std::numbers::pi;
  const double a0 = bonded ? -(1.2876 - 1.4678 * nu + 1.3442 * nu * nu) / (1.0 - nu)
                           : -0.347 * (3.0 - 2.0 * nu) / (1.0 - nu);
  const double b0 = bonded ? (0.6387 - 1.0277 * nu + 1.5164 * nu * nu) / (1.0 - nu)
                           : 0.056 * (5.0 - 2.0 * nu) / (1.0 - nu);
  const double c1 = -2.0 * a0 / pi;
  const double c2 = 4.0 * a0 * a0 / (pi * pi);
  const double c3 = -8.0 / (pi * pi * pi) * (a0 * a0 * a0 + 4.0 * pi * pi / 15.0 * b0);
  const double c4 = 16.0 * a0 / (pi * pi * pi * pi) * (a0 * a0 * a0 + 3.0 * pi * pi / 5.0 * b0);
  return 1.0 + chi * (c1 + chi * (c2 + chi * (c3 + chi * c4)));
}

double punch_layer_factor(double nu, double a_over_h) {
  if (!(nu > -1.0 && nu <= 0.5))
    throw InputError(fmt::format("punch on a layer: Poisson's ratio must be in (-1, 0.5], got {}", nu));
  if (!(a_over_h >= 0.0 && a_over_h <= 20.0))
    throw InputError(fmt::format("punch on a layer: a/h must be in [0, 20], got {}", a_over_h));
  constexpr double pi = std::numbers::pi;
  // The layer's surface under a pressure of Hankel transform p(ξ) sinks by
  // w(ξ) = (1 − ν)/G · p(ξ)/ξ · (1 − M(ξh)), M → 0 deep (a half-space) and
  //   M(x) = (2k e^{−2x} + 1 + k² + 4x² + 4x) / (2k cosh 2x + 1 + k² + 4x²),  k = 3 − 4ν,
  // for a base that holds the layer's underside still. With p(ξ) = ∫₀ᵃ g(t) cos(ξt) dt, a
  // flat punch pressed by d makes g/g₀ = φ (g₀ = 2Gd / (π(1 − ν)), the half-space's) solve
  //   φ(σ) − (λ/π) ∫₀¹ φ(τ) [K(λ(σ − τ)) + K(λ(σ + τ))] dτ = 1,   K(v) = ∫₀^∞ M(η) cos(ηv) dη,
  // λ = a/h, and κ = ∫₀¹ φ(σ) dσ (the force is 2π·a·g₀·κ).
  const double k = 3.0 - 4.0 * nu;
  auto m = [k](double x) {
    return (2.0 * k * std::exp(-2.0 * x) + 1.0 + k * k + 4.0 * x * x + 4.0 * x) /
           (2.0 * k * std::cosh(2.0 * x) + 1.0 + k * k + 4.0 * x * x);
  };
  // Gauss–Legendre, 16 points a panel; M has fallen below 1e-18 at η = 25, and each panel
  // holds at most about one period of cos(ηv) for v ≤ 2λ.
  const GaussLegendre panel_rule = gauss_legendre(16);
  const double width = std::min(0.25, 1.0 / std::max(a_over_h, 1e-9));
  const auto panels = static_cast<std::size_t>(std::ceil(25.0 / width));
  std::vector<double> eta, weighted_m;
  for (std::size_t p = 0; p < panels; ++p)
    for (Eigen::Index i = 0; i < panel_rule.nodes.size(); ++i) {
      const double e = (static_cast<double>(p) + panel_rule.nodes[i]) * width;
      eta.push_back(e);
      weighted_m.push_back(width * panel_rule.weights[i] * m(e));
    }
  auto kernel = [&](double v) {
    double sum = 0.0;
    for (std::size_t i = 0; i < eta.size(); ++i) sum += weighted_m[i] * std::cos(eta[i] * v);
    return sum;
  };
  // Nyström on 64 nodes of [0, 1]: φ is smooth, and 160 nodes change κ by under 1e-10 up to
  // a/h = 16 and by 4e-6 at a/h = 20, ν = 0.5.
  const GaussLegendre rule = gauss_legendre(64);
  const Eigen::VectorXd& s = rule.nodes;
  const Eigen::VectorXd& ws = rule.weights;
  const Eigen::Index n = s.size();
  Eigen::MatrixXd a = Eigen::MatrixXd::Identity(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j <= i; ++j) {
      const double kij = a_over_h / pi * (kernel(a_over_h * (s[i] - s[j])) + kernel(a_over_h * (s[i] + s[j])));
      a(i, j) -= kij * ws[j];
      if (j != i) a(j, i) -= kij * ws[i];
    }
  const Eigen::VectorXd phi = a.partialPivLu().solve(Eigen::VectorXd::Ones(n));
  return ws.dot(phi);
}

double hertz_force(double effective_modulus, double effective_radius, double depth) noexcept {
  if (!(depth > 0.0)) return 0.0;
  return 4.0 / 3.0 * effective_modulus * std::sqrt(effective_radius) * depth * std::sqrt(depth);
}

// ---------------------------------------------------------------------------------------
// Hertz contact

double HertzContactState::pressure_at(double r) const noexcept {
  if (!(contact_radius > 0.0)) return 0.0;
  const double x = std::abs(r) / contact_radius;
  if (!(x < 1.0)) return 0.0;
  return peak_pressure * std::sqrt((1.0 - x) * (1.0 + x));
}

HertzContact::HertzContact(const HertzParameters& parameters) : parameters_(parameters) {
  if (!positive_finite(parameters.finger_radius))
    throw InputError(fmt::format("hertz contact: finger radius must be positive and finite, got {} m",
                                 parameters.finger_radius));
  validate(parameters.finger, "hertz contact: finger");
  validate(parameters.tissue, "hertz contact: tissue");
  effective_modulus_ = contact::effective_modulus(parameters.finger, parameters.tissue);
}

double HertzContact::max_contact_radius(double tissue_mean_curvature) const noexcept {
  const double kp = std::isfinite(tissue_mean_curvature)
                        ? std::clamp(tissue_mean_curvature, -kMaxContactCurvature, kMaxContactCurvature)
                        : 0.0;
  const double finger_curvature = 1.0 / parameters_.finger_radius;
  const double curvature = finger_curvature + kp;
  // Convex tissue (R < R_f): Hertz holds while d ≤ R, i.e. a ≤ R. Flat or concave tissue:
  // the contact disc cannot outgrow the finger.
  return curvature > finger_curvature ? 1.0 / curvature : parameters_.finger_radius;
}

HertzContactState HertzContact::evaluate(double depth, double tissue_mean_curvature) const noexcept {
  HertzContactState s;
  const double kp = std::isfinite(tissue_mean_curvature)
                        ? std::clamp(tissue_mean_curvature, -kMaxContactCurvature, kMaxContactCurvature)
                        : 0.0;
  const double curvature = 1.0 / parameters_.finger_radius + kp;  // 1/R (eq. 2: R1R2/(R1+R2))
  s.effective_curvature = std::max(curvature, 0.0);
  if (!(depth > 0.0) || !std::isfinite(depth)) return s;
  s.depth = depth;

  const double e = effective_modulus_;
  const double a_max = max_contact_radius(kp);
  // Depth at which a = √(R·d) reaches a_max; zero when conformal (R = ∞).
  const double saturation_depth = a_max * a_max * s.effective_curvature;
  if (curvature > 0.0 && depth <= saturation_depth) {
    s.regime = HertzRegime::hertz;
    s.contact_radius = std::sqrt(depth / curvature);
    // F = (4/3)·E*·√R·d^{3/2} = (4/3)·E*·a³/R; stiffness 2·E*·a; p0 = 2·E*·a/(π·R) = 3F/(2πa²).
    const double a = s.contact_radius;
    s.force = 4.0 / 3.0 * e * a * a * a * curvature;
    s.stiffness = 2.0 * e * a;
    s.peak_pressure = 2.0 * e * a * curvature / std::numbers::pi;
    return s;
  }
  // Past saturation the disc keeps radius a_max and the force grows along the Hertz
  // tangent 2·E*·a_max, which is also the stiffness of a flat punch of that radius, so
  // the conformal limit (saturation depth → 0) joins continuously.
  s.regime = curvature > 0.0 ? HertzRegime::saturated : HertzRegime::conformal;
  s.contact_radius = a_max;
  const double saturation_force = 4.0 / 3.0 * e * a_max * a_max * a_max * s.effective_curvature;
  s.stiffness = 2.0 * e * a_max;
  s.force = saturation_force + s.stiffness * (depth - saturation_depth);
  // The Hertz profile carried at radius a_max (the punch's edge singularity is not rendered),
  // scaled so that it still integrates to F.
  s.peak_pressure = 3.0 * s.force / (2.0 * std::numbers::pi * a_max * a_max);
  return s;
}

// ---------------------------------------------------------------------------------------
// Friction

CoulombFriction::CoulombFriction(const FrictionParameters& parameters) : parameters_(parameters) {
  if (!(std::isfinite(parameters.coefficient) && parameters.coefficient >= 0.0))
    throw InputError(fmt::format("friction: coefficient must be finite and non-negative, got {}",
                                 parameters.coefficient));
  if (!positive_finite(parameters.regularization_speed))
    throw InputError(fmt::format("friction: regularization speed must be positive and finite, got {} m/s",
                                 parameters.regularization_speed));
}

Vec3 CoulombFriction::force(const Vec3& slip_velocity, const Vec3& normal, double normal_load) const noexcept {
  if (!positive_finite(normal_load) || !slip_velocity.allFinite()) return Vec3::Zero();
  Vec3 tangential = slip_velocity;
  const double normal_length = normal.norm();
  if (std::isfinite(normal_length) && normal_length > 0.0) {
    const Vec3 n = normal / normal_length;
    tangential -= tangential.dot(n) * n;
  }
  const double speed = tangential.stableNorm();
  if (!(speed > 0.0)) return Vec3::Zero();
  // μN·v/√(v² + v_ε²): the limit μN for fast slip, a viscous μN/v_ε near rest.
  const double magnitude =
      parameters_.coefficient * normal_load * (speed / std::hypot(speed, parameters_.regularization_speed));
  return -magnitude * (tangential / speed);
}

SphereContactForce sphere_contact_force(const HertzContact& contact, const CoulombFriction& friction,
                                        const SphereContactInput& input) noexcept {
  SphereContactForce out;
  if (input.ambient_force.allFinite()) out.ambient = input.ambient_force;
  const double normal_length = input.normal.norm();
  if (std::isfinite(normal_length) && normal_length > 0.0) {
    const Vec3 n = input.normal / normal_length;
    out.hertz = contact.evaluate(input.depth, input.tissue_mean_curvature);
    if (out.hertz.force > 0.0) {
      out.contact = out.hertz.force * n;
      // Eq. 4: μ·∫p dA = μ·F_c from the contact pressure, plus μ·m·g from the sphere's weight.
      const double weight = positive_finite(input.weight_load) ? input.weight_load : 0.0;
      out.friction = friction.force(input.slip_velocity, n, out.hertz.force + weight);
    }
  }
  out.total = out.contact + out.friction + out.ambient;
  return out;
}

// ---------------------------------------------------------------------------------------
// Fingerpad law and quasilinear viscoelasticity

FingerpadLaw::FingerpadLaw(const FingerpadParameters& parameters) : parameters_(parameters) {
  if (!positive_finite(parameters.b))
    throw InputError(fmt::format("fingerpad law: b must be positive and finite, got {} N/m", parameters.b));
  if (!positive_finite(parameters.m))
    throw InputError(fmt::format("fingerpad law: m must be positive and finite, got {} 1/m", parameters.m));
  if (!positive_finite(parameters.max_exponential_depth) || parameters.m * parameters.max_exponential_depth > 700.0)
    throw InputError(fmt::format("fingerpad law: max exponential depth must be positive with m·depth ≤ 700, got {} m",
                                 parameters.max_exponential_depth));
}

double FingerpadLaw::force(double depth) const noexcept {
  if (!(depth > 0.0) || !std::isfinite(depth)) return 0.0;
  const double b = parameters_.b, m = parameters_.m, d_max = parameters_.max_exponential_depth;
  if (depth <= d_max) return b / m * std::expm1(m * depth);  // expm1: exact near d = 0
  return b / m * std::expm1(m * d_max) + b * std::exp(m * d_max) * (depth - d_max);
}

double FingerpadLaw::depth(double force) const noexcept {
  if (!(force > 0.0) || !std::isfinite(force)) return 0.0;
  const double b = parameters_.b, m = parameters_.m, d_max = parameters_.max_exponential_depth;
  const double f_max = b / m * std::expm1(m * d_max);
  if (force <= f_max) return std::log1p(m * force / b) / m;
  return d_max + (force - f_max) / (b * std::exp(m * d_max));
}

double FingerpadLaw::stiffness(double depth) const noexcept {
  if (!(depth >= 0.0)) return 0.0;  // also NaN
  return parameters_.b * std::exp(parameters_.m * std::min(depth, parameters_.max_exponential_depth));
}

double ReducedRelaxation::at(double t) const noexcept {
  double g = steady_state;
  for (const auto& term : terms) g += term.weight * std::exp(-std::max(t, 0.0) / term.time_constant);
  return g;
}

ReducedRelaxation fingerpad_relaxation() {
  return {0.45, {{0.25, 0.004}, {0.15, 0.070}, {0.15, 1.4}}};
}

QuasiLinearViscoelastic::QuasiLinearViscoelastic(const ReducedRelaxation& relaxation)
    : steady_state_(relaxation.steady_state), count_(relaxation.terms.size()) {
  if (!(std::isfinite(relaxation.steady_state) && relaxation.steady_state >= 0.0))
    throw InputError(fmt::format("relaxation: steady-state weight g∞ must be finite and non-negative, got {}",
                                 relaxation.steady_state));
  if (relaxation.terms.size() > kMaxTerms)
    throw InputError(fmt::format("relaxation: at most {} exponential terms, got {}", kMaxTerms,
                                 relaxation.terms.size()));
  double sum = relaxation.steady_state;
  for (std::size_t i = 0; i < count_; ++i) {
    const RelaxationTerm& term = relaxation.terms[i];
    if (!(std::isfinite(term.weight) && term.weight >= 0.0))
      throw InputError(fmt::format("relaxation: term {} weight must be finite and non-negative, got {}", i + 1,
                                   term.weight));
    if (!positive_finite(term.time_constant))
      throw InputError(fmt::format("relaxation: term {} time constant must be positive and finite, got {} s", i + 1,
                                   term.time_constant));
    terms_[i] = term;
    sum += term.weight;
  }
  if (!(std::abs(sum - 1.0) <= 1e-6))
    throw InputError(fmt::format("relaxation: weights must sum to 1 (G(0) = 1), got {}", sum));
}

double QuasiLinearViscoelastic::step(double elastic_force, double dt) noexcept {
  if (!std::isfinite(elastic_force)) return force_;
  if (!(dt > 0.0) || !std::isfinite(dt)) dt = 0.0;
  const double change = elastic_force - elastic_force_;
  double force = steady_state_ * elastic_force;
  for (std::size_t i = 0; i < count_; ++i) {
    const double x = dt / terms_[i].time_constant;
    const double decay = std::exp(-x);
    // ∫ over the step of e^{−(t−τ)/τ_i} for a uniform rate: (τ_i/Δt)(1 − e^{−Δt/τ_i}), → 1 as Δt → 0.
    const double ramp = x > 0.0 ? -std::expm1(-x) / x : 1.0;
    history_[i] = decay * history_[i] + terms_[i].weight * change * ramp;
    force += history_[i];
  }
  elastic_force_ = elastic_force;
  force_ = force;
  return force_;
}

void QuasiLinearViscoelastic::reset(double elastic_force) noexcept {
  if (!std::isfinite(elastic_force)) elastic_force = 0.0;
  history_.fill(0.0);
  elastic_force_ = elastic_force;
  force_ = steady_state_ * elastic_force;
}

}  // namespace tactus::contact
