#include "haptics/algorithms/on_plane.hpp"

namespace tactus::haptics {

Rendering OnPlane::render(const FrameInputs& f, AlgorithmState& state) const {
  auto& s = static_cast<PlaneState&>(state);
  const LocalContact& contact = *f.contact;
  begin(f, s);
  const bool smooth = f.contact_fresh && f.smoothing && s.shown.valid;
  const Vec3 before = smooth ? against(s.shown, f, s, true).force : Vec3::Zero();
  Rendering r = against(contact, f, s, false);
  if (smooth) {
    r.model_changed = true;
    r.before = before;
    r.after = r.force;
  }
  s.shown = contact;
  r.surface_time = contact.surface_time;
  r.frame_point = plane_frame_point(contact);
  return r;
}

}  // namespace tactus::haptics
