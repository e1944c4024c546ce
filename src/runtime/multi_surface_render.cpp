// The haptic loop's multiple-surface palpation (the ray hits the interaction loop found per
// layer become constraint planes, smoothed at updates) and the pulse added to whatever
// contact force the tool's algorithm rendered.
#include "runtime/haptic_loop.hpp"

#include "contact/load_spread.hpp"

namespace tactus::runtime {

HapticLoop::Rendered HapticLoop::render_multi_surface(const Vec3& position, const Quat& orientation, double t) {
  const Vec3 arm = config_.spheres.empty() ? Vec3::Zero() : Vec3(orientation * config_.spheres.front().offset);
  const Vec3 goal = position + arm;
  if (channels_.needle.update()) {
    // The interaction loop cast the ray this loop asked for (ToolState::axis) through every
    // layer: each first entering hit is a constraint plane.
    const haptics::NeedleSurfaces& found = channels_.needle.read();
    haptics::SurfaceLayerHits hits;
    for (std::size_t i = 0; i < config_.multi_surface->bodies.size() && i < haptics::kMaxSurfaceLayers; ++i) {
      const haptics::NeedleLayerSurface& f = found.layers[i];
      haptics::SurfaceLayerHit& h = hits.layers[i];
      h.found = f.entry_found;
      h.point = f.entry;
      h.normal = f.entry_normal;
      h.triangle = f.entry_triangle;
      h.barycentric = f.entry_barycentric;
    }
    // The planes blend over an interaction period; the smoothing filter takes what is left
    // of a step (seed 003 §3.5 uses both).
    const bool smooth = smoother_.enabled() && multi_surface_hits_;
    const Vec3 before = smooth ? multi_surface_->evaluate(goal, velocity_, t).force : Vec3::Zero();
    multi_surface_->set_hits(hits, t);
    if (smooth) smoother_.model_changed(before, multi_surface_->evaluate(goal, velocity_, t).force);
    multi_surface_hits_ = true;
  }
  multi_out_ = multi_surface_->update(goal, velocity_, t);
  needle_axis_ = multi_surface_->ray_direction();  // the ray the interaction loop casts next
  Rendered out;
  out.force = multi_out_.force;
  out.torque = arm.cross(out.force);
  out.touching = multi_out_.touching;
  out.point = multi_out_.proxy;
  out.law_force = out.force.norm();
  if (multi_out_.touching) out.contact_radius = contact::sphere_contact_radius(multi_surface_->config().radius, multi_out_.depth);
  return out;
}

void HapticLoop::multi_surface_load(ContactLoad& load, bool touching) const {
  const int layer = multi_out_.layer;
  load.active = touching && layer >= 0 && multi_out_.triangle >= 0;
  load.body = layer >= 0 ? static_cast<std::int32_t>(config_.multi_surface->bodies[static_cast<std::size_t>(layer)]) : -1;
  load.triangle = load.active ? multi_out_.triangle : -1;
  load.barycentric = multi_out_.barycentric;
}

Vec3 HapticLoop::pulse_force(double t, const Vec3& position, const Quat& orientation, const Vec3& contact_force,
                             bool touching) const {
  if (!config_.pulse || !touching) return Vec3::Zero();
  const Vec3 arm = config_.spheres.empty() ? Vec3::Zero() : Vec3(orientation * config_.spheres.front().offset);
  return config_.pulse->force(t, position + arm, contact_force);
}

}  // namespace tactus::runtime
