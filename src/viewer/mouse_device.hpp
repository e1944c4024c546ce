#pragma once
// The mouse as a haptic device: the window's thread stores where the finger should be, the
// haptic loop reads it. The hand-over is a SeqLock, so the haptic thread never waits for the
// window (it retries only while a store of a few words is in progress) and never allocates.
// The force cannot be felt: the window draws it instead.
#include <array>

#include "core/seqlock.hpp"
#include "haptics/device.hpp"

namespace tactus::viewer {

/// Position targets from the window to the haptic thread (one writer, the window).
class MouseChannel {
 public:
  explicit MouseChannel(const Vec3& initial_device_position) { set(initial_device_position); }
  /// The window's thread: where the handle should be, device coordinates [m].
  void set(const Vec3& device_position) { target_.store({device_position.x(), device_position.y(), device_position.z()}); }
  /// Any thread: the newest target.
  [[nodiscard]] Vec3 get() const {
    const Target t = target_.load();
    return Vec3(t[0], t[1], t[2]);
  }

 private:
  using Target = std::array<double, 3>;  // trivially copyable, as SeqLock requires
  SeqLock<Target> target_;
};

class MouseDevice final : public haptics::Device {
 public:
  /// `channel` must outlive the device. Targets outside limits.workspace are clamped into it.
  MouseDevice(const MouseChannel& channel, const haptics::DeviceLimits& limits);

  haptics::DevicePose read(double t) override;
  void write(const Vec3& force, const Vec3& torque) override;
  [[nodiscard]] const haptics::DeviceLimits& limits() const override { return limits_; }
  [[nodiscard]] const char* kind() const override { return "mouse"; }

 private:
  const MouseChannel& channel_;
  haptics::DeviceLimits limits_;
  bool bounded_;  ///< the workspace is a real box (min ≤ max on every axis)
};

}  // namespace tactus::viewer
