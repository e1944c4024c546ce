// Runs the built-in default scene (a fingertip on a soft FEM block) in real time with two
// pieces written here rather than in the engine:
//  - CircleDevice, a haptics::Device: the fingertip comes down onto the block and strokes a
//    circle over its surface (a real program would read its own hardware here);
//  - ViscousGel, a haptics::ForceAlgorithm: a drag against the fingertip's velocity, felt
//    while the finger touches the tissue, added to the scene's own contact force.
// Usage: realtime_custom [seconds]   (default 1.5)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <numbers>
#include <string>

#include "compile/device_setup.hpp"    // compile::device_limits: a scene device's limits
#include "haptics/device.hpp"          // haptics::Device
#include "haptics/force_algorithm.hpp" // haptics::ForceAlgorithm
#include "haptics/haptic_step.hpp"     // haptics::HapticModel, what a device renders
#include "runtime/session.hpp"         // runtime::run_session and its options and report
#include "scene/scene.hpp"             // scene::default_scene, load_scene, parse_scene

using namespace tactus;

// A device is read and written once per haptic frame by its own loop thread: read() and
// write() must not allocate, lock or block.
class CircleDevice final : public haptics::Device {
 public:
  explicit CircleDevice(haptics::DeviceLimits limits) : limits_(limits) {}

  haptics::DevicePose read(double t) override {
    // The block's top face is at z = 0.02 m and the fingertip sphere has an 8 mm radius:
    // start 4 mm above the surface, come down 8 mm in 0.25 s (4 mm into the tissue), then
    // circle with a 20 mm radius, one turn a second.
    constexpr double radius = 0.02, turn = 1.0, descent = 0.25;
    const double z = 0.032 - 0.008 * std::min(t / descent, 1.0);
    const double angle = 2.0 * std::numbers::pi * std::max(t - descent, 0.0) / turn;
    haptics::DevicePose pose;
    pose.position = Vec3(radius * std::cos(angle), radius * std::sin(angle), z);
    return pose;
  }
  void write(const Vec3& force, const Vec3& /*torque*/) override { last_force_ = force; }
  [[nodiscard]] const haptics::DeviceLimits& limits() const override { return limits_; }
  [[nodiscard]] const char* kind() const override { return "circle"; }

 private:
  haptics::DeviceLimits limits_;
  Vec3 last_force_ = Vec3::Zero();  // a real device would send this to its motors
};

// An overlay-stage algorithm adds its force to the contact algorithm's while the contact
// touches. Algorithms are immutable; what changes per frame would live in an AlgorithmState.
class ViscousGel final : public haptics::ForceAlgorithm {
 public:
  explicit ViscousGel(double damping) : damping_(damping) {}

  [[nodiscard]] Stage stage() const override { return Stage::overlay; }
  [[nodiscard]] std::unique_ptr<haptics::AlgorithmState> make_state() const override {
    return std::make_unique<haptics::AlgorithmState>();  // nothing to remember
  }
  // Called every haptic frame: no allocation, no lock, no exception.
  [[nodiscard]] haptics::Rendering render(const haptics::FrameInputs& frame,
                                          haptics::AlgorithmState& /*state*/) const override {
    haptics::Rendering r;
    r.force = -damping_ * frame.velocity;  // [N] from [N·s/m] × [m/s], scene coordinates
    return r;
  }

 private:
  double damping_;  // [N·s/m]
};

int main(int argc, char** argv) {
  try {
    // Any scene works the same way: scene::load_scene("my.toml") or parse_scene(text, name).
    const scene::Model model = scene::default_scene();

    const double seconds = argc > 1 ? std::atof(argv[1]) : 1.5;
    if (!(seconds > 0.0 && seconds <= 60.0)) {
      std::fprintf(stderr, "usage: realtime_custom [seconds in (0, 60]]\n");
      return 1;
    }
    runtime::SessionOptions options;
    options.scheduling = runtime::Scheduling::real_time;  // a thread per loop, wall clock
    options.duration = seconds;
    // Our device replaces the scene's device 0 (returning null keeps the scene's).
    options.device_override = [](const scene::Model& m, std::size_t index) -> std::unique_ptr<haptics::Device> {
      if (index != 0) return nullptr;
      return std::make_unique<CircleDevice>(compile::device_limits(m.devices[index]));
    };
    // Our algorithm joins what the scene compiled for device 0 (here: its proxy contact).
    options.customize_haptics = [](const scene::Model&, std::size_t index, haptics::HapticModel& haptic) {
      if (index == 0) haptic.algorithms.push_back(std::make_shared<ViscousGel>(2.0));
    };

    const runtime::SessionReport report = runtime::run_session(model, options);

    // The report: what each device felt and how every loop kept its rate.
    std::printf("scene %s: %.2f s simulated in %.2f s\n", report.scene.c_str(), report.simulated_time,
                report.wall_time);
    for (const runtime::DeviceReport& d : report.devices)
      std::printf("device %s (%s): max force %.3f N, %llu contact frames, %llu clamped\n", d.name.c_str(),
                  d.kind.c_str(), d.max_force_sent, static_cast<unsigned long long>(d.contact_frames),
                  static_cast<unsigned long long>(d.safety.clamped));
    // Each loop's period histogram holds the start-to-start intervals [ns] of its steps.
    for (const runtime::LoopStats& loop : report.loops) {
      const double median_period = static_cast<double>(loop.period.percentile(50.0));
      std::printf("loop %s: %llu steps, median rate %.0f Hz (nominal %.0f Hz), max period %.2f ms, %llu missed deadlines\n",
                  loop.name.c_str(), static_cast<unsigned long long>(loop.steps),
                  median_period > 0.0 ? 1e9 / median_period : 0.0, loop.rate,
                  1e-6 * static_cast<double>(loop.period.max()),
                  static_cast<unsigned long long>(loop.missed_deadlines));
    }
    for (const std::string& note : report.realtime_notes) std::printf("note: %s\n", note.c_str());
    return 0;
  } catch (const std::exception& e) {  // a bad scene names its file, line and reason
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
