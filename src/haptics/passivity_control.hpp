#pragma once
// Keeps a contact from giving the hand more energy than the hand put into it, after
// Hannaford & Ryu's passivity observer and controller (2002). A local model between
// simulation steps is not exactly the body: at an update the new shape may push a little
// harder than the old one did, and over a press and release that can return more energy
// than went in. The observer sums the work the contact force has done on the hand since
// the contact began; while that is positive, the controller takes away as much of the
// force's part along the hand's motion as would remove the excess within one frame. It
// only ever weakens that part, never reverses it, and never by more than a damper of the
// device's max_damping would at the hand's speed: near a standstill the measured velocity's
// direction is noise, and taking the whole part along it away swung a 6 N press about by
// up to 5.8 N from frame to frame; bounded by b·|v|, what it takes grows from zero with the
// speed, and an excess it cannot take at once is taken over the next frames.
#include <cstdint>

#include "core/math.hpp"

namespace tactus::haptics {

class PassivityControl {
 public:
  /// `max_damping` [N·s/m]: the strongest damping it may apply (the device's; > 0).
  explicit PassivityControl(bool enabled = false, double max_damping = 100.0)
      : enabled_(enabled), max_damping_(max_damping) {}

  [[nodiscard]] bool enabled() const { return enabled_; }

  /// The force to render for the contact force `force`, the tool at `position` moving at
  /// `velocity`, over a frame of length `dt` [s]; `touching` whether the contact renders a
  /// force. Call once per frame.
  [[nodiscard]] Vec3 apply(const Vec3& force, bool touching, const Vec3& position, const Vec3& velocity, double dt);

  /// The contact force that actually reached the hand this frame, after the safety layer
  /// clamped or ramped it (scene coordinates): the observer counts this one, not what apply()
  /// returned. Optional; call after apply().
  void record_sent(const Vec3& sent) {
    if (enabled_) last_force_ = sent.allFinite() ? sent : Vec3::Zero();
  }

  /// Net work the contact force has done on the hand in this contact [J] (a debt from an
  /// earlier contact included): ≤ 0 while the contact is passive.
  [[nodiscard]] double observed_work() const { return work_; }
  /// Energy the controller has kept from the hand so far [J]: the force it took away times
  /// the hand's motion.
  [[nodiscard]] double removed() const { return removed_; }
  /// Frames in which it weakened the force.
  [[nodiscard]] std::uint64_t frames_acted() const { return frames_acted_; }

 private:
  bool enabled_;
  double max_damping_;  ///< [N·s/m]
  double work_ = 0.0;
  double removed_ = 0.0;
  std::uint64_t frames_acted_ = 0;
  Vec3 last_force_ = Vec3::Zero();
  Vec3 last_removed_ = Vec3::Zero();  ///< the force taken away last frame
  Vec3 last_position_ = Vec3::Zero();
  bool has_position_ = false;
  double free_time_ = 0.0;  ///< time since the contact last rendered a force [s]
  /// Out of contact this long, a contact has ended [s].
  static constexpr double kContactEnded = 0.02;
};

}  // namespace tactus::haptics
