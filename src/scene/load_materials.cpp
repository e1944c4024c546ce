// materials.<name>: constitutive model, elastic constants, damping, viscoelasticity.
#include <fmt/format.h>

#include "scene/loader.hpp"

namespace tactus::scene::detail {

namespace {

/// Fills every elastic constant from E and ν.
void from_young(Material& m, double e, double nu) {
  m.young_modulus = e;
  m.poisson_ratio = nu;
  m.shear_modulus = e / (2.0 * (1.0 + nu));
  m.bulk_modulus = e / (3.0 * (1.0 - 2.0 * nu));
  m.lame_lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  m.c10 = 0.5 * m.shear_modulus;
  m.c01 = 0.0;
}

/// Fills every elastic constant from μ and κ.
void from_mu_kappa(Material& m, double mu, double kappa) {
  from_young(m, 9.0 * kappa * mu / (3.0 * kappa + mu), (3.0 * kappa - 2.0 * mu) / (2.0 * (3.0 * kappa + mu)));
  m.shear_modulus = mu;  // keep the given values exactly, not their round trip
  m.bulk_modulus = kappa;
}

const Range kPoisson = Range::open(-1.0, 0.5);

void read_elasticity(Reader& r, Material& m) {
  const bool hyperelastic =
      m.law == physics::FemLaw::neo_hookean || m.law == physics::FemLaw::mooney_rivlin;
  const auto& t = r.table();
  const bool by_young = t.contains("young_modulus");
  const bool by_mu = hyperelastic && t.contains("mu");
  const bool by_c = m.law == physics::FemLaw::mooney_rivlin && (t.contains("c10") || t.contains("c01"));
  const int forms = int(by_young) + int(by_mu) + int(by_c);
  if (forms > 1)
    r.fail_here("give the elastic constants one way only: young_modulus + poisson_ratio"
                + std::string(hyperelastic ? ", or mu + kappa" : "")
                + (m.law == physics::FemLaw::mooney_rivlin ? ", or c10 + c01 (+ kappa or poisson_ratio)" : ""));

  if (by_mu) {
    const double mu = r.required_number("mu", Range::positive());
    const double kappa = r.required_number("kappa", Range::positive());
    from_mu_kappa(m, mu, kappa);
    return;
  }
  if (by_c) {
    const double c10 = r.required_number("c10");
    const double c01 = r.number("c01", 0.0);
    const double mu = 2.0 * (c10 + c01);
    if (!(mu > 0.0)) r.fail("c10", fmt::format("c10 + c01 = {} must be > 0", number_text(c10 + c01)));
    if (t.contains("kappa") && t.contains("poisson_ratio"))
      r.fail_here("give kappa or poisson_ratio with c10/c01, not both");
    if (const auto kappa = r.number("kappa", Range::positive())) {
      from_mu_kappa(m, mu, *kappa);
    } else {
      const double nu = r.number("poisson_ratio", 0.45, kPoisson);
      from_young(m, 2.0 * mu * (1.0 + nu), nu);
    }
    m.c10 = c10;
    m.c01 = c01;
    return;
  }
  if (!by_young) {
    std::string alternatives = "a number";
    if (hyperelastic) alternatives += "; or give mu + kappa";
    if (m.law == physics::FemLaw::mooney_rivlin) alternatives += ", or c10 + c01";
    r.fail_missing("young_modulus", alternatives);
  }
  const double e = r.required_number("young_modulus", Range::positive());
  const double nu = r.number("poisson_ratio", 0.45, kPoisson);
  from_young(m, e, nu);
}

Damping read_damping(Reader& r) {
  Damping d;
  if (auto t = r.table("damping")) {
    d.rayleigh_alpha = t->number("rayleigh_alpha", 0.0, Range::non_negative());
    d.rayleigh_beta = t->number("rayleigh_beta", 0.0, Range::non_negative());
    d.nodal = t->number("nodal", 0.0, Range::non_negative());
    t->finish();
  }
  return d;
}

Viscoelasticity read_viscoelastic(Reader& r) {
  Viscoelasticity v;
  auto t = r.table("viscoelastic");
  if (!t) return v;
  v.model = t->choice<ViscoelasticModel>("model",
                                         {{"kelvin_voigt", ViscoelasticModel::kelvin_voigt},
                                          {"standard_linear_solid", ViscoelasticModel::standard_linear_solid},
                                          {"prony", ViscoelasticModel::prony}},
                                         std::nullopt);
  switch (v.model) {
    case ViscoelasticModel::kelvin_voigt:
      v.tau = t->required_number("tau", Range::positive());
      break;
    case ViscoelasticModel::standard_linear_solid:
      v.tau = t->required_number("tau", Range::positive());
      v.long_term_fraction = t->required_number("long_term_fraction", Range::open(0.0, 1.0));
      break;
    case ViscoelasticModel::prony: {
      auto terms = t->table_array("terms");
      if (terms.empty()) t->fail_here("missing required key 'terms' (an array of {g, tau} tables)");
      double sum = 0.0;
      for (auto& term : terms) {
        PronyTerm p;
        p.g = term.required_number("g", Range::open(0.0, 1.0));
        p.tau = term.required_number("tau", Range::positive());
        term.finish();
        sum += p.g;
        v.prony.push_back(p);
      }
      if (sum >= 1.0)
        t->fail("terms", fmt::format("the g values sum to {}; it must be < 1 (long-term modulus > 0)", number_text(sum)));
      v.long_term_fraction = 1.0 - sum;
      break;
    }
    case ViscoelasticModel::none: break;
  }
  t->finish();
  return v;
}

}  // namespace

Material read_material(Reader& r, const std::string& name) {
  Material m;
  m.name = name;
  using Law = std::optional<physics::FemLaw>;  // none: a spring material
  m.law = r.choice<Law>("model",
                        {{"mass_spring", Law{}},
                         {"linear", physics::FemLaw::linear},
                         {"corotational", physics::FemLaw::corotational},
                         {"stvk", physics::FemLaw::stvk},
                         {"neo_hookean", physics::FemLaw::neo_hookean},
                         {"mooney_rivlin", physics::FemLaw::mooney_rivlin}},
                        Law{physics::FemLaw::corotational});
  read_elasticity(r, m);
  m.density = r.required_number("density", Range::positive());
  m.damping = read_damping(r);
  m.viscoelastic = read_viscoelastic(r);
  m.nodal_pressure = r.choice<bool>("volumetric", {{"element", false}, {"nodal", true}}, false);
  if (m.nodal_pressure && m.law != physics::FemLaw::mooney_rivlin)
    r.fail("volumetric", "\"nodal\" averages the volume change of mooney_rivlin, whose energy splits into an "
                         "isochoric and a volumetric part; use model = \"mooney_rivlin\" or remove the key");
  if (m.nodal_pressure && m.viscoelastic.model != ViscoelasticModel::none &&
      m.viscoelastic.model != ViscoelasticModel::kelvin_voigt)
    r.fail("volumetric", "\"nodal\" keeps the bulk response elastic, and this material's viscoelasticity relaxes it");
  r.finish();
  return m;
}

}  // namespace tactus::scene::detail
