#pragma once
// A device that plays back recorded poses exactly as they were read (no interpolation), so
// a replayed run sees bit-identical inputs.
#include <cstddef>
#include <string>
#include <vector>

#include "haptics/device.hpp"

namespace tactus::haptics {

struct TimedPose {
  double t = 0.0;  ///< [s] since the start of the recorded run
  DevicePose pose;
};

class ReplayDevice final : public Device {
 public:
  /// Throws InputError when there are no samples, a time is not finite or goes backwards,
  /// or a pose is not finite; `source` (the recording's file name) prefixes the message.
  ReplayDevice(std::vector<TimedPose> samples, DeviceLimits limits, std::string source = {});

  /// The sample with the largest time ≤ t (the last of equal times); the first one before
  /// the recording starts.
  DevicePose read(double t) override;
  /// Ignored: a recording cannot be pushed.
  void write(const Vec3& force, const Vec3& torque) override;
  /// True once t is past the last sample.
  [[nodiscard]] bool finished(double t) const override;
  [[nodiscard]] const DeviceLimits& limits() const override { return limits_; }
  [[nodiscard]] const char* kind() const override { return "replay"; }

  [[nodiscard]] std::size_t size() const { return samples_.size(); }

 private:
  std::vector<TimedPose> samples_;
  DeviceLimits limits_;
};

}  // namespace tactus::haptics
