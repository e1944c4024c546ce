#include "haptics/algorithms/spheres_on_patch.hpp"

#include <algorithm>

#include "contact/load_spread.hpp"

namespace tactus::haptics {

std::unique_ptr<AlgorithmState> SpheresOnPatch::make_state() const {
  auto s = std::make_unique<State>(kind(), capacity());
  s->stiffness = law_.stiffness();
  return s;
}

EditableSurface SpheresOnPatch::editable_surface() const { return law_.editable_surface(!spheres_.empty()); }

void SpheresOnPatch::edit_surface(const SurfaceValues& v, AlgorithmState& state) const {
  static_cast<State&>(state).stiffness = v.stiffness;
}

Rendering SpheresOnPatch::against(const FrameInputs& f, PatchState& state, bool /*trial*/) const {
  auto& s = static_cast<State&>(state);
  Rendering out;
  s.contact_count = 0;
  if (!s.local.valid()) return out;
  const contact::SurfaceQuery& surface = s.surface();
  const double curvature = f.contact->mean_curvature;
  // Every sphere against the patch's current triangles: each sphere's own contact dents the
  // patch, and goes to the simulation with its share of the load (advance()); the deepest
  // one's is the frame's contact point.
  double deepest = 0.0;
  for (const ToolSphere& sphere : spheres_) {
    const Vec3 arm = f.orientation * sphere.offset;
    const Vec3 centre = f.position + arm;
    const contact::ClosestSurfacePoint p = surface.closest_point(centre);
    if (!p.found) continue;
    const double signed_distance = p.behind ? -p.distance : p.distance;
    const double depth = sphere.radius - signed_distance;
    if (!(depth > 0.0)) continue;
    const Vec3 normal = !p.behind && p.distance > 1e-12 ? Vec3((centre - p.point) / p.distance) : p.normal;
    const double elastic = law_.force(depth, curvature, s.stiffness);
    const double fn = std::max(0.0, elastic - damping_ * normal.dot(f.velocity));
    out.touching = true;
    out.force += fn * normal;
    out.torque += arm.cross(fn * normal);
    out.law_force += fn;
    constexpr double kProbe = 1e-6;  // [m]: the law's slope by a forward difference
    const double slope = std::max(0.0, (law_.force(depth + kProbe, curvature, s.stiffness) - elastic) / kProbe);
    if (s.contact_count < contact::LocalModel::kMaxContacts)
      s.contacts[static_cast<std::size_t>(s.contact_count++)] = {
          p.triangle, p.barycentric, normal, fn, slope, disc_radius(contact::sphere_contact_radius(sphere.radius, depth))};
    if (depth > deepest) {
      deepest = depth;
      out.point = p.point;
      out.contact_radius = contact::sphere_contact_radius(sphere.radius, depth);
      out.on_patch = {p.triangle, p.barycentric, normal, 0.0, slope, disc_radius(out.contact_radius)};
    }
  }
  out.on_patch.force = out.law_force;
  return out;
}

void SpheresOnPatch::advance(const FrameInputs& f, const Rendering& rendered, const Reaction& reaction, bool on,
                             const contact::PatchContact& on_patch, PatchState& state, ContactLoad& load) const {
  auto& s = static_cast<State&>(state);
  if (!(on && s.contact_count > 1)) {
    s.local.advance(on_patch, f.dt);
    return;
  }
  // A sphere-set finger: each touching sphere dents the patch under its own force, all
  // scaled as the safety layer scaled the total.
  const contact::LocalPatch& patch = s.local.patch();
  const double rendered_norm = rendered.force.norm();
  const double scale = rendered_norm > 0.0 ? std::clamp(reaction.sent.norm() / rendered_norm, 0.0, 1.0) : 0.0;
  for (int i = 0; i < s.contact_count; ++i) {
    s.contacts[static_cast<std::size_t>(i)].force *= scale;
    s.contacts[static_cast<std::size_t>(i)].stiffness *= scale;
  }
  s.local.advance({s.contacts.data(), static_cast<std::size_t>(s.contact_count)}, f.dt);
  // The tissue takes each sphere's force where that sphere touches, in proportion; the
  // spheres' slopes add up as the tissue gives way under all of them.
  double total = 0.0;
  load.stiffness = 0.0;
  for (int i = 0; i < s.contact_count; ++i) {
    total += s.contacts[static_cast<std::size_t>(i)].force;
    load.stiffness += s.contacts[static_cast<std::size_t>(i)].stiffness;
  }
  for (int i = 0; i < s.contact_count && i < ContactLoad::kMaxParts && total > 0.0; ++i) {
    const contact::PatchContact& c = s.contacts[static_cast<std::size_t>(i)];
    if (c.triangle < 0 || c.triangle >= patch.triangle_count || !(c.force > 0.0)) continue;
    load.parts[static_cast<std::size_t>(load.part_count++)] = {
        patch.surface_triangle[static_cast<std::size_t>(c.triangle)], c.barycentric, c.force / total, c.contact_radius};
  }
}

}  // namespace tactus::haptics
