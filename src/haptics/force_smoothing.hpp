#pragma once
// Smooths the force step a haptic loop would feel when a new local model arrives (seed 003
// §3.5, last paragraph), without letting the smoothing put energy into the hand.
//
// At an update the force of the old model and of the new one are both known at the same tool
// position; their difference is kept as an offset that decays with a time constant, so the
// rendered force is continuous. The offset does not depend on position, so it could do work
// on the hand. Two guards keep it passive (in the manner of Hannaford & Ryu's passivity
// observer and controller): the part of the offset that would push the hand along its motion
// is not rendered, and an observer sums the work the smoothing has done on the hand; should
// that turn positive, the rest of the offset is dropped.
#include "core/math.hpp"

namespace tactus::haptics {

class ForceSmoother {
 public:
  /// `time_constant` [s]: 0 disables the smoothing (apply() returns the force unchanged).
  explicit ForceSmoother(double time_constant = 0.0) : time_constant_(time_constant) {}

  [[nodiscard]] bool enabled() const { return time_constant_ > 0.0; }

  /// The local model changed: at this frame the old one gave `before`, the new one `after`.
  void model_changed(const Vec3& before, const Vec3& after);

  /// The force to render for the model's `force`, with the tool at `position` after a frame
  /// of length `dt` [s] moving at `velocity`; call once per frame.
  [[nodiscard]] Vec3 apply(const Vec3& force, const Vec3& position, const Vec3& velocity, double dt);

  /// Net work the smoothing force has done on the hand so far [J] (never positive for long).
  [[nodiscard]] double observed_work() const { return work_; }
  [[nodiscard]] const Vec3& offset() const { return offset_; }

 private:
  double time_constant_;
  Vec3 offset_ = Vec3::Zero();
  Vec3 last_smoothing_ = Vec3::Zero();  ///< the smoothing force rendered last frame
  Vec3 last_position_ = Vec3::Zero();
  bool has_position_ = false;
  double work_ = 0.0;  ///< passivity observer: work of the smoothing force on the hand [J]
  /// Hand speed above which the offset's push along the motion is faded out [m/s].
  static constexpr double kSpeedScale = 1e-3;
};

}  // namespace tactus::haptics
