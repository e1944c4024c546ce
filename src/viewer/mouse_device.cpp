#include "viewer/mouse_device.hpp"

#include <cmath>

namespace tactus::viewer {

MouseDevice::MouseDevice(const MouseChannel& channel, const haptics::DeviceLimits& limits)
    : channel_(channel), limits_(limits),
      bounded_((limits.workspace.min.array() <= limits.workspace.max.array()).all() &&
               limits.workspace.min.allFinite() && limits.workspace.max.allFinite()) {}

haptics::DevicePose MouseDevice::read(double /*t*/) {
  haptics::DevicePose pose;
  Vec3 p = channel_.get();
  // A target the window computed from a degenerate camera must not reach the loop.
  if (!p.allFinite()) p = Vec3::Zero();
  if (bounded_) p = p.cwiseMax(limits_.workspace.min).cwiseMin(limits_.workspace.max);
  pose.position = p;
  return pose;
}

void MouseDevice::write(const Vec3& /*force*/, const Vec3& /*torque*/) {
  // Nothing to actuate: the force reaches the window through the run's haptic frames.
}

}  // namespace tactus::viewer
