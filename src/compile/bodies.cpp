#include "compile/bodies.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <vector>

#include "core/error.hpp"
#include "physics/fem/nodal_pressure.hpp"
#include "physics/fem/tet_fem.hpp"
#include "physics/mass_spring/surface_builder.hpp"
#include "physics/mass_spring/tet_builder.hpp"
#include "compile/nodules.hpp"

namespace tactus::compile {
namespace {

physics::FemMaterial fem_material(const scene::Material& m) {
  if (!m.law) throw InputError("a mass_spring material cannot drive a FEM body");
  physics::FemMaterial fm;
  fm.law = *m.law;
  fm.young_modulus = m.young_modulus;
  fm.poisson_ratio = m.poisson_ratio;
  fm.density = m.density;
  if (m.law == physics::FemLaw::mooney_rivlin) {
    fm.c10 = m.c10;
    fm.c01 = m.c01;
    fm.bulk_modulus = m.bulk_modulus;
    fm.nodal_pressure = m.nodal_pressure;
  }
  fm.rayleigh_mass = m.damping.rayleigh_alpha;
  fm.rayleigh_stiffness = m.damping.rayleigh_beta;
  const auto& ve = m.viscoelastic;
  switch (ve.model) {
    case scene::ViscoelasticModel::none: break;
    // σ = E (ε + τ ε̇) is stiffness-proportional damping with β = τ.
    case scene::ViscoelasticModel::kelvin_voigt: fm.rayleigh_stiffness += ve.tau; break;
    case scene::ViscoelasticModel::standard_linear_solid:
      fm.prony.push_back({1.0 - ve.long_term_fraction, ve.tau});
      fm.prony_relaxes_bulk = true;
      break;
    case scene::ViscoelasticModel::prony:
      for (const auto& t : ve.prony) fm.prony.push_back({t.g, t.tau});
      fm.prony_relaxes_bulk = true;
      break;
  }
  return fm;
}

/// The body's FEM: one material, or its regions' (Body::region_materials; the scene has
/// checked that they share the law, damping and viscoelasticity).
std::shared_ptr<const physics::ForceModel> fem_model(const scene::Model& model, const scene::Body& b) {
  std::vector<physics::FemMaterial> materials{fem_material(model.materials[*b.material])};
  std::vector<std::int32_t> element_material;
  if (!b.region_materials.empty()) {
    std::vector<std::size_t> used{*b.material};  // scene material of each FEM material
    std::map<int, std::int32_t> of_tag;
    for (const auto& [tag, m] : b.region_materials) {
      auto it = std::find(used.begin(), used.end(), m);
      if (it == used.end()) {
        used.push_back(m);
        materials.push_back(fem_material(model.materials[m]));
        it = used.end() - 1;
      }
      of_tag[tag] = static_cast<std::int32_t>(it - used.begin());
    }
    element_material.reserve(b.volume->tets.size());
    for (const int tag : b.volume->tet_regions) {
      const auto it = of_tag.find(tag);
      element_material.push_back(it == of_tag.end() ? 0 : it->second);
    }
  }
  auto fem = std::make_shared<physics::TetFem>(
      *b.volume, materials, element_material,
      b.mass_matrix == scene::MassMatrix::consistent ? physics::FemMass::consistent : physics::FemMass::lumped);
  if (materials.front().nodal_pressure) return std::make_shared<physics::NodalPressureFem>(std::move(fem));
  return fem;
}

/// Maxwell arms relative to the long-term stiffness from a scene's viscoelastic table (whose
/// Young's modulus is the instantaneous one). Returns E∞ / E₀.
double spring_viscoelasticity(const scene::Viscoelasticity& ve, physics::ViscoelasticParams& out) {
  switch (ve.model) {
    case scene::ViscoelasticModel::none: return 1.0;
    case scene::ViscoelasticModel::kelvin_voigt: out = physics::ViscoelasticParams::kelvin_voigt(ve.tau); return 1.0;
    case scene::ViscoelasticModel::standard_linear_solid: {
      const double f = ve.long_term_fraction;
      out = physics::ViscoelasticParams::standard_linear_solid(f, 1.0 - f, ve.tau);
      return f;
    }
    case scene::ViscoelasticModel::prony: {
      std::vector<physics::ViscoelasticParams::PronyTerm> terms;
      double g_inf = 1.0;
      for (const auto& t : ve.prony) {
        terms.push_back({t.g, t.tau});
        g_inf -= t.g;
      }
      out = physics::ViscoelasticParams::prony(terms);
      return g_inf;
    }
  }
  return 1.0;
}

std::shared_ptr<const physics::ForceModel> tet_spring_model(const scene::Body& b, const scene::Material& m) {
  physics::TetSpringParams p;
  const double long_term = spring_viscoelasticity(m.viscoelastic, p.viscoelastic);
  p.youngs_modulus = m.young_modulus * long_term;
  p.density = m.density;
  // The scene's nodal damping d is per node [N·s/m]; the builder takes d_i = α m_i. Use the
  // mean node mass to convert, and add the Rayleigh mass term.
  const double total_mass = m.density * b.volume->volume();
  const double mean_mass = total_mass / static_cast<double>(b.volume->vertices.size());
  p.damping_per_mass = m.damping.rayleigh_alpha + (mean_mass > 0.0 ? m.damping.nodal / mean_mass : 0.0);
  return physics::tet_mass_spring(*b.volume, p);
}

double mean_edge_length(const mesh::TriMesh& s) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const auto& t : s.triangles)
    for (int k = 0; k < 3; ++k) {
      sum += (s.vertices[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])] -
              s.vertices[static_cast<std::size_t>(t[static_cast<std::size_t>((k + 1) % 3)])])
                 .norm();
      ++n;
    }
  return n ? sum / static_cast<double>(n) : 0.0;
}

std::shared_ptr<const physics::ForceModel> surface_spring_model(const scene::Body& b, const scene::Material& m) {
  physics::SurfaceSpringParams p;
  const double long_term = spring_viscoelasticity(m.viscoelastic, p.viscoelastic);
  const double e = m.young_modulus * long_term, t = b.thickness;
  const double a = mean_edge_length(b.surface);
  auto has = [&](scene::SpringType s) { return std::find(b.springs.begin(), b.springs.end(), s) != b.springs.end(); };
  p.longitudinal = has(scene::SpringType::longitudinal);
  p.longitudinal_stiffness = e * t;
  p.diagonal = has(scene::SpringType::diagonal);
  p.diagonal_stiffness = 0.5 * e * t;
  p.torsional = has(scene::SpringType::torsional);
  p.torsional_stiffness = m.shear_modulus * long_term * t * a * a;
  p.bending = has(scene::SpringType::bending);
  p.bending_stiffness = e * t * t * t / (12.0 * a * a);
  p.areal_density = m.density * t;
  p.nodal_damping = m.damping.nodal;
  if (b.quads) return physics::surface_mass_spring(*b.quads, p);
  if (p.diagonal)
    throw InputError(fmt::format("body '{}': diagonal springs need a quad sheet (grid_plate with quads = true)", b.name));
  return physics::surface_mass_spring(b.surface, p);
}

}  // namespace

physics::Body make_physics_body(const scene::Model& model, std::size_t index) {
  const scene::Body& b = model.bodies.at(index);
  if (b.kind == scene::BodyKind::rigid) throw InputError(fmt::format("body '{}' is rigid: it has no dynamics", b.name));
  if (b.kind == scene::BodyKind::embedded)
    throw InputError(fmt::format("body '{}' is embedded: it moves with its host's tetrahedra", b.name));
  if (b.kind == scene::BodyKind::cloth) {
    physics::Body body;
    body.model = b.cloth->model;  // built and checked when the scene was read
    body.gravity = model.gravity;
    body.fixed_dofs.assign(3 * body.model->node_count(), 0);
    for (const auto& f : b.fixed) body.fix_nodes(f.nodes);
    for (const auto& p : b.prescribed) body.fix_nodes(p.nodes);
    body.settings = b.stepping;
    return body;
  }
  const scene::Material& m = model.materials.at(*b.material);
  if (b.mass_matrix == scene::MassMatrix::consistent) {
    // Explicit integrators need M^-1 f: with a consistent M that is a sparse solve per
    // evaluation, which defeats their purpose; implicit steps take M in their system matrix.
    if (b.kind != scene::BodyKind::fem)
      throw InputError(fmt::format("body '{}': mass_matrix = \"consistent\" is for 'fem' bodies; spring networks"
                                   " carry lumped masses", b.name));
    if (b.stepping.integrator != physics::Integrator::implicit_euler)
      throw InputError(fmt::format("body '{}': mass_matrix = \"consistent\" needs integrator = \"implicit_euler\":"
                                   " explicit integrators divide by a lumped mass", b.name));
  }

  physics::Body body;
  try {
    switch (b.kind) {
      case scene::BodyKind::fem: body.model = fem_model(model, b); break;
      case scene::BodyKind::tet_mass_spring: body.model = tet_spring_model(b, m); break;
      case scene::BodyKind::surface_mass_spring: body.model = surface_spring_model(b, m); break;
      case scene::BodyKind::rigid:
      case scene::BodyKind::embedded:
      case scene::BodyKind::cloth: break;
    }
  } catch (const InputError& e) {
    throw InputError(SourceLocation{model.source, {}, {}, {}}, fmt::format("body '{}': {}", b.name, e.what()));
  }
  body.gravity = model.gravity;
  body.fixed_dofs.assign(3 * body.model->node_count(), 0);
  for (const auto& f : b.fixed) body.fix_nodes(f.nodes);
  for (const auto& p : b.prescribed) body.fix_nodes(p.nodes);
  body.nodules = physics_nodules(b);
  body.settings = b.stepping;
  return body;
}

void mapped_surface_positions(const scene::Body& b, const VecX& x, std::vector<std::vector<Vec3>>& out) {
  out.resize(b.mapped.size());
  for (std::size_t i = 0; i < b.mapped.size(); ++i) b.mapped[i].mapping->apply(x, out[i]);
}

void add_mapped_surface_forces(const scene::Body& b, std::size_t index, const std::vector<Vec3>& vertex_forces,
                               VecX& node_forces) {
  b.mapped.at(index).mapping->apply_transpose(vertex_forces, node_forces);
}

}  // namespace tactus::compile
