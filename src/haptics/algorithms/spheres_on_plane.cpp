#include "haptics/algorithms/spheres_on_plane.hpp"

#include <algorithm>

#include "contact/load_spread.hpp"

namespace tactus::haptics {

std::unique_ptr<AlgorithmState> SpheresOnPlane::make_state() const {
  auto s = std::make_unique<State>();
  s->stiffness = law_.stiffness();
  return s;
}

EditableSurface SpheresOnPlane::editable_surface() const { return law_.editable_surface(!spheres_.empty()); }

void SpheresOnPlane::edit_surface(const SurfaceValues& v, AlgorithmState& state) const {
  static_cast<State&>(state).stiffness = v.stiffness;
}

Rendering SpheresOnPlane::against(const LocalContact& plane, const FrameInputs& f, PlaneState& state,
                                  bool /*trial*/) const {
  const auto& s = static_cast<const State&>(state);
  Rendering out;
  out.point = plane.point;
  if (!plane.valid) return out;
  // Penetration of each contact sphere into the plane.
  const double normal_speed = plane.normal.dot(f.velocity);
  for (const ToolSphere& sphere : spheres_) {
    const Vec3 arm = f.orientation * sphere.offset;
    const double depth = sphere.radius - plane.normal.dot(f.position + arm - plane.point);
    if (!(depth > 0.0)) continue;
    out.touching = true;
    out.contact_radius = std::max(out.contact_radius, contact::sphere_contact_radius(sphere.radius, depth));
    const double fn = std::max(0.0, law_.force(depth, plane.mean_curvature, s.stiffness) - damping_ * normal_speed);
    out.force += fn * plane.normal;
    out.torque += arm.cross(fn * plane.normal);
  }
  return out;
}

}  // namespace tactus::haptics
