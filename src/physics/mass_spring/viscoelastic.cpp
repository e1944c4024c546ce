#include "physics/mass_spring/viscoelastic.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tactus::physics {

ViscoelasticParams ViscoelasticParams::kelvin_voigt(double tau) {
  ViscoelasticParams p;
  p.kelvin_voigt_tau = tau;
  p.validate();
  return p;
}

ViscoelasticParams ViscoelasticParams::standard_linear_solid(double e_inf, double e1, double tau1) {
  if (!(e_inf > 0.0)) throw InputError("standard linear solid: E_inf must be positive");
  ViscoelasticParams p;
  p.arms.push_back({e1 / e_inf, tau1});
  p.validate();
  return p;
}

ViscoelasticParams ViscoelasticParams::prony(const std::vector<PronyTerm>& terms) {
  double g_inf = 1.0;
  for (const auto& t : terms) g_inf -= t.g;
  if (!(g_inf > 0.0)) throw InputError("Prony series: the g_i must sum to less than 1");
  ViscoelasticParams p;
  // Arm stiffness relative to the long-term one: g_i E0 / (g∞ E0).
  for (const auto& t : terms) p.arms.push_back({t.g / g_inf, t.tau});
  p.validate();
  return p;
}

double ViscoelasticParams::relaxation_ratio(double t) const {
  double r = 1.0;
  for (const auto& a : arms) r += a.ratio * std::exp(-t / a.tau);
  return r;
}

void ViscoelasticParams::validate() const {
  if (!(std::isfinite(kelvin_voigt_tau) && kelvin_voigt_tau >= 0.0))
    throw InputError("viscoelastic: Kelvin-Voigt time must be >= 0, got " + std::to_string(kelvin_voigt_tau));
  for (const auto& a : arms) {
    if (!(std::isfinite(a.ratio) && a.ratio >= 0.0))
      throw InputError("viscoelastic: arm stiffness ratio must be >= 0, got " + std::to_string(a.ratio));
    if (!(std::isfinite(a.tau) && a.tau > 0.0))
      throw InputError("viscoelastic: relaxation time must be > 0, got " + std::to_string(a.tau));
  }
}

}  // namespace tactus::physics
