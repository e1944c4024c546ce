#include "haptics/devices/scripted_device.hpp"

#include <utility>

namespace tactus::haptics {

ScriptedDevice::ScriptedDevice(Trajectory trajectory, Tremor tremor, DeviceLimits limits, unsigned seed)
    : trajectory_(std::move(trajectory)),
      tremor_(tremor),
      limits_(limits),
      seed_(seed),
      duration_(duration(trajectory_)) {}

DevicePose ScriptedDevice::read(double t) {
  DevicePose pose;
  pose.position = position_at(trajectory_, t) + tremor_at(tremor_, t, seed_);
  pose.orientation = orientation_at(trajectory_, t);
  return pose;
}

void ScriptedDevice::write(const Vec3& force, const Vec3& torque) {
  last_force_ = force;
  last_torque_ = torque;
}

bool ScriptedDevice::finished(double t) const { return t > duration_; }

}  // namespace tactus::haptics
