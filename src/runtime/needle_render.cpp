// The haptic loop's needle: the axis from the device (or the scripted insertion line),
// the layer crossings the interaction loop found, the insertion stages, and where the
// reaction goes on the tissue.
#include "runtime/haptic_loop.hpp"

namespace tactus::runtime {

HapticLoop::Rendered HapticLoop::render_needle(const Vec3& position, const Quat& orientation, double t) {
  channels_.needle.update();
  // A handle's needle points along its −z; a scripted line fixes the axis to the line.
  Vec3 axis = config_.needle_axis ? *config_.needle_axis : Vec3(orientation * Vec3(0, 0, -1));
  const double norm = axis.norm();
  if (norm > 1e-9 && axis.allFinite()) {
    needle_axis_ = axis / norm;
  } else if (needle_axis_.isZero()) {
    needle_axis_ = Vec3(0, 0, -1);
  }
  needle_out_ = needle_->update(position, needle_axis_, velocity_, channels_.needle.read(), t);
  if (needle_out_.rupture)
    emit(t, EventKind::rupture, needle_out_.rupture->force, static_cast<std::int32_t>(needle_out_.rupture->layer));
  Rendered out;
  out.force = needle_out_.force;
  out.touching = needle_out_.touching;
  out.point = needle_out_.load_point;
  out.law_force = needle_out_.spring_force;
  return out;
}

void HapticLoop::needle_load(ContactLoad& load, bool touching) const {
  const int layer = needle_out_.load_layer;
  load.active = touching && layer >= 0 && needle_out_.load_triangle >= 0;
  load.body = layer >= 0 ? static_cast<std::int32_t>(needle_->config().layers[static_cast<std::size_t>(layer)].body) : -1;
  load.triangle = load.active ? needle_out_.load_triangle : -1;
  load.barycentric = needle_out_.load_barycentric;
}

}  // namespace tactus::runtime
