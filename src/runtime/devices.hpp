#pragma once
// Haptic devices built from a scene's device entries, or replaced by recorded motion.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "haptics/device.hpp"
#include "haptics/devices/replay_device.hpp"
#include "runtime/recording.hpp"
#include "scene/model.hpp"

namespace tactus::runtime {

/// The device scene entry `index` describes. A replay device reads its recording; a
/// network device binds its socket (InputError when it cannot). `seed` varies tremor.
std::unique_ptr<haptics::Device> make_device(const scene::Model& model, std::size_t index, unsigned seed = 0);

/// A device whose pose its owner sets between frames (a program embedding the engine, the
/// Python module): read() returns the last pose set. The force sent reaches the owner through
/// the run's frames (runtime/stepped_run.hpp), so write() keeps nothing.
class ControlledDevice final : public haptics::Device {
 public:
  explicit ControlledDevice(haptics::DeviceLimits limits) : limits_(std::move(limits)) {}
  void set_pose(const haptics::DevicePose& pose) { pose_ = pose; }
  haptics::DevicePose read(double /*t*/) override { return pose_; }
  void write(const Vec3& /*force*/, const Vec3& /*torque*/) override {}
  [[nodiscard]] const haptics::DeviceLimits& limits() const override { return limits_; }
  [[nodiscard]] const char* kind() const override { return "controlled"; }

 private:
  haptics::DeviceLimits limits_;
  haptics::DevicePose pose_;
};

/// Recorded poses of one device, for a replay.
struct RecordedMotion {
  std::vector<haptics::TimedPose> poses;
  std::string source;  ///< the recording, for messages
};
/// Poses of every device of a recording, by device name.
std::map<std::string, RecordedMotion> recorded_motion(const Recording& recording, const std::string& source);

}  // namespace tactus::runtime
