#pragma once
// A simulated hand holding the device handle: a point mass pulled towards a target
// trajectory by a spring and a damper, and pushed by the force the haptic loop renders.
// Closing the loop through it lets tests check stability and passivity without hardware.
#include "haptics/device.hpp"
#include "haptics/trajectory.hpp"

namespace tactus::haptics {

/// The handle as the hand model sees it.
struct HandState {
  Vec3 position = Vec3::Zero();  ///< [m], device coordinates
  Vec3 velocity = Vec3::Zero();  ///< [m/s]
  double kinetic_energy = 0.0;   ///< ½·m·|v|² [J]
  double device_work = 0.0;      ///< Σ F·Δx: energy the device force put into the hand [J]
};

class SimulatedOperator final : public Device {
 public:
  /// Max substep of the integration [s].
  static constexpr double kMaxSubstep = 1e-4;

  /// Throws InputError unless mass and stiffness are positive and damping is ≥ 0.
  SimulatedOperator(Trajectory target, Tremor tremor, double hand_mass, double hand_stiffness,
                    double hand_damping, DeviceLimits limits, unsigned seed = 0);

  /// Integrates m·a = k(x* − x) + c(v* − v) + F from the last read to t (semi-implicit Euler,
  /// equal substeps of at most kMaxSubstep) and returns the handle position. x* is the target
  /// plus tremor, v* the target's velocity_at, F the force last written.
  DevicePose read(double t) override;
  /// The force acts on the hand until the next read.
  void write(const Vec3& force, const Vec3& torque) override;
  /// True once t is past the end of the target trajectory.
  [[nodiscard]] bool finished(double t) const override;
  [[nodiscard]] const DeviceLimits& limits() const override { return limits_; }
  [[nodiscard]] const char* kind() const override { return "simulated_operator"; }

  [[nodiscard]] const HandState& hand() const { return hand_; }
  [[nodiscard]] const Vec3& device_force() const { return force_; }

 private:
  void substep(double t, double h);

  Trajectory target_;
  Tremor tremor_;
  double mass_;
  double stiffness_;
  double damping_;
  DeviceLimits limits_;
  unsigned seed_;
  double duration_;
  double time_ = 0.0;  ///< time the hand state belongs to [s]
  Vec3 force_ = Vec3::Zero();
  HandState hand_;
};

}  // namespace tactus::haptics
