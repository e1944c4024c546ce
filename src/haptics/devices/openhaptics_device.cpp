#include "haptics/devices/openhaptics_device.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include <HD/hd.h>
#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::haptics {
namespace {

static_assert(sizeof(HHD) == sizeof(unsigned int), "HHD is stored as unsigned int");

// The scheduler is process-wide: started with the first device, stopped with the last.
int open_devices = 0;

void throw_if_error(const char* doing, const std::string& name) {
  const HDErrorInfo error = hdGetError();
  if (HD_DEVICE_ERROR(error))
    throw InputError(fmt::format("OpenHaptics device '{}': {} failed: {}", name.empty() ? "default" : name, doing,
                                 hdGetErrorString(error.errorCode)));
}

}  // namespace

OpenHapticsDevice::OpenHapticsDevice(DeviceLimits limits, const std::string& device_name) : limits_(limits) {
  const HHD handle = hdInitDevice(device_name.empty() ? HD_DEFAULT_DEVICE : device_name.c_str());
  throw_if_error("hdInitDevice", device_name);
  frame_.handle = handle;
  HDdouble nominal_max_force = 0.0;
  hdGetDoublev(HD_NOMINAL_MAX_FORCE, &nominal_max_force);
  if (nominal_max_force > 0.0) limits_.max_force = std::min(limits_.max_force, nominal_max_force);
  hdEnable(HD_FORCE_OUTPUT);
  if (open_devices == 0) hdStartScheduler();
  const HDErrorInfo error = hdGetError();
  if (HD_DEVICE_ERROR(error)) {
    hdDisableDevice(handle);
    throw InputError(fmt::format("OpenHaptics device '{}': cannot start the scheduler: {}",
                                 device_name.empty() ? "default" : device_name, hdGetErrorString(error.errorCode)));
  }
  ++open_devices;
}

OpenHapticsDevice::~OpenHapticsDevice() {
  frame_.force = {0.0, 0.0, 0.0};
  exchange();  // leave the handle with no force on it
  if (--open_devices == 0) hdStopScheduler();
  hdDisableDevice(frame_.handle);
}

void OpenHapticsDevice::exchange() {
  // Runs on the servo thread while this thread waits in hdScheduleSynchronous.
  const HDSchedulerCallback callback = [](void* data) -> HDCallbackCode {
    auto* frame = static_cast<Frame*>(data);
    hdMakeCurrentDevice(frame->handle);
    hdBeginFrame(frame->handle);
    hdSetDoublev(HD_CURRENT_FORCE, frame->force.data());
    hdGetDoublev(HD_CURRENT_POSITION, frame->position.data());
    hdGetDoublev(HD_CURRENT_TRANSFORM, frame->transform.data());
    hdGetIntegerv(HD_CURRENT_BUTTONS, &frame->buttons);
    hdEndFrame(frame->handle);
    frame->ok = !HD_DEVICE_ERROR(hdGetError());
    return HD_CALLBACK_DONE;
  };
  hdScheduleSynchronous(callback, &frame_, HD_MAX_SCHEDULER_PRIORITY);
}

DevicePose OpenHapticsDevice::read(double /*t*/) {
  exchange();
  DevicePose pose;
  pose.position = 1e-3 * Vec3(frame_.position[0], frame_.position[1], frame_.position[2]);
  Mat3 rotation;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) rotation(r, c) = frame_.transform[static_cast<std::size_t>(4 * c + r)];
  pose.orientation = Quat(rotation).normalized();
  pose.buttons = static_cast<std::uint32_t>(frame_.buttons);
  return pose;
}

void OpenHapticsDevice::write(const Vec3& force, const Vec3& /*torque*/) {
  // 3-DOF output: torques are not sent.
  frame_.force = {force.x(), force.y(), force.z()};
}

}  // namespace tactus::haptics
