#include "haptics/algorithms/proxy_on_plane.hpp"

#include "contact/load_spread.hpp"

namespace tactus::haptics {

std::unique_ptr<AlgorithmState> ProxyOnPlane::make_state() const {
  auto s = std::make_unique<State>();
  s->params = params_;
  return s;
}

EditableSurface ProxyOnPlane::editable_surface() const {
  return {EditableSurface::Kind::proxy, {params_.stiffness, params_.static_friction, params_.kinetic_friction}};
}

void ProxyOnPlane::edit_surface(const SurfaceValues& v, AlgorithmState& state) const {
  auto& s = static_cast<State&>(state);
  s.params.stiffness = v.stiffness;
  s.params.static_friction = v.static_friction;
  s.params.kinetic_friction = v.kinetic_friction;
}

void ProxyOnPlane::begin(const FrameInputs& f, PlaneState& state) const {
  auto& s = static_cast<State&>(state);
  if (s.started) return;
  s.proxy = contact::make_proxy_state(f.position + f.orientation * sphere_.offset);
  s.started = true;
}

Rendering ProxyOnPlane::against(const LocalContact& plane, const FrameInputs& f, PlaneState& state, bool trial) const {
  auto& s = static_cast<State&>(state);
  contact::ProxyState copy;
  contact::ProxyState& proxy = trial ? (copy = s.proxy) : s.proxy;
  const Vec3 arm = f.orientation * sphere_.offset;
  const Vec3 goal = f.position + arm;
  contact::ProxyResult r;
  if (plane.valid) {
    const contact::ConstraintPlane p{plane.normal, plane.normal.dot(plane.point)};
    r = contact::update_proxy(s.params, proxy, goal, f.velocity, f.dt, contact::HalfSpaceQuery(p.normal, p.offset));
  } else {
    r = contact::update_proxy(s.params, proxy, goal, f.velocity, f.dt, s.no_surface);
  }
  Rendering out;
  out.point = plane.point;
  out.touching = r.in_contact;
  out.force = r.force;
  out.torque = arm.cross(out.force);
  out.contact_radius = contact::sphere_contact_radius(s.params.radius, r.depth);
  return out;
}

}  // namespace tactus::haptics
