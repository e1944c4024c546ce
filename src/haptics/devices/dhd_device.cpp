#include "haptics/devices/dhd_device.hpp"

#include <cstdint>
#include <string>

#include <dhdc.h>
#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::haptics {

DhdDevice::DhdDevice(DeviceLimits limits, int index) : limits_(limits) {
  id_ = index < 0 ? dhdOpen() : dhdOpenID(static_cast<char>(index));
  if (id_ < 0)
    throw InputError(fmt::format("Force Dimension device {}: cannot open it: {}",
                                 index < 0 ? std::string("(first available)") : std::to_string(index),
                                 dhdErrorGetLastStr()));
  has_wrist_ = dhdHasWrist(static_cast<char>(id_));
  if (dhdEnableForce(DHD_ON, static_cast<char>(id_)) < 0) {
    const std::string reason = dhdErrorGetLastStr();
    dhdClose(static_cast<char>(id_));
    throw InputError(fmt::format("Force Dimension device {}: cannot enable forces: {}", id_, reason));
  }
}

DhdDevice::~DhdDevice() {
  dhdSetForce(0.0, 0.0, 0.0, static_cast<char>(id_));  // leave the handle with no force on it
  dhdClose(static_cast<char>(id_));
}

DevicePose DhdDevice::read(double /*t*/) {
  const char id = static_cast<char>(id_);
  DevicePose pose;
  double x = 0.0, y = 0.0, z = 0.0;
  alive_ = dhdGetPosition(&x, &y, &z, id) >= 0;  // already in metres
  pose.position = Vec3(x, y, z);
  if (has_wrist_) {
    double frame[3][3];
    if (dhdGetOrientationFrame(frame, id) >= 0) {
      Mat3 rotation;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) rotation(r, c) = frame[r][c];
      pose.orientation = Quat(rotation).normalized();
    }
  }
  pose.buttons = static_cast<std::uint32_t>(dhdGetButtonMask(id));
  return pose;
}

void DhdDevice::write(const Vec3& force, const Vec3& /*torque*/) {
  // Translational forces only; DHD_MOTOR_SATURATED (> 0) is not an error.
  if (dhdSetForce(force.x(), force.y(), force.z(), static_cast<char>(id_)) < 0) alive_ = false;
}

}  // namespace tactus::haptics
