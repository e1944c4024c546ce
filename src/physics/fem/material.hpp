#pragma once
// FEM material description: the constitutive law, its parameters, damping and
// viscoelastic relaxation.
#include <optional>
#include <string_view>
#include <vector>

namespace tactus::physics {

enum class FemLaw { linear, corotational, stvk, neo_hookean, mooney_rivlin };

/// Parses "linear", "corotational", "stvk", "neo_hookean" or "mooney_rivlin"; throws
/// InputError naming the alternatives otherwise.
FemLaw parse_fem_law(std::string_view name);
std::string_view to_string(FemLaw law);

/// One term of a Prony series G(t) = G0 (g_inf + sum g_i exp(-t / tau_i)), g_inf = 1 - sum g_i:
/// a Maxwell branch of a generalized Maxwell solid (one term = the standard linear solid).
struct PronyTerm {
  double weight = 0.0;  ///< g_i, normalized (0, 1); the weights sum below 1
  double tau = 1.0;     ///< relaxation time tau_i [s]
  friend bool operator==(const PronyTerm&, const PronyTerm&) = default;
};

struct FemMaterial {
  FemLaw law = FemLaw::corotational;
  double young_modulus = 1e4;  ///< E [Pa], the instantaneous (short-time) modulus
  double poisson_ratio = 0.3;  ///< nu, in (-1, 0.5)
  double density = 1000.0;     ///< [kg/m^3]
  /// Mooney-Rivlin: psi = C10 (I1bar - 3) + C01 (I2bar - 3) + kappa/2 (J - 1)^2. Unset values
  /// follow from E and nu: C10 + C01 = mu / 2 (C01 = 0 when neither is set) and
  /// kappa = E / (3 (1 - 2 nu)).
  std::optional<double> c10, c01, bulk_modulus;
  double rayleigh_mass = 0.0;       ///< alpha [1/s]: D = alpha M + beta K
  double rayleigh_stiffness = 0.0;  ///< beta [s]
  /// Relaxation of the stress: the small-strain (linear), corotated (corotational) or second
  /// Piola-Kirchhoff stress (hyperelastic laws; its isochoric part Dev S unless the bulk relaxes).
  std::vector<PronyTerm> prony;
  /// Relax the bulk response with the same weights too (E(t) relaxes at constant nu);
  /// otherwise only the deviatoric (hyperelastic: isochoric) stress relaxes.
  bool prony_relaxes_bulk = false;
  /// Hyperelastic laws: below this volume ratio J the volumetric functions continue as
  /// their second-order Taylor expansion, so inverted elements get finite, restoring forces.
  double inversion_threshold = 0.1;
  /// Hyperelastic laws: project each element's tangent onto the positive semi-definite
  /// cone (Teran et al. 2005), so Newton and CG stay well-posed. Off = the exact tangent.
  bool project_tangent = true;
  /// Mooney–Rivlin: the elements leave out the volumetric term kappa/2 (J − 1)², which a
  /// NodalPressureFem over the body adds with the volume change averaged at the nodes
  /// (physics/fem/nodal_pressure.hpp): no volumetric locking as nu → 0.5.
  bool nodal_pressure = false;

  [[nodiscard]] double shear_modulus() const;  ///< mu = E / (2 (1 + nu))
  [[nodiscard]] double lame_lambda() const;    ///< lambda = E nu / ((1 + nu)(1 - 2 nu))
  /// Throws InputError with the offending parameter.
  void validate() const;
};

/// Parameters the element loop needs, derived once from a FemMaterial.
struct LawParams {
  FemLaw law = FemLaw::linear;
  double lambda = 0.0, mu = 0.0;
  double c10 = 0.0, c01 = 0.0, kappa = 0.0;
  double j_min = 0.1;  ///< inversion_threshold

  static LawParams from(const FemMaterial& m);
};

}  // namespace tactus::physics
