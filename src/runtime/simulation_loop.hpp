#pragma once
// The simulation loop step: every deformable body advances one period under its scene
// loads and the contact reactions the haptic loops handed over, then the deformed surfaces
// are published for the interaction (and visual) loops.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "compile/cspace_body.hpp"
#include "core/spsc_ring.hpp"
#include "core/triple_buffer.hpp"
#include "physics/body.hpp"
#include "runtime/haptic_loop.hpp"
#include "runtime/loop_stats.hpp"
#include "scene/model.hpp"

namespace tactus::runtime {

class LiveParameters;
class LiveMaterialModel;

class SimulationLoop {
 public:
  /// `devices` are the haptic loops' channels (their contact loads are read here).
  SimulationLoop(const scene::Model& model, std::vector<DeviceChannels*> devices,
                 const compile::CspaceBodies& cspaces = {});

  /// The rest surfaces, sized as every snapshot will be: the initial value of an output.
  [[nodiscard]] SurfaceSnapshot initial_snapshot() const;
  /// Adds a buffer that receives a surface snapshot after each step (before the loop runs).
  void add_output(TripleBuffer<SurfaceSnapshot>& output) { outputs_.push_back(&output); }
  /// Material edits read at each step (runtime/live_parameters.hpp); before the loop runs.
  void set_live_parameters(const LiveParameters* live);

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
  /// Current positions of body i's simulation nodes (for tests and reports).
  [[nodiscard]] const VecX* positions(std::size_t body) const;

 private:
  struct SimBody {
    std::size_t index = 0;  ///< into Model::bodies
    std::optional<physics::Body> body;  ///< empty for rigid (static) bodies
    physics::BodyState state;
    VecX rest, f_ext;
    int substeps = 1;
    std::vector<mesh::Index> surface_to_node;
    VecX x_before;  ///< positions before the last step (the patches' border velocities)
    std::vector<Vec3> surface, surface_before;
    std::vector<double> surface_area;  ///< per surface vertex, at rest (spreads contact loads)
    std::shared_ptr<const compile::CspaceBody> cspace;  ///< kind = "cspace": shaped, not simulated
    std::shared_ptr<LiveMaterialModel> live;   ///< wraps body->model under live edits
    /// kind = "embedded": carried by the host's tetrahedra (scene::Body::host_mapping); the
    /// forces on its vertices and its mapped positions, sized once.
    std::vector<Vec3> carried_forces, carried_positions;
    /// Volumetric bodies: nodes within this distance of a needle's shaft share its push
    /// (three quarters of the mean tetrahedron edge, so the shaft always finds some) [m].
    double shaft_reach = 0.0;
    /// The devices' contact pushes on this body this step, coupled into its solve.
    std::vector<physics::ContactSpring> springs;
  };
  /// Where a device's push went this step: its nodes' shares, and the spring it became.
  struct DevicePush {
    std::vector<physics::NodeShare> nodes;
    std::size_t body = 0;
    int spring = -1;  ///< index into that body's springs; −1: none this step
  };
  /// A device whose local model is a patch: one builder per body it may touch, and the
  /// contact load the last step applied for it.
  struct PatchSource {
    DeviceChannels* channels = nullptr;
    std::vector<std::unique_ptr<contact::PatchBuilder>> builders;  ///< per body; null if not touched
    ContactLoad applied;
    std::vector<contact::LoadShare> applied_shares;  ///< how the step spread it
  };
  /// The surface vertices' shares of a contact load, on the body's current shape.
  std::span<const contact::LoadShare> spread(SimBody& sb, const ContactLoad& load);

  /// Cspace bodies take the interpolated shape at the tool's position.
  void update_cspace_shapes();
  /// Embedded surfaces follow their hosts' new node positions.
  void update_embedded_shapes();
  /// Adds a contact load on an embedded surface to its host's external forces.
  void carry_to_host(SimBody& sb, std::span<const contact::LoadShare> shares, const Vec3& force);
  /// A needle shaft's push shared by the tissue nodes near it (seed 003 §3.3's proximity
  /// search of behaviour-mesh nodes near the needle's ray).
  void push_along_shaft(const ContactLoad& load);
  void publish(double t);
  void publish_patches(double t);
  void apply_live_parameters(double t);  // live_parameters.cpp

  const scene::Model& model_;
  bool embedded_ = false;  ///< some body is an embedded surface
  std::vector<DeviceChannels*> devices_;
  std::vector<TripleBuffer<SurfaceSnapshot>*> outputs_;
  std::vector<SimBody> bodies_;
  std::vector<PatchSource> patch_sources_;
  std::vector<DevicePush> pushes_;  ///< per device
  static constexpr std::size_t kSharesPerContact = 64;  ///< vertices one contact's load spreads over, at most
  std::array<contact::LoadShare, 256> shares_{};         ///< up to 32 per sphere of an 8-sphere finger
  std::uint64_t step_ = 0;
  LoopStats stats_;
  std::vector<PartStats> parts_;  ///< loads, integrate, publish
  SpscRing<SimulationStep> steps_ring_;
  std::uint64_t dropped_steps_ = 0;
  const LiveParameters* live_ = nullptr;
  std::uint64_t live_version_ = 0;
};

}  // namespace tactus::runtime
