#include "haptics/algorithms/proxy_on_objects.hpp"

#include <algorithm>
#include <optional>

#include "contact/load_spread.hpp"

namespace tactus::haptics {

struct ProxyOnObjects::State final : AlgorithmState {
  ProxyCoupling coupling;
  LevelChooser::State levels;
  // What the proxy touched last frame, where the material is looked up.
  bool have_material = false;
  property_images::Lookup material;
};

ProxyOnObjects::ProxyOnObjects(ToolSphere sphere, const contact::ProxyParams& params,
                               std::vector<TouchableObject> objects, const ObjectsSettings& settings)
    : sphere_(sphere), params_(params), chooser_(std::move(objects), settings, params.radius) {}

std::unique_ptr<AlgorithmState> ProxyOnObjects::make_state() const {
  auto s = std::make_unique<State>();
  s->coupling.params = params_;
  s->levels = chooser_.make_state();
  return s;
}

void ProxyOnObjects::edit_surface(const SurfaceValues& v, AlgorithmState& state) const {
  static_cast<State&>(state).coupling.edit(v);
}

std::span<const std::size_t> ProxyOnObjects::levels_in_use(const AlgorithmState& state) {
  return static_cast<const State&>(state).levels.level;
}

double ProxyOnObjects::cost_in_use(const AlgorithmState& state) {
  return static_cast<const State&>(state).levels.cost;
}

Rendering ProxyOnObjects::render(const FrameInputs& f, AlgorithmState& state) const {
  auto& s = static_cast<State&>(state);
  s.coupling.start(f, sphere_);
  const Vec3 arm = f.orientation * sphere_.offset;
  const Vec3 goal = f.position + arm;
  const std::size_t n = chooser_.objects().size();
  chooser_.choose(f.t, goal, s.coupling.proxy.position, *f.contact, s.levels);

  // The proxy with the material where it touched last frame.
  contact::ProxyParams params = s.coupling.params;
  if (s.have_material) {
    const auto& m = s.material.properties;
    using property_images::Channel;
    params.stiffness = std::min(m[Channel::stiffness], chooser_.settings().max_stiffness);
    params.static_friction = m[Channel::static_friction];
    params.kinetic_friction = std::min(m[Channel::kinetic_friction], params.static_friction);
    params.damping = m[Channel::damping];
  }
  const bool blending = chooser_.blending(f.t, s.levels);
  std::optional<contact::ProxyState> old_proxy;
  if (blending) old_proxy = s.coupling.proxy;
  const contact::ProxyResult r =
      contact::update_proxy(params, s.coupling.proxy, goal, f.velocity, f.dt, s.levels.query);

  Rendering out;
  out.touching = r.in_contact;
  out.force = r.force;
  out.surface_time = f.t;
  s.have_material = false;
  int touched = -1;
  if (r.in_contact) {
    const contact::ClosestSurfacePoint c = s.levels.query.closest_point(s.coupling.proxy.position);
    touched = s.levels.query.last_member();
    out.point = c.point;
    if (touched == static_cast<int>(n)) out.surface_time = f.contact->surface_time;
    const auto objects = chooser_.objects();
    if (touched >= 0 && touched < static_cast<int>(n) && objects[static_cast<std::size_t>(touched)].properties) {
      const auto& images = *objects[static_cast<std::size_t>(touched)].properties;
      s.material = images.lookup(c.point, c.normal);
      s.have_material = true;
      using property_images::Channel;
      const double amplitude = s.material.properties[Channel::roughness_amplitude];
      const double fn = out.force.dot(c.normal);
      if (amplitude > 0.0 && fn > 0.0) {
        const auto h = images.roughness_height(c.point, s.material.view, amplitude,
                                               s.material.properties[Channel::roughness_wavelength]);
        const Vec3 tangential = h.gradient - h.gradient.dot(c.normal) * c.normal;
        out.force += params.stiffness * h.h * c.normal - fn * tangential;
      }
    }
  }

  // Across a switch of the touched object, the old level's force (the proxy moved on a copy) fades out.
  if (blending) {
    chooser_.old_level(s.levels, true);
    const contact::ProxyResult old = contact::update_proxy(params, *old_proxy, goal, f.velocity, f.dt, s.levels.query);
    chooser_.old_level(s.levels, false);
    out.force = s.levels.blend.blend(f.t, old.force, out.force);
    out.touching = out.touching || old.in_contact;
  }
  out.torque = arm.cross(out.force);
  out.frame_point = out.touching ? out.point : Vec3::Zero();
  out.contact_radius = contact::sphere_contact_radius(params.radius, r.depth);
  chooser_.finish(f.t, touched, out.force.norm(), s.levels, out);
  return out;
}

void ProxyOnObjects::react(const FrameInputs& frame, const Rendering& rendered, const Reaction& /*reaction*/,
                           AlgorithmState& state, ContactLoad& load) const {
  const auto& s = static_cast<const State&>(state);
  if (s.levels.touched == static_cast<int>(chooser_.objects().size())) {
    plane_load(*frame.contact, rendered.touching, load);
  } else {
    load.active = false;  // rigid objects take no load
  }
}

}  // namespace tactus::haptics
