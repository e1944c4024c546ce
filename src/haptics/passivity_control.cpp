#include "haptics/passivity_control.hpp"

#include <algorithm>
#include <cmath>

namespace tactus::haptics {

Vec3 PassivityControl::apply(const Vec3& force, bool touching, const Vec3& position, const Vec3& velocity, double dt) {
  if (!enabled_) return force;
  // Observer: the work last frame's force did on the hand as it moved. A non-finite force
  // went to the device as zero (the safety layer), and a non-finite pose moved nothing we
  // can count: neither may poison the sum.
  if (has_position_) {
    const Vec3 moved = position - last_position_;
    if (moved.allFinite()) {
      work_ += last_force_.dot(moved);
      removed_ += last_removed_.dot(moved);
    }
  }
  if (position.allFinite()) {
    last_position_ = position;
    has_position_ = true;
  }
  last_removed_.setZero();
  last_force_ = force.allFinite() ? force : Vec3::Zero();
  if (!touching) {
    // What a finished contact absorbed is no credit for the next one (a debt is kept, and
    // the next contact pays it); a contact lost for a frame or two has not finished.
    free_time_ += dt;
    if (free_time_ >= kContactEnded) work_ = std::max(work_, 0.0);
    return force;
  }
  free_time_ = 0.0;
  // Controller: the part of the force along the motion does work |v|·dt per newton; a
  // damper of at most max_damping takes it away.
  const double speed = velocity.norm();
  if (work_ > 0.0 && speed > 0.0 && dt > 0.0 && force.allFinite() && std::isfinite(speed)) {
    const Vec3 direction = velocity / speed;
    const double along = force.dot(direction);
    if (along > 0.0) {
      last_removed_ = std::min({along, work_ / (speed * dt), max_damping_ * speed}) * direction;
      ++frames_acted_;
    }
  }
  last_force_ -= last_removed_;
  return force - last_removed_;
}

}  // namespace tactus::haptics
