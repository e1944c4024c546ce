#include "runtime/interaction_step.hpp"

#include <limits>

#include "contact/closest_point.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "mesh/half_edge.hpp"

namespace tactus::runtime {
namespace {

void find_needle_crossings(const InteractionModel& model, InteractionState& state, const InteractionInputs& in,
                           std::span<PartStats> parts, std::size_t k, const ToolState& tool,
                           haptics::NeedleSurfaces& out) {
  const InteractionTarget& target = model.targets[k];
  out = haptics::NeedleSurfaces{};
  const double axis_norm = tool.axis.norm();
  if (!tool.valid || !(axis_norm > 0.0) || !tool.position.allFinite() || !tool.axis.allFinite()) return;
  const Vec3 axis = tool.axis / axis_norm;
  // From behind the hub to a reach ahead of the tip: every surface the shaft is in or is
  // about to meet.
  const Vec3 from = tool.position - (target.needle_length + target.reach) * axis;
  const Vec3 to = tool.position + target.reach * axis;
  for (std::size_t i = 0; i < target.bodies.size() && i < haptics::kMaxNeedleLayers; ++i) {
    const std::size_t b = target.bodies[i];
    const PartTimer query(in.clock);
    state.trees[b].segment(from, to, state.hits);
    query.record(parts, 2 * k);
    haptics::NeedleLayerSurface& layer = out.layers[i];
    for (const contact::RayHit& h : state.hits) {
      if (!layer.entry_found) {
        if (!h.entering) continue;  // leaving a body the ray started in
        layer.entry_found = true;
        layer.entry = h.point;
        layer.entry_triangle = h.triangle;
        layer.entry_barycentric = h.barycentric;
        layer.entry_normal = h.normal;
      } else if (!h.entering) {
        layer.exit_found = true;
        layer.exit = h.point;
        break;
      }
    }
  }
}

void find_contact_plane(const InteractionModel& model, InteractionState& state, const InteractionInputs& in,
                        std::span<PartStats> parts, std::size_t k, const ToolState& tool, LocalContact& out) {
  const InteractionTarget& target = model.targets[k];
  const SurfaceSnapshot& surfaces = *in.surfaces;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t b : target.bodies) {
    const PartTimer query(in.clock);
    const contact::SurfacePoint p = state.trees[b].closest_point(tool.position);
    query.record(parts, 2 * k);
    if (p.triangle < 0 || p.distance >= best) continue;
    best = p.distance;
    // Outside the tissue the plane faces the tool (smooth over edges and corners); inside,
    // the face normal says which way is out.
    const Vec3 to_tool = tool.position - p.point;
    const bool outside = to_tool.dot(p.normal) > 0.0 && p.distance > 1e-12;
    out.valid = p.distance <= target.reach || !outside;
    out.body = static_cast<std::int32_t>(b);
    out.triangle = p.triangle;
    out.point = p.point;
    out.normal = outside ? Vec3(to_tool / p.distance) : p.normal;
    out.barycentric = p.barycentric;
    out.mean_curvature = 0.0;
    if (const auto& estimator = model.curvature[k][b]) {
      const mesh::VertexCurvature c = estimator->estimate_at_point(surfaces.positions[b], p.triangle, p.barycentric);
      if (c.valid) out.mean_curvature = c.kmean;
    }
  }
}

}  // namespace

InteractionModel make_interaction_model(const scene::Model& scene, std::vector<InteractionTarget> targets) {
  InteractionModel model;
  model.scene = &scene;
  model.targets = std::move(targets);
  model.queried.assign(scene.bodies.size(), false);
  for (const InteractionTarget& target : model.targets)
    for (std::size_t b : target.bodies) model.queried[b] = true;
  for (const InteractionTarget& target : model.targets) {
    auto& per_body = model.curvature.emplace_back(scene.bodies.size());
    if (target.curvature_rings <= 0) continue;
    for (std::size_t b : target.bodies) {
      try {
        const mesh::HalfEdgeMesh topology(scene.bodies[b].surface);
        per_body[b] = std::make_unique<const mesh::CurvatureEstimator>(topology, target.curvature_rings);
      } catch (const InputError& e) {
        log::warn("body '{}': no curvature estimate on its surface ({}); contact treats it as flat",
                  scene.bodies[b].name, e.reason());
      }
    }
  }
  return model;
}

InteractionState make_interaction_state(const InteractionModel& model) {
  InteractionState state;
  state.trees.resize(model.scene->bodies.size());
  return state;
}

void interaction_step(const InteractionModel& model, InteractionState& state, const InteractionInputs& in,
                      const InteractionOutputs& out) {
  const SurfaceSnapshot& surfaces = *in.surfaces;
  if (surfaces.step != state.tree_step) {
    const PartTimer refit(in.clock);
    for (std::size_t b = 0; b < state.trees.size(); ++b) {
      // Only the bodies some device touches here; a rigid body's tree, once built, stays right.
      if (!model.queried[b]) continue;
      if (!state.trees[b].empty() && model.scene->bodies[b].kind == scene::BodyKind::rigid) continue;
      if (state.trees[b].empty() || state.trees[b].needs_rebuild())
        state.trees[b].build(surfaces.positions[b], model.scene->bodies[b].surface.triangles);
      else
        state.trees[b].refit(surfaces.positions[b]);
    }
    state.tree_step = surfaces.step;
    refit.record(out.parts, 2 * model.targets.size());
  }
  for (std::size_t k = 0; k < model.targets.size(); ++k) {
    const PartTimer handling(in.clock);
    const ToolState& tool = in.tools[k];
    LocalContact& contact = *out.contacts[k];
    contact = LocalContact{};
    contact.surface_time = surfaces.t;
    if (model.targets[k].needle_length > 0.0)
      find_needle_crossings(model, state, in, out.parts, k, tool, *out.needles[k]);
    else if (tool.valid)
      find_contact_plane(model, state, in, out.parts, k, tool, contact);
    handling.record(out.parts, 2 * k + 1);
  }
}

}  // namespace tactus::runtime
