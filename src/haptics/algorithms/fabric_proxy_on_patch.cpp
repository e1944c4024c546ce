#include "haptics/algorithms/fabric_proxy_on_patch.hpp"

#include <limits>
#include <numeric>

#include "contact/grasp_state.hpp"

namespace tactus::haptics {
namespace {

/// The grasp's laws for a pair: the thumb is the finger on the front. A sheet held between
/// two pads rubs on both, so the pinch holds twice the pad–fabric coefficients (grasp.hpp).
contact::GraspParams grasp_params(const contact::FabricProxyParams& params, const TwoFingerParams& two) {
  contact::GraspParams g;
  const bool is_thumb = params.side > 0;
  g.thumb = is_thumb ? two.own : two.partner;
  g.index = is_thumb ? two.partner : two.own;
  g.fabric_thickness = two.fabric_thickness;
  g.capture_distance = two.capture_distance;
  g.hold_across_plane = false;  // nodes caught up to an edge length off the plane (capture_distance)
  g.static_friction = 2.0 * params.static_friction;
  g.kinetic_friction = 2.0 * params.kinetic_friction;
  return g;
}

/// The patch triangle whose centroid lies nearest `point` (−1 for an empty patch).
std::int32_t nearest_triangle(const contact::LocalPatch& patch, std::span<const Vec3> positions, const Vec3& point) {
  std::int32_t best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  for (int t = 0; t < patch.triangle_count; ++t) {
    const mesh::Triangle& tri = patch.triangles[static_cast<std::size_t>(t)];
    const Vec3 centroid = (positions[static_cast<std::size_t>(tri[0])] + positions[static_cast<std::size_t>(tri[1])] +
                           positions[static_cast<std::size_t>(tri[2])]) /
                          3.0;
    const double d = (centroid - point).squaredNorm();
    if (d < best_distance) {
      best_distance = d;
      best = t;
    }
  }
  return best;
}

}  // namespace

FabricProxyOnPatch::FabricProxyOnPatch(const contact::FabricProxyParams& params, contact::LocalModelKind kind,
                                       contact::PatchCapacity capacity, bool spread_over_disc,
                                       const std::optional<TwoFingerParams>& two_fingers)
    : OnPatch(kind, capacity, spread_over_disc), proxy_(params), is_thumb_(params.side > 0) {
  if (two_fingers) {
    const auto& two = *two_fingers;
    fingers_.emplace(is_thumb_ ? two.own : two.partner, is_thumb_ ? two.partner : two.own, two.finger_contact);
    grasp_.emplace(grasp_params(params, two));
  }
}

FabricProxyOnPatch::State::State(contact::LocalModelKind kind, const contact::PatchCapacity& capacity,
                                 const contact::Grasp* grasp_law)
    : PatchState(kind, capacity),
      candidates(static_cast<std::size_t>(capacity.triangles)),
      nodes(static_cast<std::size_t>(capacity.nodes)) {
  std::iota(candidates.begin(), candidates.end(), 0);
  std::iota(nodes.begin(), nodes.end(), 0);
  if (grasp_law) {
    grasp = grasp_law->make_state();
    trial_grasp = grasp_law->make_state();
  }
}

std::unique_ptr<AlgorithmState> FabricProxyOnPatch::make_state() const {
  return std::make_unique<State>(kind(), capacity(), grasp());
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
  // The grasp holds particles by their patch index too, but re-catches them every frame from
  // the new patch's nodes: it keeps its frame and targets, which ride with the fingers.
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
  Rendering out = on_fabric(f, s, proxy);
  with_partner(f, s, trial, proxy, out);
  return out;
}

Rendering FabricProxyOnPatch::on_fabric(const FrameInputs& f, State& s, contact::FabricProxyState& proxy) const {
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
  out.on_fabric = r.in_contact;
  out.slipping = r.in_contact && r.friction == contact::FrictionState::slip;
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

void FabricProxyOnPatch::with_partner(const FrameInputs& f, State& s, bool trial, contact::FabricProxyState& proxy,
                                      Rendering& out) const {
  const PeerFinger* peer = f.peer;
  if (!grasp_ || !fingers_) return;
  const bool partner_seen = peer && peer->valid;
  bool grasping = false, fingers_touch = false;
  if (partner_seen) {
    const contact::Pose own{f.position, f.orientation}, other{peer->position, peer->orientation};
    const contact::Pose& thumb = is_thumb_ ? own : other;
    const contact::Pose& index = is_thumb_ ? other : own;
    const contact::GraspParams& gp = grasp_->params();
    contact::GraspState& held = trial ? (s.trial_grasp = s.grasp) : s.grasp;  // the copy reuses reserved storage
    // The fabric is squeezed only once the pads come within its thickness of each other.
    const double gap =
        contact::capsule_capsule(contact::posed(gp.thumb, thumb), contact::posed(gp.index, index)).signed_distance;
    if (s.local.valid() && (held.active || gap < gp.fabric_thickness)) {
      const auto nodes = std::span<const std::int32_t>(s.nodes).first(static_cast<std::size_t>(s.local.patch().node_count));
      const contact::GraspResult g = grasp_->update(held, thumb, index, s.local.positions(), nodes);
      if (g.active) {
        grasping = true;
        out = Rendering{};
        out.force = is_thumb_ ? g.force_on_thumb : g.force_on_index;
        out.touching = true;
        out.on_fabric = true;
        out.slipping = g.friction == contact::FrictionState::slip;
        out.point = g.frame.origin;
        // The fabric takes the pull of the held particles, through this finger's share, at the
        // patch triangle nearest the grasp's centre; its stiffness is the hold's first slope.
        const double magnitude = out.force.norm();
        out.law_force = magnitude;
        const std::int32_t t = nearest_triangle(s.local.patch(), s.local.positions(), g.frame.origin);
        if (t >= 0)
          out.on_patch = {t, Vec3::Constant(1.0 / 3.0), magnitude > 0.0 ? Vec3(out.force / magnitude) : g.frame.normal(),
                          magnitude, gp.hold_law.b, disc_radius(0.0)};
        // The V-proxy lets go: after the grasp it starts afresh at the finger.
        proxy = contact::make_fabric_proxy_state(f.position);
      }
    } else if (held.active) {  // no patch any more: the grasp lets go
      held.active = false;
      held.held.clear();
      held.friction = contact::FrictionState::none;
    }
    contact::FingerContactState finger_copy;
    contact::FingerContactState& touch = trial ? (finger_copy = s.fingers) : s.fingers;
    if (grasping) {
      touch = {};  // skin meets skin afresh once the fabric is out from between them
    } else {
      const contact::FingerContactResult c = fingers_->update(touch, thumb, index);
      if (c.in_contact) {
        fingers_touch = true;
        out.force += is_thumb_ ? c.force_on_thumb : c.force_on_index;
        if (!out.touching) out.point = c.contact_point;
        out.touching = true;
        out.slipping = out.slipping || c.friction == contact::FrictionState::slip;
      }
    }
  }
  const bool own_on = out.on_fabric;
  const bool partner_on = partner_seen && peer->on_fabric;
  contact::ContactInputs inputs;
  inputs.thumb_on_fabric = is_thumb_ ? own_on : partner_on;
  inputs.index_on_fabric = is_thumb_ ? partner_on : own_on;
  inputs.fingers_touch = grasping || fingers_touch;
  inputs.dynamic_friction = out.slipping || (partner_seen && peer->slipping);
  out.contact_state = static_cast<std::uint8_t>(contact::classify(inputs));
  if (!trial) s.grasping = grasping;
}

void FabricProxyOnPatch::advance(const FrameInputs& f, const Rendering& /*rendered*/, const Reaction& /*reaction*/,
                                 bool /*on*/, const contact::PatchContact& on_patch, PatchState& state,
                                 ContactLoad& /*load*/) const {
  // The patch moves under the force sent; the proxy follows the material point it rests on
  // at its next update (FabricProxyState keeps it). A grasp holds the patch's particles
  // where the fingers take them: the patch is not dented by the squeeze (the other pad
  // pushes back on it, which this finger's patch does not know); the simulation gets the
  // pull (OnPatch::react has set the load).
  auto& s = static_cast<State&>(state);
  contact::PatchContact none;
  state.local.advance(s.grasping ? none : on_patch, f.dt);
}

}  // namespace tactus::haptics
