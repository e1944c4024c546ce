#include "haptics/algorithms/fabric_proxy_on_patch.hpp"

#include <numeric>

namespace tactus::haptics {

FabricProxyOnPatch::FabricProxyOnPatch(const contact::FabricProxyParams& params, contact::LocalModelKind kind,
                                       contact::PatchCapacity capacity, bool spread_over_disc)
    : OnPatch(kind, capacity, spread_over_disc), proxy_(params) {}

FabricProxyOnPatch::State::State(contact::LocalModelKind kind, const contact::PatchCapacity& capacity)
    : PatchState(kind, capacity), candidates(static_cast<std::size_t>(capacity.triangles)) {
  std::iota(candidates.begin(), candidates.end(), 0);
}

std::unique_ptr<AlgorithmState> FabricProxyOnPatch::make_state() const {
  return std::make_unique<State>(kind(), capacity());
}

void FabricProxyOnPatch::begin(const FrameInputs& f, PatchState& state) const {
  auto& s = static_cast<State&>(state);
  if (!s.started) {  // the proxy starts free, where the finger is
    s.proxy = contact::make_fabric_proxy_state(f.position);
    s.started = true;
  }
}

void FabricProxyOnPatch::patch_replacing(PatchState& state) const {
  auto& s = static_cast<State&>(state);
  const contact::LocalPatch& old = s.local.patch();
  const std::int32_t t = s.proxy.triangle;
  s.surface_triangle = t >= 0 && t < old.triangle_count ? old.surface_triangle[static_cast<std::size_t>(t)] : -1;
}

void FabricProxyOnPatch::patch_replaced(PatchState& state) const {
  // The proxy rests on a material point of a triangle named by its patch index: found again
  // in the new patch, the proxy is carried by the fabric's motion over the simulation step
  // (its surface point is where that point was in the old patch); lost, it keeps its place.
  auto& s = static_cast<State&>(state);
  const contact::LocalPatch& patch = s.local.patch();
  std::int32_t found = -1;
  if (s.surface_triangle >= 0)
    for (int t = 0; t < patch.triangle_count && found < 0; ++t)
      if (patch.surface_triangle[static_cast<std::size_t>(t)] == s.surface_triangle) found = t;
  s.proxy.triangle = found;
}

Rendering FabricProxyOnPatch::against(const FrameInputs& f, PatchState& state, bool trial) const {
  auto& s = static_cast<State&>(state);
  contact::FabricProxyState copy;
  contact::FabricProxyState& proxy = trial ? (copy = s.proxy) : s.proxy;
  Rendering out;
  const contact::Pose pose{f.position, f.orientation};
  if (!s.local.valid()) {
    // No fabric near the finger: the proxy follows it freely.
    proxy = contact::make_fabric_proxy_state(f.position);
    return out;
  }
  const contact::LocalPatch& patch = s.local.patch();
  const auto count = static_cast<std::size_t>(patch.triangle_count);
  const contact::FabricProxyResult r =
      proxy_.update(proxy, pose, s.local.positions(), {patch.triangles.data(), count}, {s.candidates.data(), count},
                    f.dt > 0.0 ? f.dt : 1e-3);  // the first frame has no period yet: a nominal one
  out.touching = r.in_contact;
  out.force = r.force;
  out.torque = (r.contact_point - f.position).cross(r.force);
  if (r.in_contact && r.triangle >= 0) {
    out.point = r.contact_point;
    const double magnitude = r.force.norm();
    const Vec3 direction = magnitude > 0.0 ? Vec3(r.force / magnitude) : r.contact_normal;
    out.law_force = magnitude;
    out.contact_radius = 0.0;
    out.on_patch = {r.triangle, r.barycentric, direction, magnitude, proxy_.params().stiffness, disc_radius(0.0)};
  }
  return out;
}

void FabricProxyOnPatch::advance(const FrameInputs& f, const Rendering& /*rendered*/, const Reaction& /*reaction*/,
                                 bool /*on*/, const contact::PatchContact& on_patch, PatchState& state,
                                 ContactLoad& /*load*/) const {
  // The patch moves under the force sent; the proxy follows the material point it rests on
  // at its next update (FabricProxyState keeps it).
  state.local.advance(on_patch, f.dt);
}

}  // namespace tactus::haptics
