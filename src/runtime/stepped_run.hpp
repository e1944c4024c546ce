#pragma once
// A lockstep run driven one haptic period at a time by its caller (a program embedding the
// engine, the Python module): the loops, the schedule and the recorder of run_session's
// lockstep scheduler, so that stepping a scene to a time gives the frames `tactus run
// --lockstep` gives, bit for bit. Devices named `controlled` take their pose from the caller
// (set_pose) instead of the scene's device entry.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "runtime/session.hpp"

namespace tactus::runtime {

struct Loops;
class Recorder;
class ControlledDevice;

class SteppedRun {
 public:
  /// The options' scheduling is taken as lockstep; their duration, interrupt, visual sink
  /// and emergency stop time are not used (the caller decides when to stop). Throws
  /// InputError for a scene the runtime cannot run or a controlled device it lacks.
  SteppedRun(const scene::Model& model, SessionOptions options, const std::vector<std::string>& controlled = {});
  ~SteppedRun();
  SteppedRun(const SteppedRun&) = delete;
  SteppedRun& operator=(const SteppedRun&) = delete;

  /// One haptic period at t = frames() / haptic rate: the simulation and interaction steps due
  /// by then, then every device's frame; the recorder is drained. Throws std::logic_error
  /// after finish(), std::runtime_error when the simulation diverges.
  void step();
  /// Haptic periods stepped so far; the next one runs at frames() / haptic rate.
  [[nodiscard]] std::uint64_t frames() const { return frames_; }
  /// Time of the last period stepped [s] (0 before the first).
  [[nodiscard]] double time() const;

  /// The pose device `device` (a scene index) reads at the next step; device coordinates.
  /// Throws std::invalid_argument for a device that is not controlled.
  void set_pose(std::size_t device, const haptics::DevicePose& pose);
  [[nodiscard]] bool controlled(std::size_t device) const;
  /// Per device, the newest frame (force sent, pose, proxy, contact); stable storage that
  /// each step overwrites in place.
  [[nodiscard]] const std::vector<HapticFrame>& latest_frames() const;
  /// Current positions of body i's simulation nodes; null for a body without dynamics. The
  /// vector may be swapped for another by the next step: copy what you keep.
  [[nodiscard]] const VecX* positions(std::size_t body) const;
  /// The emergency stop of every device from the next step on.
  void emergency_stop();

  /// Closes the recording and returns the run's report (statistics, safety counters, the
  /// frames when options.keep_frames). Stepping ends here; latest_frames() stays readable.
  SessionReport finish();
  [[nodiscard]] bool finished() const { return finished_; }

 private:
  const scene::Model& model_;
  SessionOptions options_;
  std::unique_ptr<Loops> loops_;
  SessionReport report_;
  std::unique_ptr<Recorder> recorder_;
  std::vector<ControlledDevice*> controlled_;  ///< per scene device; null: the scene's device
  std::uint64_t frames_ = 0;
  std::uint64_t simulation_steps_ = 0, interaction_steps_ = 0;
  Nanos wall_ = 0;
  bool finished_ = false;
};

}  // namespace tactus::runtime
