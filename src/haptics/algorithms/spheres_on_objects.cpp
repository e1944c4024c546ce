#include "haptics/algorithms/spheres_on_objects.hpp"

#include <algorithm>

#include "contact/load_spread.hpp"
#include "core/error.hpp"

namespace tactus::haptics {

namespace {

double reach_of(const std::vector<ToolSphere>& spheres) {
  double r = 0.0;
  for (const ToolSphere& s : spheres) r = std::max(r, s.offset.norm() + s.radius);
  return r;
}

}  // namespace

struct SpheresOnObjects::State final : AlgorithmState {
  LevelChooser::State levels;
};

SpheresOnObjects::SpheresOnObjects(std::vector<ToolSphere> spheres, std::vector<ContactLaw> laws, double damping,
                                   std::vector<TouchableObject> objects, const ObjectsSettings& settings)
    : spheres_(std::move(spheres)),
      laws_(std::move(laws)),
      damping_(damping),
      chooser_(std::move(objects), settings, reach_of(spheres_)) {
  if (laws_.size() != chooser_.objects().size() + 1)
    throw InputError("spheres among objects: one contact law per object and one for the contact plane");
}

std::unique_ptr<AlgorithmState> SpheresOnObjects::make_state() const {
  auto s = std::make_unique<State>();
  s->levels = chooser_.make_state();
  return s;
}

std::span<const std::size_t> SpheresOnObjects::levels_in_use(const AlgorithmState& state) {
  return static_cast<const State&>(state).levels.level;
}

SpheresOnObjects::Pressed SpheresOnObjects::press(const FrameInputs& f, const LevelChooser::State& levels) const {
  Pressed out;
  const std::size_t n = chooser_.objects().size();
  double largest = -1.0;
  for (const ToolSphere& sphere : spheres_) {
    const Vec3 arm = f.orientation * sphere.offset;
    const Vec3 centre = f.position + arm;
    const contact::ClosestSurfacePoint c = levels.query.closest_point(centre);
    const int member = levels.query.last_member();
    if (!c.found || member < 0) continue;
    const double depth = sphere.radius - (c.behind ? -c.distance : c.distance);
    if (!(depth > 0.0)) continue;
    // The law and the curvature of what the sphere touches: the object's level, or the plane.
    double curvature = 0.0, modulus_factor = 1.0;
    const ContactLaw& law = laws_[static_cast<std::size_t>(member)];
    if (member < static_cast<int>(n)) {
      const auto object = static_cast<std::size_t>(member);
      curvature = chooser_.level_of(levels, object).mean_curvature_at(c.triangle % ObjectsQuery::kObjectStride, c.barycentric);
      // E and ν painted where the sphere presses (0: the object's material, the law's own).
      if (const auto& images = chooser_.objects()[object].properties) {
        using property_images::Channel;
        const property_images::SurfaceProperties m = images->lookup(c.point, c.normal).properties;
        if (m[Channel::young_modulus] > 0.0)
          modulus_factor = law.modulus_factor({m[Channel::young_modulus], m[Channel::poisson_ratio]});
      }
    } else {
      curvature = f.contact->mean_curvature;
    }
    const double fn =
        std::max(0.0, modulus_factor * law.force(depth, curvature, law.stiffness()) - damping_ * c.normal.dot(f.velocity));
    out.touching = true;
    out.force += fn * c.normal;
    out.torque += arm.cross(fn * c.normal);
    out.contact_radius = std::max(out.contact_radius, contact::sphere_contact_radius(sphere.radius, depth));
    if (fn > largest) {
      largest = fn;
      out.member = member;
      out.point = c.point;
    }
  }
  return out;
}

Rendering SpheresOnObjects::render(const FrameInputs& f, AlgorithmState& state) const {
  auto& s = static_cast<State&>(state);
  const Vec3 origin = f.position + f.orientation * spheres_.front().offset;
  chooser_.choose(f.t, origin, origin, *f.contact, s.levels);
  Pressed now = press(f, s.levels);
  if (chooser_.blending(f.t, s.levels)) {
    chooser_.old_level(s.levels, true);
    const Pressed old = press(f, s.levels);
    chooser_.old_level(s.levels, false);
    now.force = s.levels.blend.blend(f.t, old.force, now.force);
    now.torque = s.levels.blend.blend(f.t, old.torque, now.torque);
    now.touching = now.touching || old.touching;
  }
  Rendering out;
  out.force = now.force;
  out.torque = now.torque;
  out.touching = now.touching;
  out.point = now.point;
  out.frame_point = now.touching ? now.point : Vec3::Zero();
  out.contact_radius = now.contact_radius;
  out.law_force = now.force.norm();
  out.surface_time = now.member == static_cast<int>(chooser_.objects().size()) ? f.contact->surface_time : f.t;
  chooser_.finish(f.t, now.member, now.force.norm(), s.levels, out);
  return out;
}

void SpheresOnObjects::react(const FrameInputs& frame, const Rendering& rendered, const Reaction& /*reaction*/,
                             AlgorithmState& state, ContactLoad& load) const {
  const auto& s = static_cast<const State&>(state);
  if (s.levels.touched == static_cast<int>(chooser_.objects().size()))
    plane_load(*frame.contact, rendered.touching, load);
  else
    load.active = false;  // rigid objects take no load
}

}  // namespace tactus::haptics
