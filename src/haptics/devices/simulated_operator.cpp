#include "haptics/devices/simulated_operator.hpp"

#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::haptics {

SimulatedOperator::SimulatedOperator(Trajectory target, Tremor tremor, double hand_mass, double hand_stiffness,
                                     double hand_damping, DeviceLimits limits, unsigned seed)
    : target_(std::move(target)),
      tremor_(tremor),
      mass_(hand_mass),
      stiffness_(hand_stiffness),
      damping_(hand_damping),
      limits_(limits),
      seed_(seed),
      duration_(duration(target_)) {
  if (!(std::isfinite(mass_) && mass_ > 0.0))
    throw InputError(fmt::format("simulated operator: hand_mass must be positive, got {}", mass_));
  if (!(std::isfinite(stiffness_) && stiffness_ > 0.0))
    throw InputError(fmt::format("simulated operator: hand_stiffness must be positive, got {}", stiffness_));
  if (!(std::isfinite(damping_) && damping_ >= 0.0))
    throw InputError(fmt::format("simulated operator: hand_damping must not be negative, got {}", damping_));
  hand_.position = position_at(target_, 0.0);
}

void SimulatedOperator::substep(double t, double h) {
  const Vec3 target = position_at(target_, t) + tremor_at(tremor_, t, seed_);
  const Vec3 target_velocity = velocity_at(target_, t);
  const Vec3 accel =
      (stiffness_ * (target - hand_.position) + damping_ * (target_velocity - hand_.velocity) + force_) / mass_;
  // Semi-implicit Euler: new velocity first, then the position with it (symplectic, stable
  // for h·ω < 2).
  hand_.velocity += h * accel;
  const Vec3 dx = h * hand_.velocity;
  hand_.position += dx;
  hand_.device_work += force_.dot(dx);
}

DevicePose SimulatedOperator::read(double t) {
  if (std::isfinite(t) && t > time_) {
    const double span = t - time_;
    const double steps = std::ceil(span / kMaxSubstep);
    const double h = span / steps;
    const double start = time_;
    for (double i = 0.0; i < steps; i += 1.0) substep(start + i * h, h);
    time_ = t;
    hand_.kinetic_energy = 0.5 * mass_ * hand_.velocity.squaredNorm();
  }
  DevicePose pose;
  pose.position = hand_.position;
  return pose;
}

void SimulatedOperator::write(const Vec3& force, const Vec3& /*torque*/) {
  // A point hand has no rotational inertia to feel a torque.
  force_ = force.allFinite() ? force : Vec3::Zero();
}

bool SimulatedOperator::finished(double t) const { return t > duration_; }

}  // namespace tactus::haptics
