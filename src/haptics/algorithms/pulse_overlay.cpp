#include "haptics/algorithms/pulse_overlay.hpp"

namespace tactus::haptics {

Rendering PulseOverlay::render(const FrameInputs& f, AlgorithmState& /*state*/) const {
  Rendering r;
  if (!f.contact_touching) return r;
  const Vec3 arm = f.orientation * offset_;
  r.force = pulse_.force(f.t, f.position + arm, f.contact_force);
  return r;
}

}  // namespace tactus::haptics
