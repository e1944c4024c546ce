#pragma once
// 3D Systems Touch / Phantom devices through the OpenHaptics HD API. Compiled only when
// cmake/FindOpenHaptics.cmake finds the SDK (TACTUS_HAVE_OPENHAPTICS).
//
// The HD servo thread owns the device. Each read() runs one synchronous scheduler callback:
// inside one hdBeginFrame/hdEndFrame it sends the force of the previous write() and samples
// the new pose, so the haptic loop is paced by the servo tick and the force reaches the
// device one tick after it was computed.
#include <array>
#include <string>

#include "haptics/device.hpp"

namespace tactus::haptics {

class OpenHapticsDevice final : public Device {
 public:
  /// Opens the named device (empty: the default one), enables force output and starts the
  /// scheduler. Throws InputError when the device cannot be opened. max_force is lowered
  /// to the device's nominal maximum when that is smaller.
  explicit OpenHapticsDevice(DeviceLimits limits, const std::string& device_name = {});
  ~OpenHapticsDevice() override;

  DevicePose read(double t) override;
  void write(const Vec3& force, const Vec3& torque) override;
  [[nodiscard]] bool alive() const override { return frame_.ok; }
  [[nodiscard]] const DeviceLimits& limits() const override { return limits_; }
  [[nodiscard]] const char* kind() const override { return "openhaptics"; }

 private:
  /// What one servo tick exchanges; plain data so the callback needs no allocation.
  struct Frame {
    unsigned int handle = 0;                 ///< HHD
    std::array<double, 3> force{};           ///< to send [N]
    std::array<double, 3> position{};        ///< read [mm]
    std::array<double, 16> transform{};      ///< read, column-major, translation in mm
    int buttons = 0;
    bool ok = true;
  };
  void exchange();

  DeviceLimits limits_;
  Frame frame_;
};

}  // namespace tactus::haptics
