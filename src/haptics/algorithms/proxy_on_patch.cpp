#include "haptics/algorithms/proxy_on_patch.hpp"

#include "contact/load_spread.hpp"

namespace tactus::haptics {

std::unique_ptr<AlgorithmState> ProxyOnPatch::make_state() const {
  auto s = std::make_unique<State>(kind(), capacity());
  s->coupling.params = params_;
  return s;
}

EditableSurface ProxyOnPatch::editable_surface() const { return proxy_surface(params_); }

void ProxyOnPatch::edit_surface(const SurfaceValues& v, AlgorithmState& state) const {
  static_cast<State&>(state).coupling.edit(v);
}

void ProxyOnPatch::begin(const FrameInputs& f, PatchState& state) const {
  static_cast<State&>(state).coupling.start(f, sphere_);
}

void ProxyOnPatch::patch_replaced(PatchState& state) const {
  // The proxy remembers triangles by index, and indices name other triangles in a new patch.
  auto& s = static_cast<State&>(state);
  s.coupling.proxy.side_triangle = -1;
  s.coupling.proxy.side = 0;
  s.coupling.proxy.anchor_triangle = -1;
  s.coupling.proxy.surface_replaced = true;
}

Rendering ProxyOnPatch::against(const FrameInputs& f, PatchState& state, bool trial) const {
  auto& s = static_cast<State&>(state);
  contact::ProxyState copy;
  contact::ProxyState& proxy = trial ? (copy = s.coupling.proxy) : s.coupling.proxy;
  const Vec3 arm = f.orientation * sphere_.offset;
  const contact::ProxyResult r =
      contact::update_proxy(s.coupling.params, proxy, f.position + arm, f.velocity, f.dt, s.surface());
  Rendering out;
  out.touching = r.in_contact;
  out.force = r.force;
  out.torque = arm.cross(out.force);
  if (r.in_contact && r.triangle >= 0) {
    out.point = r.contact_point;
    out.contact_radius = contact::sphere_contact_radius(s.coupling.params.radius, r.depth);
    // The proxy may rest on several faces at once (in a dent): the coupling force, not the
    // closest face's normal, is the direction the tissue is pushed.
    const double magnitude = r.force.norm();
    const Vec3 direction = magnitude > 0.0 ? Vec3(r.force / magnitude) : r.contact_normal;
    out.law_force = magnitude;
    out.on_patch = {r.triangle, r.barycentric, direction, out.law_force, s.coupling.params.stiffness,
                    disc_radius(out.contact_radius)};
  }
  return out;
}

void ProxyOnPatch::advance(const FrameInputs& f, const Rendering& /*rendered*/, const Reaction& /*reaction*/, bool on,
                           const contact::PatchContact& on_patch, PatchState& state, ContactLoad& /*load*/) const {
  auto& s = static_cast<State&>(state);
  s.local.advance(on_patch, f.dt);
  // The proxy rests on the surface, so it rides with the contact point: the implicit force
  // solve in advance() settled the force counting on exactly that motion. Left behind, a
  // patch springing back would pass through the proxy.
  if (on) s.coupling.proxy.position += s.local.contact_motion();
}

}  // namespace tactus::haptics
