#include "haptics/devices/replay_device.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::haptics {

ReplayDevice::ReplayDevice(std::vector<TimedPose> samples, DeviceLimits limits, std::string source)
    : samples_(std::move(samples)), limits_(limits) {
  const SourceLocation where{std::move(source), {}, {}, {}};
  if (samples_.empty()) throw InputError(where, "the recording has no device samples");
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    const TimedPose& s = samples_[i];
    if (!std::isfinite(s.t)) throw InputError(where, fmt::format("sample {}: time {} is not finite", i, s.t));
    if (i > 0 && s.t < samples_[i - 1].t)
      throw InputError(where, fmt::format("sample {}: time {} is before the previous sample's {}", i, s.t,
                                          samples_[i - 1].t));
    if (!s.pose.position.allFinite() || !s.pose.orientation.coeffs().allFinite())
      throw InputError(where, fmt::format("sample {} (t = {}): the pose is not finite", i, s.t));
  }
}

DevicePose ReplayDevice::read(double t) {
  // A binary search per frame: about 20 comparisons for a million samples, and correct
  // whichever way t moves.
  const auto after = std::upper_bound(samples_.begin(), samples_.end(), t,
                                      [](double time, const TimedPose& s) { return time < s.t; });
  return after == samples_.begin() ? samples_.front().pose : std::prev(after)->pose;
}

void ReplayDevice::write(const Vec3& /*force*/, const Vec3& /*torque*/) {}

bool ReplayDevice::finished(double t) const { return t > samples_.back().t; }

}  // namespace tactus::haptics
