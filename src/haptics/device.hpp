#pragma once
// The one interface every haptic device implements: read a pose, write a force.
//
// A device is driven by exactly one haptic loop thread. read() and write() are called once
// per haptic frame, in that order; after construction they never allocate, never lock and
// never block (a network device polls a non-blocking socket). Times are seconds since the
// start of the run: wall-clock in real time, virtual in lockstep, so a device that only
// depends on t (scripted, simulated operator, replay) is deterministic.
#include <cstdint>
#include <string>

#include "core/math.hpp"

namespace tactus::haptics {

struct DevicePose {
  Vec3 position = Vec3::Zero();           ///< handle position, device coordinates [m]
  Quat orientation = Quat::Identity();    ///< handle orientation, device coordinates
  std::uint32_t buttons = 0;              ///< bit i = button i pressed
};

struct DeviceLimits {
  double max_force = 10.0;        ///< [N]; the safety layer never sends more
  double max_stiffness = 2000.0;  ///< [N/m]; the largest stable rendering stiffness
  Aabb workspace;                 ///< reachable positions, device coordinates [m]
};

/// Device space → scene space: p_scene = offset + scale · R · p_device. Forces go the other
/// way by the transpose rotation (a force is not scaled: the user feels newtons).
struct WorkspaceMap {
  double scale = 1.0;
  Quat rotation = Quat::Identity();
  Vec3 offset = Vec3::Zero();

  [[nodiscard]] Vec3 to_scene(const Vec3& p_device) const {
    return offset + scale * (rotation * p_device);
  }
  [[nodiscard]] Quat to_scene(const Quat& q_device) const { return rotation * q_device; }
  [[nodiscard]] Vec3 to_device(const Vec3& p_scene) const {
    return rotation.conjugate() * ((p_scene - offset) / scale);
  }
  [[nodiscard]] Vec3 force_to_device(const Vec3& f_scene) const {
    return rotation.conjugate() * f_scene;
  }
};

class Device {
 public:
  virtual ~Device() = default;
  Device() = default;
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  /// Advance the device to time t (non-decreasing between calls) and return the handle
  /// pose in device coordinates.
  virtual DevicePose read(double t) = 0;
  /// Send the force and torque for the pose last read [N, N·m, device coordinates]. The
  /// caller (the safety layer) guarantees finite values within limits().max_force.
  virtual void write(const Vec3& force, const Vec3& torque) = 0;
  /// False while the device delivers no fresh poses (a network peer went quiet); the
  /// safety layer then fades the force out.
  [[nodiscard]] virtual bool alive() const { return true; }
  /// True once the device has no more input at time t (a replay or a script has ended).
  [[nodiscard]] virtual bool finished(double /*t*/) const { return false; }
  [[nodiscard]] virtual const DeviceLimits& limits() const = 0;
  /// "scripted", "simulated_operator", "replay", "network", "openhaptics", "dhd".
  [[nodiscard]] virtual const char* kind() const = 0;
};

}  // namespace tactus::haptics
