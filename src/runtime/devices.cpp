#include "runtime/devices.hpp"

#include <fmt/format.h>

#include "core/error.hpp"
#include "haptics/devices/network_device.hpp"
#include "haptics/devices/scripted_device.hpp"
#include "haptics/devices/simulated_operator.hpp"
#ifdef TACTUS_HAVE_OPENHAPTICS
#include "haptics/devices/openhaptics_device.hpp"
#endif
#ifdef TACTUS_HAVE_DHD
#include "haptics/devices/dhd_device.hpp"
#endif
#include "compile/device_setup.hpp"
#include "runtime/recording_reader.hpp"

namespace tactus::runtime {

std::map<std::string, RecordedMotion> recorded_motion(const Recording& recording, const std::string& source) {
  std::map<std::string, RecordedMotion> out;
  for (const auto& name : recording.header.devices) out[name].source = source;
  for (const HapticFrame& f : recording.frames) {
    if (f.device >= recording.header.devices.size()) continue;  // the reader rejects these
    haptics::TimedPose p;
    p.t = f.t;
    p.pose.position = f.position;
    p.pose.orientation = f.orientation;
    p.pose.buttons = f.buttons;
    out[recording.header.devices[f.device]].poses.push_back(p);
  }
  return out;
}

std::unique_ptr<haptics::Device> make_device(const scene::Model& model, std::size_t index, unsigned seed) {
  const scene::Device& d = model.devices.at(index);
  const haptics::DeviceLimits limits = compile::device_limits(d);
  if (const auto* s = std::get_if<scene::ScriptedDevice>(&d.source))
    return std::make_unique<haptics::ScriptedDevice>(s->trajectory, s->tremor, limits, seed);
  if (const auto* s = std::get_if<scene::SimulatedOperatorDevice>(&d.source))
    return std::make_unique<haptics::SimulatedOperator>(s->target, s->tremor, s->hand_mass, s->hand_stiffness,
                                                        s->hand_damping, limits, seed);
  if (const auto* s = std::get_if<scene::ReplayDevice>(&d.source)) {
    const Recording rec = read_recording(s->file);
    auto motion = recorded_motion(rec, s->file.string());
    const auto it = motion.find(d.name);
    if (it == motion.end() || it->second.poses.empty())
      throw InputError(SourceLocation{s->file.string(), {}, {}, {}},
                       fmt::format("the recording has no frames of a device named '{}'", d.name));
    return std::make_unique<haptics::ReplayDevice>(std::move(it->second.poses), limits, s->file.string());
  }
  if (const auto* s = std::get_if<scene::NetworkDevice>(&d.source)) {
    haptics::NetworkConfig config;
    config.address = s->address;
    config.port = s->port;
    config.timeout = s->timeout;
    return std::make_unique<haptics::NetworkDevice>(config, limits);
  }
  if (const auto* s = std::get_if<scene::OpenHapticsDevice>(&d.source)) {
#ifdef TACTUS_HAVE_OPENHAPTICS
    return std::make_unique<haptics::OpenHapticsDevice>(limits, s->device_name);
#else
    (void)s;
    throw InputError(SourceLocation{model.source, {}, {}, {}},
                     fmt::format("device '{}': this tactus was built without OpenHaptics (docs/devices.md says "
                                 "how to build with it)", d.name));
#endif
  }
  if (const auto* s = std::get_if<scene::DhdDevice>(&d.source)) {
#ifdef TACTUS_HAVE_DHD
    return std::make_unique<haptics::DhdDevice>(limits, s->index);
#else
    (void)s;
    throw InputError(SourceLocation{model.source, {}, {}, {}},
                     fmt::format("device '{}': this tactus was built without the Force Dimension SDK "
                                 "(docs/devices.md says how to build with it)", d.name));
#endif
  }
  throw InputError(fmt::format("device '{}': unknown device type", d.name));
}

}  // namespace tactus::runtime
