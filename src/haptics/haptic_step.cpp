#include "haptics/haptic_step.hpp"

#include <algorithm>
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

/// A tool without a contact algorithm: no force, the plane's time and point for the record.
Rendering nothing_touched(const LocalContact& contact) {
  Rendering r;
  r.surface_time = contact.surface_time;
  r.frame_point = plane_frame_point(contact);
  return r;
}

}  // namespace

const ForceAlgorithm* HapticModel::contact() const {
  for (const auto& a : algorithms)
    if (a->stage() == ForceAlgorithm::Stage::contact) return a.get();
  return nullptr;
}

HapticState::HapticState(const HapticModel& model)
    : smoother(model.force_smoothing), passivity(model.passivity_control), safety(model.safety) {
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
  FrameInputs f;
  f.t = in.t;
  f.position = model.map.to_scene(in.pose.position);
  f.orientation = model.map.to_scene(in.pose.orientation);
  // Tool velocity for damping and friction: a first-order low-pass of finite differences,
  // since device positions are quantized and the raw difference is noisy at 1 kHz.
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
  f.patch_fresh = in.patch_fresh;
  f.surfaces = in.surfaces;
  f.surfaces_fresh = in.surfaces_fresh;
  f.smoothing = s.smoother.enabled();

  // The contact: its algorithm, the smoothing of model updates, the passivity controller.
  std::size_t contact_index = model.algorithms.size();
  for (std::size_t i = 0; i < model.algorithms.size(); ++i)
    if (model.algorithms[i]->stage() == ForceAlgorithm::Stage::contact) contact_index = i;
  const Rendering r = contact_index < model.algorithms.size()
                          ? model.algorithms[contact_index]->render(f, *s.algorithms[contact_index])
                          : nothing_touched(*in.contact);
  if (r.has_event) emit(out, r.event.kind, r.event.value, r.event.detail);
  if (r.model_changed) s.smoother.model_changed(r.before, r.after);
  const bool touching = r.touching;
  const Vec3 force = s.passivity.apply(s.smoother.apply(r.force, f.position, f.velocity, f.dt), touching, f.position,
                                       f.velocity, f.dt);

  // Overlays join after the smoothing: a pulse beat is no model update.
  f.contact_force = force;
  f.contact_touching = touching;
  Vec3 overlay = Vec3::Zero();
  bool overlaid = false;
  for (std::size_t i = 0; i < model.algorithms.size(); ++i) {
    if (model.algorithms[i]->stage() != ForceAlgorithm::Stage::overlay) continue;
    const Vec3 o = model.algorithms[i]->render(f, *s.algorithms[i]).force;
    overlay = overlaid ? Vec3(overlay + o) : o;
    overlaid = true;
  }

  SafetyInput safe;
  safe.force = model.map.force_to_device(force + overlay);
  safe.torque = model.map.force_to_device(r.torque);
  safe.contact = touching;
  safe.last_simulation_update = r.surface_time;
  safe.device_alive = in.device_alive;
  safe.emergency_stop = in.emergency_stop;
  out.sent = s.safety.apply(safe, in.t);
  sink.write(out.sent.force, out.sent.torque);

  // The tissue feels what the hand feels: the reaction of the force actually sent, less the
  // overlays (the vessel beneath pushes the pulse), scaled as the safety layer scaled the total.
  const double in_norm = safe.force.norm();
  Reaction reaction;
  reaction.kept = in_norm > 0.0 ? std::min(1.0, out.sent.force.norm() / in_norm) : 0.0;
  reaction.sent = model.map.rotation * out.sent.force - reaction.kept * overlay;
  s.passivity.record_sent(reaction.sent);
  ContactLoad& load = *out.load;
  load.part_count = 0;
  load.shaft = false;
  load.force = -reaction.sent;
  if (contact_index < model.algorithms.size())
    model.algorithms[contact_index]->react(f, r, reaction, *s.algorithms[contact_index], load);
  else
    plane_load(*in.contact, touching, load);
  load.contact_radius = model.spread_over_contact_disc ? r.contact_radius : -1.0;

  out.requested_force = in_norm;
  out.touching = touching;
  out.position = f.position;
  out.frame_point = r.frame_point;
  out.tool_axis = r.tool_axis;
  if (touching != s.in_contact) {
    emit(out, touching ? Kind::contact_begin : Kind::contact_end, out.sent.force.norm());
    s.in_contact = touching;
  }
  const std::uint8_t rising = out.sent.flags & static_cast<std::uint8_t>(~s.last_flags);
  if (rising & kSafetyClamped) emit(out, Kind::force_clamped, in_norm);
  if (rising & kSafetyNonFinite) emit(out, Kind::non_finite_force, 0.0);
  if (rising & kSafetyWatchdog) emit(out, in.device_alive ? Kind::watchdog_trip : Kind::device_stall, 0.0);
  if (rising & kSafetyEmergencyStop) emit(out, Kind::emergency_stop, 0.0);
  s.last_flags = out.sent.flags;
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
