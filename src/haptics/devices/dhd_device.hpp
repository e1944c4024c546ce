#pragma once
// Force Dimension devices (omega, delta, sigma, lambda, Novint Falcon) through the DHD API.
// Compiled only when cmake/FindDHD.cmake finds the SDK (TACTUS_HAVE_DHD).
//
// DHD calls talk to the device directly (USB round trip, well under a millisecond), so
// read() samples the pose and write() sends the force within the same haptic frame.
#include "haptics/device.hpp"

namespace tactus::haptics {

class DhdDevice final : public Device {
 public:
  /// Opens device `index` (−1: the first one available) and enables force output. Throws
  /// InputError when it cannot be opened.
  explicit DhdDevice(DeviceLimits limits, int index = -1);
  ~DhdDevice() override;

  DevicePose read(double t) override;
  void write(const Vec3& force, const Vec3& torque) override;
  [[nodiscard]] bool alive() const override { return alive_; }
  [[nodiscard]] const DeviceLimits& limits() const override { return limits_; }
  [[nodiscard]] const char* kind() const override { return "dhd"; }

 private:
  DeviceLimits limits_;
  int id_ = -1;
  bool has_wrist_ = false;
  bool alive_ = true;
};

}  // namespace tactus::haptics
