#include "haptics/algorithms/fabric_proxy_on_patch.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <tuple>
#include <utility>

#include "contact/closest_point.hpp"
#include "contact/grasp_state.hpp"

namespace tactus::haptics {
namespace {

/// When the pads open the grasp's force has faded with the squeeze, but the finger may still
/// press the bunched fabric the grasp held between the pads, which the V-proxy meets afresh:
/// its force comes in over this time instead of in one frame (it stepped by 1.09 N). A grasp
/// that starts comes in over the same time.
constexpr double kHandOverTime = 0.02;  // s

/// How far a slipping pinch's hold moves over the fabric in a frame, at most: 0.25 m/s at
/// 1 kHz, faster than a pinch slides, and the pull onto the pads' plane changes by at most
/// the hold's stiffness times this (0.05 N at 190 N/m) when the sheet there lies off it.
constexpr double kHoldTravel = 0.25e-3;  // m

/// The grasp's laws for a pair: the thumb is the finger on the front. A sheet held between
/// two pads rubs on both, so the pinch holds twice the pad–fabric coefficients (grasp.hpp).
contact::GraspParams grasp_params(const contact::FabricProxyParams& params, const TwoFingerParams& two) {
  contact::GraspParams g;
  const bool is_thumb = params.side > 0;
  g.thumb = is_thumb ? two.own : two.partner;
  g.index = is_thumb ? two.partner : two.own;
  g.fabric_thickness = two.fabric_thickness;
  g.static_friction = 2.0 * params.static_friction;
  g.kinetic_friction = 2.0 * params.kinetic_friction;
  return g;
}

/// The point of the patch nearest `point`: its triangle (−1 for an empty patch) and
/// barycentric coordinates. Both fingers' loops find the same material point there, whichever
/// of the triangles around it each patch lists first.
std::pair<std::int32_t, Vec3> nearest_point(const contact::LocalPatch& patch, std::span<const Vec3> positions,
                                            const Vec3& point) {
  std::int32_t best = -1;
  Vec3 barycentric = Vec3::Zero();
  double best_distance = std::numeric_limits<double>::infinity();
  for (int t = 0; t < patch.triangle_count; ++t) {
    const mesh::Triangle& tri = patch.triangles[static_cast<std::size_t>(t)];
    const contact::TrianglePoint q = contact::closest_point_on_triangle(
        point, positions[static_cast<std::size_t>(tri[0])], positions[static_cast<std::size_t>(tri[1])],
        positions[static_cast<std::size_t>(tri[2])]);
    const double d = (q.point - point).squaredNorm();
    if (d < best_distance) {
      best_distance = d;
      best = t;
      barycentric = q.barycentric;
    }
  }
  return {best, barycentric};
}

/// The patch's triangle that is the body's surface triangle `surface_triangle`; −1 where the
/// patch does not reach it.
std::int32_t patch_triangle_of(const contact::LocalPatch& patch, std::int32_t surface_triangle) {
  if (surface_triangle < 0) return -1;
  for (int t = 0; t < patch.triangle_count; ++t)
    if (patch.surface_triangle[static_cast<std::size_t>(t)] == surface_triangle) return t;
  return -1;
}

/// The patch's triangle under a material point of its body; −1 for another body's point or
/// one the patch does not reach.
std::int32_t patch_triangle_of(const contact::LocalPatch& patch, const MaterialPoint& point) {
  return point.valid() && point.body == patch.body ? patch_triangle_of(patch, point.triangle) : -1;
}

}  // namespace

FabricProxyOnPatch::FabricProxyOnPatch(const contact::FabricProxyParams& params, contact::LocalModelKind kind,
                                       contact::PatchCapacity capacity, bool spread_over_disc,
                                       const std::optional<TwoFingerParams>& two_fingers)
    : OnPatch(kind, capacity, spread_over_disc), proxy_(params), is_thumb_(params.side > 0) {
  if (two_fingers) {
    const auto& two = *two_fingers;
    fingers_.emplace(is_thumb_ ? two.own : two.partner, is_thumb_ ? two.partner : two.own, two.finger_contact);
    // The hold is the V-proxy's own coupling, finger and fabric in series: the grasp takes
    // over from the two proxies without a change of stiffness.
    grasp_.emplace(grasp_params(params, two), params.stiffness);
  }
}

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
  const std::int32_t h = s.held_triangle;
  s.held_surface_triangle = h >= 0 && h < old.triangle_count ? old.surface_triangle[static_cast<std::size_t>(h)] : -1;
}

void FabricProxyOnPatch::patch_replaced(PatchState& state) const {
  // The proxy rests on a material point of a triangle named by its patch index: found again
  // in the new patch, the proxy is carried by the fabric's motion over the simulation step
  // (its surface point is where that point was in the old patch); lost, it keeps its place.
  // The grasp's held point is found again the same way (lost: the grasp lets go).
  auto& s = static_cast<State&>(state);
  const contact::LocalPatch& patch = s.local.patch();
  s.proxy.triangle = patch_triangle_of(patch, s.surface_triangle);
  s.held_triangle = patch_triangle_of(patch, s.held_surface_triangle);
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
    contact::PointGraspState copy;
    contact::PointGraspState& held = trial ? (copy = s.grasp) : s.grasp;
    // The grasp starts where the pads close on the fabric between them: it holds the fabric's
    // point nearest the pads' centre, if that lies within the capture distance of both pads.
    // The V-proxies need not touch the sheet at that frame: on a hanging sheet, which gives
    // way under the lightest push, each loses and finds it again every few frames, and a
    // real-time pair seldom had both on it in the same frame. The pinch is one grasp of one
    // material point: a finger whose partner holds the fabric takes hold of the partner's
    // point as soon as its patch reaches it (each loop's patch follows the simulation at its
    // own frame, and one that lagged left a pad squeezing alone).
    std::int32_t triangle = s.held_triangle;
    Vec3 barycentric = s.held_barycentric;
    bool may_start = false;
    if (!held.active && s.local.valid()) {
      const std::int32_t partners = patch_triangle_of(s.local.patch(), peer->held);
      if (partners >= 0) {
        triangle = partners;
        barycentric = peer->held.barycentric;
        may_start = true;
      } else {
        const contact::Capsule thumb_pad = contact::posed(gp.thumb, thumb), index_pad = contact::posed(gp.index, index);
        const contact::CapsulePair pads = contact::capsule_capsule(thumb_pad, index_pad);
        if (pads.signed_distance < gp.fabric_thickness) {
          std::tie(triangle, barycentric) =
              nearest_point(s.local.patch(), s.local.positions(), 0.5 * (pads.on_first + pads.on_second));
          const Vec3 between = s.local.point(triangle, barycentric);
          may_start = contact::point_capsule(between, thumb_pad).signed_distance <= gp.capture_distance &&
                      contact::point_capsule(between, index_pad).signed_distance <= gp.capture_distance;
        }
      }
    }
    const Vec3 point = s.local.point(triangle, barycentric);
    const contact::PointGraspResult g = grasp_->update(held, thumb, index, point, may_start);
    if (!trial && g.active && g.friction == contact::FrictionState::slip) {
      // The pinch slides over the fabric: the hold moves over the material toward the pads'
      // centre, at most kHoldTravel a frame. Where the sheet beside the held point lies off
      // the pads' plane (a fold beside the pinch), the hold pulls each new point onto it: a
      // jump to the material at the centre stepped that pull, and the force on both fingers,
      // in a frame, and refusing it left the hold up to 15 mm behind the pinch, off the pads.
      const Vec3 e3 = g.frame.normal();
      const Vec3 to_centre = g.frame.origin - point;
      const Vec3 in_plane = to_centre - e3 * e3.dot(to_centre);
      const double distance = in_plane.norm();
      if (distance > 0.0) {
        const Vec3 probe = point + std::min(distance, kHoldTravel) / distance * in_plane;
        const auto [moved_to, moved_barycentric] = nearest_point(s.local.patch(), s.local.positions(), probe);
        if (moved_to >= 0) {
          const Vec3 moved = s.local.point(moved_to, moved_barycentric);
          const double off_plane = std::abs(e3.dot(moved - g.frame.origin));
          if (off_plane <= std::max(std::abs(e3.dot(point - g.frame.origin)), gp.fabric_thickness) + kHoldTravel) {
            contact::PointGrasp::move_hold(held, point, moved);
            triangle = moved_to;
            barycentric = moved_barycentric;
          }
        }
      }
    }
    if (!trial) {
      s.held_triangle = g.active ? triangle : -1;
      s.held_barycentric = barycentric;
    }
    if (g.active) {
      grasping = true;
      out = Rendering{};
      out.force = is_thumb_ ? g.force_on_thumb : g.force_on_index;
      out.touching = true;
      out.on_fabric = true;
      out.slipping = g.friction == contact::FrictionState::slip;
      out.point = point;
      // The fabric takes this finger's share at the held point (the two shares' squeezes
      // cancel there, leaving the hold); its stiffness is the hold's.
      const double magnitude = out.force.norm();
      out.law_force = magnitude;
      out.on_patch = {triangle, barycentric, magnitude > 0.0 ? Vec3(out.force / magnitude) : g.frame.normal(), magnitude,
                      grasp_->hold_stiffness(), disc_radius(0.0)};
      // The fabric takes the hold (the pads' squeezes cancel on it), split between the two
      // loops: the thumb's across the pads' plane, the index's along it.
      if (!trial) {
        const Vec3 e3 = g.frame.normal();
        const Vec3 across = e3.dot(g.hold) * e3;
        s.fabric_share = is_thumb_ ? across : Vec3(g.hold - across);
        s.pads_normal = e3;
      }
      out.held = {s.local.patch().body, s.local.patch().surface_triangle[static_cast<std::size_t>(triangle)],
                  barycentric};
      const contact::Capsule pad = contact::posed(is_thumb_ ? gp.thumb : gp.index, is_thumb_ ? thumb : index);
      const Vec3 toward_partner = is_thumb_ ? g.frame.normal() : Vec3(-g.frame.normal());
      out.pad = {true, pad.base, pad.tip, pad.radius, g.frame.origin, toward_partner};
      // The pinch acts on the pad where it meets the fabric, the pad's point nearest the held
      // point: about the tool's origin its pull along the plane turns the finger, as the
      // V-proxy's drag does.
      out.torque = (contact::point_capsule(point, pad).surface_point - f.position).cross(out.force);
      // The V-proxy lets go: after the grasp it starts afresh at the finger.
      proxy = contact::make_fabric_proxy_state(f.position);
    }
    contact::FingerContactState finger_copy;
    contact::FingerContactState& touch = trial ? (finger_copy = s.fingers) : s.fingers;
    if (grasping) {
      touch = {};  // skin meets skin afresh once the fabric is out from between them
    } else {
      const contact::FingerContactResult c = fingers_->update(touch, thumb, index);
      if (c.in_contact) {
        fingers_touch = true;
        const Vec3& on_this = is_thumb_ ? c.force_on_thumb : c.force_on_index;
        out.force += on_this;
        out.torque += (c.contact_point - f.position).cross(on_this);
        if (!out.touching) out.point = c.contact_point;
        out.touching = true;
        out.slipping = out.slipping || c.friction == contact::FrictionState::slip;
      }
    }
  }
  // The hand-over: when a grasp ends, or starts, the new rendering's force and torque (and
  // what the fabric takes of it) ramp in from those the last frame rendered: a finger whose
  // patch lost the held point while its partner held on rejoins at its next patch, and that
  // frame would step its force by the whole grasp.
  const bool handed_now = s.grasping != grasping;
  const double handed_at = handed_now ? f.t : s.handed_over_at;
  const Vec3 from = handed_now ? s.last_force : s.handed_over_from;
  const Vec3 from_torque = handed_now ? s.last_torque : s.handed_over_torque;
  if (handed_at >= 0.0 && f.t - handed_at < kHandOverTime) {
    const double w = std::clamp((f.t - handed_at) / kHandOverTime, 0.0, 1.0);
    out.force = (1.0 - w) * from + w * out.force;
    out.torque = (1.0 - w) * from_torque + w * out.torque;
    out.law_force = out.force.norm();
    if (!trial && grasping) s.fabric_share *= w;
  }
  if (!trial) {
    s.handed_over_at = handed_at;
    s.handed_over_from = from;
    s.handed_over_torque = from_torque;
    s.last_force = out.force;
    s.last_torque = out.torque;
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

void FabricProxyOnPatch::advance(const FrameInputs& f, const Rendering& /*rendered*/, const Reaction& reaction,
                                 bool on, const contact::PatchContact& on_patch, PatchState& state,
                                 ContactLoad& load) const {
  // The patch moves under the force sent; the proxy follows the material point it rests on
  // at its next update (FabricProxyState keeps it). In a grasp the patch keeps the shape the
  // simulation published: this finger's force, mostly the squeeze, would dent it alone (the
  // other pad pushes back on the same point in its own patch), and left without a contact
  // its free nodes run away within milliseconds of an update.
  auto& s = static_cast<State&>(state);
  if (!s.grasping) {
    state.local.advance(on_patch, f.dt);
    return;
  }
  // The fabric takes this finger's part of the hold, scaled as the safety layer scaled the
  // force sent, with the hold's slope: the thumb's across the pads' plane, as a spring that
  // pulls back as well (the hold holds the point on the plane from both sides), the index's
  // along it, in the whole plane. Sent along each finger's force, mostly the squeeze, the
  // push coupled the held point into the simulation's step across the plane only; along it
  // the hold came from where the point was when the patch was published, and in real time,
  // with steps late by tens of milliseconds, the held point moved by up to 9 mm from one step
  // to the next.
  if (on && grasp_) {
    const double kept = std::clamp(reaction.kept, 0.0, 1.0);
    load.force = kept * s.fabric_share;
    load.stiffness = kept * grasp_->hold_stiffness();
    load.bilateral = is_thumb_;
    load.hold_plane_normal = is_thumb_ ? Vec3::Zero() : s.pads_normal;
  }
}

}  // namespace tactus::haptics
