#pragma once
// A run of a scene: the haptic loops (one per device), the simulation and interaction
// loops and the recorder, wired through lock-free channels and driven by one of two
// schedulers over the same step functions:
//  - real time: a thread per loop on the wall clock (SCHED_FIFO and pinning when the
//    system permits, sleep-then-spin waits);
//  - lockstep: one thread, virtual time, bit-for-bit reproducible.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "compile/touchables.hpp"
#include "core/clock.hpp"
#include "core/triple_buffer.hpp"
#include "haptics/device.hpp"
#include "haptics/safety.hpp"
#include "runtime/devices.hpp"
#include "runtime/exchange.hpp"
#include "runtime/loop_stats.hpp"
#include "runtime/needle_report.hpp"
#include "runtime/palpation_feedback.hpp"
#include "runtime/recording.hpp"
#include "scene/model.hpp"

namespace tactus::haptics {
struct HapticModel;
}

namespace tactus::runtime {

enum class Scheduling { real_time, lockstep };

struct LoopEvent;
class LiveParameters;

/// What a viewer sees of a run (docs/viewer.md). Every call comes from off the haptic
/// threads: the buffer is asked for once before the loops start, frames and events as the
/// recorder drains them.
class VisualSink {
 public:
  virtual ~VisualSink() = default;
  /// A buffer the simulation publishes its surfaces into (beside the interaction loop's),
  /// built from `initial` and owned by the sink; the sink's thread is its one reader.
  virtual TripleBuffer<SurfaceSnapshot>& surface_buffer(const SurfaceSnapshot& initial) = 0;
  virtual void frame(const HapticFrame& frame) = 0;
  virtual void event(const LoopEvent& event) = 0;
};

struct SessionOptions {
  Scheduling scheduling = Scheduling::real_time;
  /// Run length [s]; 0 = until every device has finished its input, at most max_duration.
  double duration = 0.0;
  double max_duration = 30.0;
  std::optional<std::filesystem::path> record;
  /// The scene's text and origin, stored in a recording so that it replays by itself.
  std::string scene_text;
  std::string scene_source;
  /// Devices whose poses come from a recording instead of the scene's device (by name).
  std::map<std::string, RecordedMotion> replay;
  /// Real time, overriding the scene's [realtime] table: SCHED_FIFO priority of the haptic
  /// threads (0 = normal scheduler; the other loops get 10 less, or nice 10 off SCHED_FIFO), the CPU to pin them to
  /// (−1 = none), and how long before each haptic deadline the wait spins.
  std::optional<int> realtime_priority;
  std::optional<int> haptic_cpu;
  std::optional<Nanos> spin_window;
  /// Keep every haptic frame in the report (tests, replay comparison).
  bool keep_frames = false;
  /// Lockstep runs: a progress bar over the run's length with this label
  /// (core/progress.hpp); empty = none.
  std::string progress;
  /// Emergency stop of every device at this time [s] (tests; the viewer has a key).
  std::optional<double> emergency_stop_at;
  /// When set and it becomes true (a signal handler, another thread), the run ends
  /// cleanly: loops stop, the recording is closed.
  const std::atomic<bool>* interrupt = nullptr;
  /// A ParaView time series of the run written into this folder (runtime/vtk_series.hpp),
  /// `vtk_rate` frames per second of simulated time.
  std::optional<std::filesystem::path> vtk;
  double vtk_rate = 30.0;
  /// A viewer reading the run; null = none.
  VisualSink* visual = nullptr;
  /// Parameters edited during the run and the emergency stop (runtime/live_parameters.hpp);
  /// null = none. Its surfaces are described by the run when its loops are built.
  LiveParameters* live = nullptr;
  /// The scene's touchable objects, built by the caller so that it shares them with the run
  /// (the viewer paints their property images); null: the run builds its own.
  const compile::Touchables* touchables = nullptr;
  /// Replaces the device of scene entry `index` (the viewer's mouse) when it returns one.
  std::function<std::unique_ptr<haptics::Device>(const scene::Model&, std::size_t index)> device_override;
  /// Edits what scene device `index` renders, as compiled from the scene, before its haptic
  /// loop is built: a program embedding the engine appends its own force algorithms here
  /// (haptics/force_algorithm.hpp; at most one contact-stage algorithm per device, the
  /// scene's included) or changes the smoothing and safety settings. Called once per device,
  /// on the thread that starts the run (docs/api.md).
  std::function<void(const scene::Model&, std::size_t index, haptics::HapticModel& model)> customize_haptics;
};

struct DeviceReport {
  std::string name;
  std::string kind;
  haptics::SafetyCounters safety;
  std::uint64_t dropped_frames = 0;
  double max_force_sent = 0.0;  ///< [N]
  std::uint64_t contact_frames = 0;
  /// Frames in which the passivity controller weakened the force, and the energy it kept
  /// from the hand [J] (haptics/passivity_control.hpp).
  std::uint64_t passivity_frames = 0;
  double passivity_energy = 0.0;
  bool has_patch = false;  ///< rendered on local patches the simulation cut (patch_reach applies)
  PatchReach patch_reach{};
};

/// A two-finger contact state as one finger's loop classified it (seed 002 Table I).
struct ContactStateChange {
  double t = 0.0;          ///< when it began [s]
  std::uint16_t device = 0;
  std::uint8_t state = 0;  ///< 1..9: I..IX
};

/// An object's impostor level changed (scenes of many objects, docs/lod.md).
struct LevelSwitchRecord {
  double t = 0.0;  ///< [s]
  std::uint16_t device = 0;
  std::int32_t body = -1;   ///< index into Model::bodies
  std::uint32_t level = 0;  ///< the new level, 0 coarsest
};

/// A touchable object's levels, as the haptic loop chose among them.
struct TouchableReport {
  std::string name;
  std::int32_t body = -1;
  struct Level {
    std::size_t triangles = 0;
    double cost = 0.0;        ///< charged by the selection per frame [s]
    double hausdorff = 0.0;   ///< to the finest level [m]
    double query_p50 = 0.0;   ///< measured closest-point query [s]
  };
  std::vector<Level> levels;  ///< coarse to fine
};

struct SessionReport {
  std::string scene;
  Scheduling scheduling = Scheduling::real_time;
  double simulated_time = 0.0;  ///< [s] time reached by the loops
  double wall_time = 0.0;       ///< [s]
  std::vector<LoopStats> loops;   ///< haptic loops first, then simulation, interaction
  std::vector<PartStats> parts;   ///< simulation step parts, per-body query times
  std::vector<DeviceReport> devices;
  std::map<std::string, std::uint64_t> events;  ///< count per event kind
  std::vector<std::string> realtime_notes;      ///< what the real-time requests obtained
  std::uint64_t recorded_frames = 0;
  std::uint64_t recording_bytes = 0;
  std::uint64_t vtk_frames = 0, vtk_bytes = 0;  ///< the --vtk series written
  std::uint64_t dropped_steps = 0;
  /// Simulation steps that spanned more than one period to keep real time ([rates] catch_up).
  std::uint64_t caught_up_steps = 0;
  bool visual = false;  ///< a viewer read the run (SessionOptions::visual)
  std::vector<HapticFrame> frames;  ///< only with SessionOptions::keep_frames
  std::optional<PalpationFeedback> palpation;  ///< scenes with nodules (docs/scenes.md)
  std::vector<NeedleReport> needles;           ///< one per device driving a needle
  std::vector<ContactStateChange> contact_states;  ///< two-finger fabric scenes, in time order per device
  std::vector<LevelSwitchRecord> level_switches;   ///< scenes of many objects, in time order per device
  std::vector<TouchableReport> touchables;         ///< the scene's touchable objects
  double level_budget = 0.0;                       ///< [s] of each haptic frame ([lod] haptic_budget)
  /// The budget used, per device and 100 ms window [s].
  std::vector<std::pair<std::uint16_t, double>> level_costs;
  std::vector<std::string> cspace_notes;       ///< what on-line spaces solved during the run
};

/// Runs the scene. Throws InputError for a scene the runtime cannot run (named in the
/// message), std::runtime_error when the simulation diverges.
SessionReport run_session(const scene::Model& model, const SessionOptions& options);

}  // namespace tactus::runtime
