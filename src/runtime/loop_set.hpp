#pragma once
// Every loop of a run and the channels between them, built before any loop starts, and
// the two schedulers that drive them.
#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "compile/touchables.hpp"
#include "core/triple_buffer.hpp"
#include "runtime/haptic_loop.hpp"
#include "runtime/interaction_loop.hpp"
#include "runtime/recorder.hpp"
#include "runtime/session.hpp"
#include "runtime/simulation_loop.hpp"
#include "runtime/vtk_series.hpp"

namespace tactus::runtime {

/// Everything a run owns, built before any loop starts.
struct Loops {
  compile::CspaceBodies cspaces;  ///< per scene body; shared by the loops that render them
  compile::Touchables touchables;  ///< the scene's touchable objects, shared by every device and the viewer
  std::vector<std::unique_ptr<DeviceChannels>> channels;
  std::vector<std::unique_ptr<HapticLoop>> haptic;
  std::unique_ptr<TripleBuffer<SurfaceSnapshot>> surfaces;
  std::unique_ptr<SimulationLoop> simulation;
  std::unique_ptr<InteractionLoop> interaction;
  /// SessionOptions::vtk: the simulation's nodes for the series the recorder writes.
  std::unique_ptr<TripleBuffer<NodeSnapshot>> nodes;
  std::unique_ptr<VtkSeries> vtk;

  [[nodiscard]] std::vector<DeviceChannels*> channel_ptrs() const {
    std::vector<DeviceChannels*> out;
    for (const auto& c : channels) out.push_back(c.get());
    return out;
  }
  [[nodiscard]] bool all_finished(double t) const {
    return std::all_of(haptic.begin(), haptic.end(), [t](const auto& h) { return h->finished(t); });
  }
};

/// Builds the devices (or their replays), the haptic loops and the channels, the
/// simulation and interaction loops.
Loops build_loops(const scene::Model& model, const SessionOptions& options);

/// Where a lockstep run stands: the simulation and interaction steps taken so far.
struct LockstepCursor {
  std::uint64_t simulation_steps = 0;
  std::uint64_t interaction_steps = 0;
};
/// The simulation and interaction steps due by haptic time t (the recorder drained after each
/// simulation step): the first half of a lockstep haptic period.
void lockstep_catch_up(const scene::Model& model, Loops& loops, Recorder& recorder, LockstepCursor& cursor, double t);
/// Every device's haptic frame at t: the second half.
void lockstep_haptic_frames(Loops& loops, double t);

/// Throws InputError for a scene or options the runtime cannot run (no device, a replay of
/// a device the scene lacks).
void check_runnable(const scene::Model& model, const SessionOptions& options);
/// The report's device entries, before the loops run.
void start_report(const scene::Model& model, const SessionOptions& options, const Loops& loops, SessionReport& report);
/// The loops' statistics, safety counters, needle and space notes, after they stopped.
void complete_report(const scene::Model& model, const Loops& loops, SessionReport& report);

/// One thread, virtual time: reproducible bit for bit.
void run_lockstep(const scene::Model& model, const SessionOptions& options, Loops& loops, Recorder& recorder,
                  SessionReport& report);
/// A thread per loop on the wall clock; this thread records and decides when to stop.
void run_real_time(const scene::Model& model, const SessionOptions& options, Loops& loops, Recorder& recorder,
                   SessionReport& report);

}  // namespace tactus::runtime
