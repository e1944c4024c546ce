#pragma once
// Viscoelastic laws for one spring, in a form a scene file can name: Kelvin–Voigt (a dashpot
// in parallel), the standard linear solid (Zener) and its generalization, the Prony series
// (Maxwell arms in parallel with the long-term spring).
#include <vector>

namespace tactus::physics {

/// One Maxwell arm: a spring in series with a dashpot, relative to the long-term stiffness.
struct MaxwellArm {
  double ratio = 0.0;  ///< arm stiffness / long-term stiffness (E_i / E∞)
  double tau = 1.0;    ///< relaxation time c_i / k_i [s]
};

struct ViscoelasticParams {
  /// Kelvin–Voigt retardation time c/k [s] of a dashpot in parallel with every spring;
  /// 0 for none. Creeps under constant load, does not relax under constant strain.
  double kelvin_voigt_tau = 0.0;
  /// Maxwell arms: relaxation modulus E(t) = E∞ (1 + Σ ratio_i e^(−t/τ_i)).
  std::vector<MaxwellArm> arms;

  /// Dashpot c = τ k in parallel with each spring.
  static ViscoelasticParams kelvin_voigt(double tau);
  /// Standard linear solid: long-term modulus E∞, arm modulus E1, relaxation time τ1 = c1/E1.
  static ViscoelasticParams standard_linear_solid(double e_inf, double e1, double tau1);
  /// Prony series normalized on the instantaneous modulus E0 (the usual convention):
  /// E(t) = E0 (g∞ + Σ g_i e^(−t/τ_i)), g∞ = 1 − Σ g_i > 0. The body's Young's modulus is then
  /// the long-term E∞ = g∞ E0.
  struct PronyTerm {
    double g;
    double tau;
  };
  static ViscoelasticParams prony(const std::vector<PronyTerm>& terms);

  /// E(t)/E∞ under a held step strain.
  [[nodiscard]] double relaxation_ratio(double t) const;
  /// E(0)/E∞: the instantaneous over the long-term stiffness.
  [[nodiscard]] double instantaneous_ratio() const { return relaxation_ratio(0.0); }
  /// Throws InputError when a time or ratio is negative or not finite.
  void validate() const;
};

}  // namespace tactus::physics
