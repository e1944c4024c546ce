#pragma once
// The simulation loop: the channels, the clock and the statistics around the simulation
// step (runtime/simulation_step.hpp). Each step reads every device's newest push and the
// live material edits, advances the bodies, reads the newest tools and publishes the
// deformed surfaces and the devices' local patches.
#include <cstdint>
#include <vector>

#include "compile/cspace_body.hpp"
#include "core/spsc_ring.hpp"
#include "core/triple_buffer.hpp"
#include "runtime/haptic_loop.hpp"
#include "runtime/loop_stats.hpp"
#include "runtime/simulation_step.hpp"
#include "scene/model.hpp"

namespace tactus::runtime {

class LiveParameters;

class SimulationLoop {
 public:
  /// `devices` are the haptic loops' channels (their contact loads are read here); `live`,
  /// when set, the material edits read at each step.
  SimulationLoop(const scene::Model& model, std::vector<DeviceChannels*> devices,
                 const compile::CspaceBodies& cspaces = {}, const LiveParameters* live = nullptr);

  /// The rest surfaces, sized as every snapshot will be: the initial value of an output.
  [[nodiscard]] SurfaceSnapshot initial_snapshot() const { return rest_surfaces(model_); }
  /// Adds a buffer that receives a surface snapshot after each step (before the loop runs).
  void add_output(TripleBuffer<SurfaceSnapshot>& output) { outputs_.push_back(&output); }
  /// The rest nodes, sized as every node snapshot will be.
  [[nodiscard]] NodeSnapshot initial_nodes() const { return rest_nodes(model_); }
  /// Adds a buffer that receives every body's nodes after each step (before the loop runs).
  void add_node_output(TripleBuffer<NodeSnapshot>& output) { node_outputs_.push_back(&output); }
  /// Body i as the compile stage built it (null: not simulated). Immutable while the loop
  /// runs, so another thread may read it (its const methods; never its scratch).
  [[nodiscard]] const physics::Body* body(std::size_t i) const {
    return i < model_.bodies.size() && model_.bodies[i].physics ? &*model_.bodies[i].physics : nullptr;
  }

  /// Advances every body by one period (1 / rate) and publishes the surfaces and the devices' local
  /// patches; `t` is the time reached.
  /// Throws std::runtime_error when a body diverges (NaN positions).
  void step(double t, Nanos deadline, Nanos start, bool real_time);

  [[nodiscard]] double rate() const { return stats_.rate; }
  [[nodiscard]] const LoopStats& stats() const { return stats_; }
  [[nodiscard]] const std::vector<PartStats>& parts() const { return parts_; }
  /// Simulation steps for the recorder.
  SpscRing<SimulationStep>& steps() { return steps_ring_; }
  [[nodiscard]] std::uint64_t dropped_steps() const { return dropped_steps_; }
  /// Steps that spanned more than one period ([rates] catch_up). Read after the loop stopped.
  [[nodiscard]] std::uint64_t caught_up_steps() const { return state_.late_steps; }
  /// Current positions of body i's simulation nodes (for tests and reports).
  [[nodiscard]] const VecX* positions(std::size_t body) const;

 private:
  SimulationModel model_;
  SimulationState state_;
  std::vector<DeviceChannels*> devices_;
  std::vector<TripleBuffer<SurfaceSnapshot>*> outputs_;
  std::vector<TripleBuffer<NodeSnapshot>*> node_outputs_;
  const LiveParameters* live_ = nullptr;
  // Per device and per output, sized once: the step's inputs and the buffers it writes.
  std::vector<ContactLoad> loads_;
  std::vector<ToolState> tools_;
  std::vector<contact::LocalPatch*> patches_;
  std::vector<SurfaceSnapshot*> surfaces_;
  LoopStats stats_;
  std::vector<PartStats> parts_;
  SpscRing<SimulationStep> steps_ring_;
  std::uint64_t dropped_steps_ = 0;
};

}  // namespace tactus::runtime
