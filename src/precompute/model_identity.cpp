#include "precompute/model_identity.hpp"

#include <fmt/format.h>

#include "core/error.hpp"
#include "physics/fem/nodal_pressure.hpp"

namespace tactus::precompute {

std::string hash_text(std::uint64_t h) { return fmt::format("{:016x}", h); }

ModelIdentity identify(const physics::Body& body, const SpaceSettings& settings, const Grid& grid) {
  ModelIdentity id;
  const VecX& rest = body.model->rest_positions();
  id.node_count = body.model->node_count();
  Fnv1a mesh;
  mesh.add(rest.data(), static_cast<std::size_t>(rest.size()) * sizeof(double));
  const auto* fem = physics::tet_fem_of(body.model.get());
  if (fem) {
    id.element_count = fem->elements().size();
    for (const auto& e : fem->elements()) mesh.add(e.nodes.data(), sizeof e.nodes);
  }
  id.mesh_hash = mesh.value();

  Fnv1a model;
  model.add_value(id.mesh_hash);
  if (fem) {
    const auto& m = fem->material();
    model.add_value(static_cast<int>(m.law));
    for (double v : {m.young_modulus, m.poisson_ratio, m.density, m.c10.value_or(-1.0), m.c01.value_or(-1.0),
                     m.bulk_modulus.value_or(-1.0), m.inversion_threshold})
      model.add_value(v);
    model.add_value(m.project_tangent);
    if (m.nodal_pressure) model.add_value(std::uint64_t{0x6e6f64616c});  // another energy (hashed only when set)
    // Regions (a single-region body hashes as before, so its files stay valid): each
    // region's constants and each element's region.
    if (fem->materials().size() > 1) {
      for (const auto& r : fem->materials())
        for (double v : {r.young_modulus, r.poisson_ratio, r.density, r.c10.value_or(-1.0), r.c01.value_or(-1.0),
                         r.bulk_modulus.value_or(-1.0), r.inversion_threshold})
          model.add_value(v);
      for (const auto& e : fem->elements()) model.add_value(e.material);
    }
  }
  model.add(body.fixed_dofs.data(), body.fixed_dofs.size());
  if (settings.gravity) model.add(body.gravity.data(), 3 * sizeof(double));
  model.add_value(settings.contact_node);
  model.add(settings.patch_nodes.data(), settings.patch_nodes.size() * sizeof(std::int32_t));
  model.add_value(settings.load_steps);
  model.add_value(settings.max_step_halvings);
  model.add_value(settings.max_iterations);
  model.add_value(settings.tolerance);
  model.add_value(settings.gravity);
  model.add(grid.origin.data(), 3 * sizeof(double));
  model.add_value(grid.spacing);
  model.add(grid.counts.data(), sizeof grid.counts);
  if (settings.probe.enabled()) {
    // A probe space's levels differ in their lean (hashed only for probes: point spaces keep
    // their identity).
    model.add(settings.probe.axis.data(), 3 * sizeof(double));
    model.add_value(settings.probe.max_tilt);
    model.add_value(settings.probe.tilt_levels);
    model.add(settings.tilt.data(), 2 * sizeof(double));
  }
  if (settings.held_node >= 0) {
    model.add_value(settings.held_node);
    model.add(settings.held_at.data(), 3 * sizeof(double));
    // A held patch beyond the node alone (hashed only then: a held node keeps its identity).
    if (settings.held_patch.size() > 1)
      model.add(settings.held_patch.data(), settings.held_patch.size() * sizeof(std::int32_t));
  }
  if (settings.pair.enabled()) {
    model.add_value(settings.finger);
    model.add_value(settings.pair.node);
    model.add(settings.pair.patch_nodes.data(), settings.pair.patch_nodes.size() * sizeof(std::int32_t));
    model.add(settings.pair.bounds_min.data(), 3 * sizeof(double));
    model.add(settings.pair.bounds_max.data(), 3 * sizeof(double));
  }
  id.model_hash = model.value();
  return id;
}

void check_identity(const ModelIdentity& space, const ModelIdentity& model, const std::string& space_file) {
  const SourceLocation at{space_file, {}, {}, {}};
  if (space.node_count != model.node_count || space.element_count != model.element_count)
    throw InputError(at, fmt::format("the space was built for another mesh ({} nodes, {} elements); this model has "
                                     "{} nodes, {} elements",
                                     space.node_count, space.element_count, model.node_count, model.element_count));
  if (space.mesh_hash != model.mesh_hash)
    throw InputError(at, fmt::format("the space was built for another mesh (mesh hash {}, this model's {})",
                                     hash_text(space.mesh_hash), hash_text(model.mesh_hash)));
  if (space.model_hash != model.model_hash)
    throw InputError(at, fmt::format("the space was built for this mesh with another material, fixed region, "
                                     "contact patch, grid or solver setting (model hash {}, this model's {})",
                                     hash_text(space.model_hash), hash_text(model.model_hash)));
}

}  // namespace tactus::precompute
