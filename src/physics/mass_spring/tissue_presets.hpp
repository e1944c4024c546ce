#pragma once
// Tissue parameters from docs/materials.md, for tests, benchmarks and scenes that want a
// named tissue. Values and sources are in that document; this table mirrors it.
#include <string_view>
#include <vector>

#include "physics/mass_spring/tet_builder.hpp"

namespace tactus::physics {

struct TissueMaterial {
  std::string_view name;
  double youngs_modulus;    ///< long-term (quasi-static) E [Pa]
  double poisson_ratio;     ///< for FEM; a spring network cannot use it
  double density;           ///< [kg/m³]
  double damping_per_mass;  ///< nodal damping α = d_i/m_i [1/s]: a model choice, not measured
  double relaxation_ratio;  ///< SLS arm E1/E∞ (0: elastic)
  double relaxation_time;   ///< SLS τ1 [s]
};

/// skin, fat, muscle, fascia, ligament, cortical_bone, liver, artery_wall, silicone_rubber.
const std::vector<TissueMaterial>& tissue_materials();
/// Throws InputError for an unknown name.
const TissueMaterial& tissue_material(std::string_view name);

/// Tet mass-spring parameters of a tissue: E, density, nodal damping, and its SLS arm.
TetSpringParams tet_spring_params(const TissueMaterial& tissue);

}  // namespace tactus::physics
