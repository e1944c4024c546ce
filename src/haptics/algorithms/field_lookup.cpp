#include "haptics/algorithms/field_lookup.hpp"

namespace tactus::haptics {

Rendering FieldLookup::render(const FrameInputs& f, AlgorithmState& /*state*/) const {
  const Vec3 arm = f.orientation * offset_;
  FieldForce field;
  if (point_) {
    // The partner's newest frame, one haptic period old at most (its loop publishes it).
    const bool partner = f.peer && f.peer->valid;
    const Vec3 other = partner ? Vec3(f.peer->position + f.peer->orientation * point_->partner_offset) : Vec3::Zero();
    field = field_->force_on(point_->finger, f.position + arm, f.orientation, partner ? &other : nullptr, f.t);
  } else {
    field = field_->force(f.position + arm, f.orientation, f.t);
  }
  Rendering r;
  r.force = field.force;
  // About the tool's origin: the force's moment at the point looked up, and the field's own
  // torque there (a probe space's probe).
  r.torque = arm.cross(field.force) + field.torque;
  r.touching = field.touching;
  r.point = f.position + arm;
  r.surface_time = f.contact->surface_time;
  // With a patch channel (the scene asked for a local model) the frame records the point
  // looked up while touching, as patch algorithms record theirs; else the plane's.
  r.frame_point = f.patch ? (r.touching ? r.point : Vec3::Zero()) : plane_frame_point(*f.contact);
  return r;
}

void FieldLookup::react(const FrameInputs& frame, const Rendering& /*rendered*/, const Reaction& /*reaction*/,
                        AlgorithmState& /*state*/, ContactLoad& load) const {
  plane_load(*frame.contact, false, load);  // a space takes no loads
}

}  // namespace tactus::haptics
