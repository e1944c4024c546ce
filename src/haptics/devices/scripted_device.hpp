#pragma once
// A device that plays a trajectory (plus tremor) and ignores the forces sent to it: the
// open-loop operator of tests and batch runs.
#include "haptics/device.hpp"
#include "haptics/trajectory.hpp"

namespace tactus::haptics {

class ScriptedDevice final : public Device {
 public:
  ScriptedDevice(Trajectory trajectory, Tremor tremor, DeviceLimits limits, unsigned seed = 0);

  /// position_at(t) + tremor_at(t); identity orientation, no buttons.
  DevicePose read(double t) override;
  /// Forces move nothing here; the last one is kept so tests can see what was sent.
  void write(const Vec3& force, const Vec3& torque) override;
  /// True once t is past the end of the trajectory (never for circles and loops).
  [[nodiscard]] bool finished(double t) const override;
  [[nodiscard]] const DeviceLimits& limits() const override { return limits_; }
  [[nodiscard]] const char* kind() const override { return "scripted"; }

  [[nodiscard]] const Vec3& last_force() const { return last_force_; }
  [[nodiscard]] const Vec3& last_torque() const { return last_torque_; }
  [[nodiscard]] const Trajectory& trajectory() const { return trajectory_; }

 private:
  Trajectory trajectory_;
  Tremor tremor_;
  DeviceLimits limits_;
  unsigned seed_;
  double duration_;
  Vec3 last_force_ = Vec3::Zero();
  Vec3 last_torque_ = Vec3::Zero();
};

}  // namespace tactus::haptics
