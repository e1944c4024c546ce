#include "haptics/algorithms/multi_surface_algorithm.hpp"

#include "contact/load_spread.hpp"

namespace tactus::haptics {

MultiSurfaceAlgorithm::MultiSurfaceAlgorithm(MultiSurfaceConfig config, std::vector<std::size_t> bodies, Vec3 offset)
    : config_(std::move(config)), bodies_(std::move(bodies)), offset_(offset) {
  const MultiSurfaceForce check(config_);  // the configuration's errors at build time
}

std::unique_ptr<AlgorithmState> MultiSurfaceAlgorithm::make_state() const { return std::make_unique<State>(config_); }

Rendering MultiSurfaceAlgorithm::render(const FrameInputs& f, AlgorithmState& state) const {
  auto& s = static_cast<State&>(state);
  const Vec3 arm = f.orientation * offset_;
  const Vec3 goal = f.position + arm;
  Rendering r;
  if (f.surfaces_fresh) {
    // The interaction loop cast the ray this algorithm asked for (Rendering::tool_axis)
    // through every layer: each first entering hit is a constraint plane.
    SurfaceLayerHits hits;
    for (std::size_t i = 0; i < bodies_.size() && i < kMaxSurfaceLayers; ++i) {
      const NeedleLayerSurface& found = f.surfaces->layers[i];
      SurfaceLayerHit& h = hits.layers[i];
      h.found = found.entry_found;
      h.point = found.entry;
      h.normal = found.entry_normal;
      h.triangle = found.entry_triangle;
      h.barycentric = found.entry_barycentric;
    }
    // The planes blend over an interaction period; the smoothing filter takes what is left
    // of a step (seed 003 §3.5 uses both).
    const bool smooth = f.smoothing && s.has_hits;
    const Vec3 before = smooth ? s.force.evaluate(goal, f.velocity, f.t).force : Vec3::Zero();
    s.force.set_hits(hits, f.t);
    if (smooth) {
      r.model_changed = true;
      r.before = before;
      r.after = s.force.evaluate(goal, f.velocity, f.t).force;
    }
    s.has_hits = true;
  }
  s.out = s.force.update(goal, f.velocity, f.t);
  r.tool_axis = s.force.ray_direction();  // the ray the interaction loop casts next
  r.force = s.out.force;
  r.torque = arm.cross(r.force);
  r.touching = s.out.touching;
  r.point = s.out.proxy;
  r.law_force = r.force.norm();
  if (s.out.touching) r.contact_radius = contact::sphere_contact_radius(config_.radius, s.out.depth);
  r.surface_time = f.contact->surface_time;
  r.frame_point = plane_frame_point(*f.contact);
  return r;
}

void MultiSurfaceAlgorithm::react(const FrameInputs& /*frame*/, const Rendering& rendered, const Reaction& /*reaction*/,
                                  AlgorithmState& state, ContactLoad& load) const {
  const auto& s = static_cast<const State&>(state);
  const int layer = s.out.layer;
  load.active = rendered.touching && layer >= 0 && s.out.triangle >= 0;
  load.body = layer >= 0 ? static_cast<std::int32_t>(bodies_[static_cast<std::size_t>(layer)]) : -1;
  load.triangle = load.active ? s.out.triangle : -1;
  load.barycentric = s.out.barycentric;
}

}  // namespace tactus::haptics
