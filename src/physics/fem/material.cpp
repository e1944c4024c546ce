#include "physics/fem/material.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tactus::physics {

FemLaw parse_fem_law(std::string_view name) {
  if (name == "linear") return FemLaw::linear;
  if (name == "corotational") return FemLaw::corotational;
  if (name == "stvk") return FemLaw::stvk;
  if (name == "neo_hookean") return FemLaw::neo_hookean;
  if (name == "mooney_rivlin") return FemLaw::mooney_rivlin;
  throw InputError("unknown FEM law '" + std::string(name) +
                   "' (expected linear, corotational, stvk, neo_hookean or mooney_rivlin)");
}

std::string_view to_string(FemLaw law) {
  switch (law) {
    case FemLaw::linear: return "linear";
    case FemLaw::corotational: return "corotational";
    case FemLaw::stvk: return "stvk";
    case FemLaw::neo_hookean: return "neo_hookean";
    case FemLaw::mooney_rivlin: return "mooney_rivlin";
  }
  return "?";
}

double FemMaterial::shear_modulus() const { return young_modulus / (2.0 * (1.0 + poisson_ratio)); }

double FemMaterial::lame_lambda() const {
  return young_modulus * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
}

void FemMaterial::validate() const {
  auto fail = [](const std::string& what) { throw InputError("FEM material: " + what); };
  if (!(std::isfinite(young_modulus) && young_modulus > 0.0))
    fail("young_modulus must be positive, got " + std::to_string(young_modulus));
  if (!(poisson_ratio > -1.0 && poisson_ratio < 0.5))
    fail("poisson_ratio must lie in (-1, 0.5), got " + std::to_string(poisson_ratio));
  if (!(std::isfinite(density) && density > 0.0)) fail("density must be positive, got " + std::to_string(density));
  if (!(rayleigh_mass >= 0.0 && rayleigh_stiffness >= 0.0)) fail("Rayleigh coefficients must be non-negative");
  for (const auto* p : {&c10, &c01, &bulk_modulus})
    if (p->has_value() && !(std::isfinite(**p) && **p >= 0.0)) fail("Mooney-Rivlin parameters must be non-negative");
  if (law == FemLaw::mooney_rivlin) {
    const LawParams lp = LawParams::from(*this);
    if (!(lp.c10 + lp.c01 > 0.0 && lp.kappa > 0.0)) fail("Mooney-Rivlin needs C10 + C01 > 0 and a positive bulk modulus");
  }
  if (nodal_pressure && law != FemLaw::mooney_rivlin)
    fail("nodal_pressure is for mooney_rivlin, whose energy splits into an isochoric and a volumetric part");
  if (nodal_pressure && prony_relaxes_bulk) fail("nodal_pressure keeps the bulk response elastic: relax the shear only");
  if (!(inversion_threshold > 0.0 && inversion_threshold < 1.0))
    fail("inversion_threshold must lie in (0, 1), got " + std::to_string(inversion_threshold));
  double sum = 0.0;
  for (const auto& t : prony) {
    if (!(t.weight > 0.0 && t.weight < 1.0)) fail("Prony weights must lie in (0, 1), got " + std::to_string(t.weight));
    if (!(std::isfinite(t.tau) && t.tau > 0.0)) fail("Prony times must be positive, got " + std::to_string(t.tau));
    sum += t.weight;
  }
  if (sum >= 1.0) fail("Prony weights must sum below 1 (a positive long-term modulus), got " + std::to_string(sum));
}

LawParams LawParams::from(const FemMaterial& m) {
  LawParams p;
  p.law = m.law;
  p.mu = m.shear_modulus();
  p.lambda = m.lame_lambda();
  // Small-strain consistency: shear modulus 2 (C10 + C01), bulk modulus kappa.
  if (m.c10 || m.c01) {
    p.c10 = m.c10.value_or(0.0);
    p.c01 = m.c01.value_or(0.0);
  } else {
    p.c10 = 0.5 * p.mu;
  }
  p.kappa = m.bulk_modulus.value_or(m.young_modulus / (3.0 * (1.0 - 2.0 * m.poisson_ratio)));
  p.j_min = m.inversion_threshold;
  return p;
}

}  // namespace tactus::physics
