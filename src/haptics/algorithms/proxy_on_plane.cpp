#include "haptics/algorithms/proxy_on_plane.hpp"

#include "contact/load_spread.hpp"

namespace tactus::haptics {

std::unique_ptr<AlgorithmState> ProxyOnPlane::make_state() const {
  auto s = std::make_unique<State>();
  s->coupling.params = params_;
  return s;
}

EditableSurface ProxyOnPlane::editable_surface() const { return proxy_surface(params_); }

void ProxyOnPlane::edit_surface(const SurfaceValues& v, AlgorithmState& state) const {
  static_cast<State&>(state).coupling.edit(v);
}

void ProxyOnPlane::begin(const FrameInputs& f, PlaneState& state) const {
  static_cast<State&>(state).coupling.start(f, sphere_);
}

Rendering ProxyOnPlane::against(const LocalContact& plane, const FrameInputs& f, PlaneState& state, bool trial) const {
  auto& s = static_cast<State&>(state);
  contact::ProxyState copy;
  contact::ProxyState& proxy = trial ? (copy = s.coupling.proxy) : s.coupling.proxy;
  const Vec3 arm = f.orientation * sphere_.offset;
  const Vec3 goal = f.position + arm;
  contact::ProxyResult r;
  if (plane.valid) {
    const contact::ConstraintPlane p{plane.normal, plane.normal.dot(plane.point)};
    r = contact::update_proxy(s.coupling.params, proxy, goal, f.velocity, f.dt,
                              contact::HalfSpaceQuery(p.normal, p.offset));
  } else {
    r = contact::update_proxy(s.coupling.params, proxy, goal, f.velocity, f.dt, s.no_surface);
  }
  Rendering out;
  out.point = plane.point;
  out.touching = r.in_contact;
  out.force = r.force;
  out.torque = arm.cross(out.force);
  out.contact_radius = contact::sphere_contact_radius(s.coupling.params.radius, r.depth);
  return out;
}

}  // namespace tactus::haptics
