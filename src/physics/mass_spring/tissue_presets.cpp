#include "physics/mass_spring/tissue_presets.hpp"

#include <string>

#include "core/error.hpp"

namespace tactus::physics {

const std::vector<TissueMaterial>& tissue_materials() {
  // name, E∞ [Pa], ν, ρ [kg/m³], α [1/s], SLS E1/E∞, τ1 [s]. Sources: docs/materials.md.
  static const std::vector<TissueMaterial> table = {
      {"skin", 0.42e6, 0.48, 1100.0, 10.0, 1.0, 1.0},
      {"fat", 3.25e3, 0.49, 920.0, 10.0, 1.0, 1.0},
      {"muscle", 21e3, 0.49, 1060.0, 10.0, 1.22, 6.0},
      {"fascia", 400e6, 0.45, 1100.0, 10.0, 0.0, 1.0},
      {"ligament", 111e6, 0.45, 1100.0, 10.0, 0.3, 10.0},
      {"cortical_bone", 17e9, 0.35, 1900.0, 10.0, 0.0, 1.0},
      {"liver", 5.4e3, 0.49, 1060.0, 10.0, 1.0, 1.0},
      {"artery_wall", 0.6e6, 0.49, 1050.0, 10.0, 0.5, 1.0},
      {"silicone_rubber", 1.5e6, 0.49, 1030.0, 10.0, 0.0, 1.0},
  };
  return table;
}

const TissueMaterial& tissue_material(std::string_view name) {
  for (const auto& t : tissue_materials())
    if (t.name == name) return t;
  throw InputError("unknown tissue '" + std::string(name) + "'");
}

TetSpringParams tet_spring_params(const TissueMaterial& tissue) {
  TetSpringParams p;
  p.youngs_modulus = tissue.youngs_modulus;
  p.density = tissue.density;
  p.damping_per_mass = tissue.damping_per_mass;
  if (tissue.relaxation_ratio > 0.0) p.viscoelastic.arms.push_back({tissue.relaxation_ratio, tissue.relaxation_time});
  return p;
}

}  // namespace tactus::physics
