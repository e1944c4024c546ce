#include "haptics/haptic_step.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace tactus::haptics {
namespace {

using Kind = HapticEvent::Kind;

void emit(HapticOutputs& out, Kind kind, double value, std::int32_t detail = -1) {
  if (out.event_count < HapticOutputs::kMaxEvents)
    out.events[static_cast<std::size_t>(out.event_count++)] = {kind, value, detail};
}

/// A live edit of the coupling, taken once from its time on; bounded again here, the step
/// trusting no other thread.
void take_edit(const HapticModel& model, HapticState& s, const HapticInputs& in) {
  const SurfaceEdit* e = in.edit;
  if (!e || e->version == s.surface_version || in.t < e->from) return;
  s.surface_version = e->version;
  SurfaceValues v;
  v.stiffness = std::clamp(e->values.stiffness, 0.0, e->max_stiffness);
  if (!(v.stiffness > 0.0)) return;
  v.static_friction = std::max(0.0, e->values.static_friction);
  v.kinetic_friction = std::clamp(e->values.kinetic_friction, 0.0, v.static_friction);
  for (std::size_t i = 0; i < model.algorithms.size(); ++i) model.algorithms[i]->edit_surface(v, *s.algorithms[i]);
}

/// The frame as the algorithms see it: the tool in the scene, its velocity (a first-order
/// low-pass of finite differences, since device positions are quantized and the raw difference
/// is noisy at 1 kHz), and the channels' newest values.
FrameInputs frame_of(const HapticModel& model, HapticState& s, const HapticInputs& in) {
  FrameInputs f;
  f.t = in.t;
  f.position = model.map.to_scene(in.pose.position);
  f.orientation = model.map.to_scene(in.pose.orientation);
  f.dt = s.last_t >= 0.0 && in.t > s.last_t ? in.t - s.last_t : 1.0 / model.rate;
  if (s.last_t >= 0.0 && in.t > s.last_t) {
    const Vec3 raw = (f.position - s.last_position) / f.dt;
    s.velocity += f.dt / (model.velocity_filter + f.dt) * (raw - s.velocity);
  }
  s.last_position = f.position;
  s.last_t = in.t;
  f.velocity = s.velocity;
  f.contact = in.contact;
  f.contact_fresh = in.contact_fresh;
  f.patch = in.patch;
  f.patch_previous = in.patch_previous;
  f.patch_fresh = in.patch_fresh;
  f.surfaces = in.surfaces;
  f.surfaces_fresh = in.surfaces_fresh;
  f.peer = in.peer;
  f.smoothing = s.smoother.enabled();
  return f;
}

/// The contact-stage algorithm's index, or the number of algorithms when there is none.
std::size_t contact_index(const HapticModel& model) {
  for (std::size_t i = 0; i < model.algorithms.size(); ++i)
    if (model.algorithms[i]->stage() == ForceAlgorithm::Stage::contact) return i;
  return model.algorithms.size();
}

/// A tool without a contact algorithm: no force, the plane's time and point for the record.
Rendering nothing_touched(const LocalContact& contact) {
  Rendering r;
  r.surface_time = contact.surface_time;
  r.frame_point = plane_frame_point(contact);
  return r;
}

/// The overlays' force, summed.
Vec3 overlays(const HapticModel& model, HapticState& s, const FrameInputs& f) {
  Vec3 sum = Vec3::Zero();
  bool any = false;
  for (std::size_t i = 0; i < model.algorithms.size(); ++i) {
    if (model.algorithms[i]->stage() != ForceAlgorithm::Stage::overlay) continue;
    const Vec3 o = model.algorithms[i]->render(f, *s.algorithms[i]).force;
    sum = any ? Vec3(sum + o) : o;  // the first as it is: 0 + (−0) would turn a −0 into +0
    any = true;
  }
  return sum;
}

SafetyInput safety_input(const HapticModel& model, const HapticInputs& in, const Rendering& r, const Vec3& force,
                         const Vec3& overlay) {
  SafetyInput safe;
  safe.force = model.map.force_to_device(force + overlay);
  safe.torque = model.map.force_to_device(r.torque);
  safe.contact = r.touching;
  safe.last_simulation_update = r.surface_time;
  safe.device_alive = in.device_alive;
  safe.emergency_stop = in.emergency_stop;
  return safe;
}

Reaction reaction_to(const HapticModel& model, const SafetyInput& safe, const SafetyOutput& sent, const Vec3& overlay) {
  const double asked = safe.force.norm();
  Reaction reaction;
  reaction.kept = asked > 0.0 ? std::min(1.0, sent.force.norm() / asked) : 0.0;
  reaction.sent = model.map.rotation * sent.force - reaction.kept * overlay;
  return reaction;
}

/// Contact begins and ends, and the safety layer's flags as they rise.
void report_changes(HapticState& s, const HapticInputs& in, HapticOutputs& out) {
  if (out.touching != s.in_contact) {
    emit(out, out.touching ? Kind::contact_begin : Kind::contact_end, out.sent.force.norm());
    s.in_contact = out.touching;
  }
  const std::uint8_t rising = out.sent.flags & static_cast<std::uint8_t>(~s.last_flags);
  if (rising & kSafetyClamped) emit(out, Kind::force_clamped, out.requested_force);
  if (rising & kSafetyNonFinite) emit(out, Kind::non_finite_force, 0.0);
  if (rising & kSafetyWatchdog) emit(out, in.device_alive ? Kind::watchdog_trip : Kind::device_stall, 0.0);
  if (rising & kSafetyEmergencyStop) emit(out, Kind::emergency_stop, 0.0);
  s.last_flags = out.sent.flags;
}

}  // namespace

const ForceAlgorithm* HapticModel::contact() const {
  for (const auto& a : algorithms)
    if (a->stage() == ForceAlgorithm::Stage::contact) return a.get();
  return nullptr;
}

HapticState::HapticState(const HapticModel& model)
    : smoother(model.force_smoothing), passivity(model.passivity_control, model.max_damping), safety(model.safety) {
  int contacts = 0;
  for (const auto& a : model.algorithms) {
    contacts += a->stage() == ForceAlgorithm::Stage::contact ? 1 : 0;
    algorithms.push_back(a->make_state());
  }
  if (contacts > 1) throw std::invalid_argument("a device renders at most one contact algorithm (and any overlays)");
}

void haptic_step(const HapticModel& model, HapticState& s, const HapticInputs& in, ForceSink& sink, HapticOutputs& out) {
  out.event_count = 0;
  take_edit(model, s, in);
  FrameInputs f = frame_of(model, s, in);

  // The contact: its algorithm, the smoothing of model updates, the passivity controller.
  const std::size_t c = contact_index(model);
  const Rendering r = c < model.algorithms.size() ? model.algorithms[c]->render(f, *s.algorithms[c])
                                                  : nothing_touched(*in.contact);
  if (r.has_event) emit(out, r.event.kind, r.event.value, r.event.detail);
  if (r.model_changed) s.smoother.model_changed(r.before, r.after);
  const Vec3 force = s.passivity.apply(s.smoother.apply(r.force, f.position, f.velocity, f.dt), r.touching,
                                       f.position, f.velocity, f.dt);

  // Overlays join after the smoothing: a pulse beat is no model update.
  f.contact_force = force;
  f.contact_touching = r.touching;
  const Vec3 overlay = overlays(model, s, f);

  // The safety layer, and the force written at once.
  const SafetyInput safe = safety_input(model, in, r, force, overlay);
  out.sent = s.safety.apply(safe, in.t);
  sink.write(out.sent.force, out.sent.torque);

  // The tissue feels what the hand feels: the reaction of the force actually sent, less the
  // overlays (the vessel beneath pushes the pulse), scaled as the safety layer scaled the total.
  const Reaction reaction = reaction_to(model, safe, out.sent, overlay);
  s.passivity.record_sent(reaction.sent);
  ContactLoad& load = *out.load;
  load.part_count = 0;
  load.shaft = false;
  load.bilateral = false;
  load.hold_plane_normal = Vec3::Zero();
  load.force = -reaction.sent;
  load.stiffness = 0.0;  // a constant push unless the algorithm knows its slope
  load.surface_offset = 0.0;
  load.published_point = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  if (c < model.algorithms.size())
    model.algorithms[c]->react(f, r, reaction, *s.algorithms[c], load);
  else
    plane_load(*in.contact, r.touching, load);
  load.contact_radius = model.spread_over_contact_disc ? r.contact_radius : -1.0;
  load.pad = r.pad;

  out.requested_force = safe.force.norm();
  out.touching = r.touching;
  out.position = f.position;
  out.orientation = f.orientation;
  out.frame_point = r.frame_point;
  out.tool_axis = r.tool_axis;
  out.finger = {true, f.position, f.orientation, r.on_fabric, r.slipping, r.held};
  if (r.contact_state != 0 && r.contact_state != s.contact_state) {
    emit(out, Kind::contact_state, r.contact_state);
    s.contact_state = r.contact_state;
  }
  report_changes(s, in, out);
}

void plane_load(const LocalContact& contact, bool touching, ContactLoad& load) {
  load.active = touching && contact.valid;
  load.body = contact.body;
  load.triangle = contact.triangle;
  load.barycentric = contact.barycentric;
}

void ForceAlgorithm::react(const FrameInputs& frame, const Rendering& rendered, const Reaction& /*reaction*/,
                           AlgorithmState& /*state*/, ContactLoad& load) const {
  plane_load(*frame.contact, rendered.touching, load);
}

}  // namespace tactus::haptics
