#include "haptics/force_smoothing.hpp"

#include <algorithm>
#include <cmath>

namespace tactus::haptics {

void ForceSmoother::model_changed(const Vec3& before, const Vec3& after) {
  if (!enabled()) return;
  const Vec3 step = before - after;
  if (!step.allFinite()) return;
  offset_ += step;
  // A new update starts with the energy the smoothing has taken out so far, not with a debt.
  work_ = std::min(work_, 0.0);
}

Vec3 ForceSmoother::apply(const Vec3& force, const Vec3& position, const Vec3& velocity, double dt) {
  if (!enabled()) return force;
  // Observer: the work last frame's smoothing force did on the hand as it moved.
  if (has_position_) work_ += last_smoothing_.dot(position - last_position_);
  last_position_ = position;
  has_position_ = true;

  offset_ *= std::exp(-dt / time_constant_);
  // Controller: once the smoothing has given the hand net energy, the rest of the step is
  // rendered at once.
  if (work_ > 0.0) offset_.setZero();
  if (offset_.squaredNorm() < 1e-18) offset_.setZero();
  // Of the offset, render only what does not push the hand along its motion: the part along
  // the velocity is faded out as the speed exceeds kSpeedScale (smoothly, so a hand at rest
  // does not make it chatter).
  const double along = offset_.dot(velocity);
  Vec3 smoothing = offset_;
  if (along > 0.0) smoothing -= along / (velocity.squaredNorm() + kSpeedScale * kSpeedScale) * velocity;
  if (!smoothing.allFinite()) smoothing.setZero();
  last_smoothing_ = smoothing;
  return force + smoothing;
}

}  // namespace tactus::haptics
