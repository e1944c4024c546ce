#pragma once
// The simulation step, in two functions of its model, state and inputs: advance every
// deformable body one period under its scene loads and the contact pushes the haptic steps
// handed over (advance_bodies), then shape the bodies that follow others (configuration
// spaces, embedded layers) and write the deformed surfaces and each patch device's local
// patch (publish_shapes). Two, so that the tools a patch is cut around are read after the
// integration, as late as they can be. SimulationLoop wraps them with the channels, the
// clock and the statistics.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "compile/cspace_body.hpp"
#include "contact/load_spread.hpp"
#include "contact/local_model.hpp"
#include "core/clock.hpp"
#include "physics/body.hpp"
#include "runtime/exchange.hpp"
#include "runtime/live_parameters.hpp"
#include "runtime/loop_stats.hpp"
#include "scene/model.hpp"

namespace tactus::runtime {

/// What the step reads and never changes: each body as the compile stage built it.
struct SimulationModel {
  /// One per scene body, in the scene's order (bodies[i] is scene->bodies[i]).
  struct Body {
    std::optional<physics::Body> physics;   ///< empty for rigid, embedded and cspace bodies
    VecX rest;
    int substeps = 1;  ///< steps of at most the body's time step in one period
    std::vector<mesh::Index> surface_to_node;
    std::vector<double> surface_area;  ///< per surface vertex, at rest (spreads contact loads)
    std::shared_ptr<const compile::CspaceBody> cspace;  ///< kind = "cspace": shaped, not simulated
    /// Volumetric bodies: nodes within this distance of a needle's shaft share its push
    /// (three quarters of the mean tetrahedron edge, so the shaft always finds some) [m].
    double shaft_reach = 0.0;
  };
  const scene::Model* scene = nullptr;
  double period = 0.0;  ///< 1 / simulation rate [s]
  std::vector<Body> bodies;
  bool embedded = false;  ///< some body is an embedded surface
  /// Per device: the patch it is rendered on (none: a plane or no contact model).
  std::vector<std::optional<PatchRequest>> patches;
};
[[nodiscard]] SimulationModel make_simulation_model(const scene::Model& scene,
                                                    std::vector<std::optional<PatchRequest>> patches,
                                                    const compile::CspaceBodies& cspaces = {});

/// What the steps change.
struct SimulationState {
  struct Body {
    physics::BodyState state;
    VecX f_ext;
    VecX x_before;  ///< positions before the last step (the patches' border velocities)
    double span = 0.0;  ///< the time the last step covered [s]
    std::vector<Vec3> surface, surface_before;
    /// Embedded surfaces: the forces on their vertices and their mapped positions, sized once.
    std::vector<Vec3> carried_forces, carried_positions;
    /// The devices' contact pushes on this body this step, coupled into its solve.
    std::vector<physics::ContactSpring> springs;
    /// Live material edits: the body stepped with its force model wrapped, scaled as edited.
    std::shared_ptr<LiveMaterialModel> live;
    std::optional<physics::Body> edited;
  };
  /// Per device: where its push went this step, and for a patch device the builders (one per
  /// body it may touch) and the push the last step applied.
  struct Device {
    std::vector<physics::NodeShare> nodes;
    std::size_t body = 0;
    int spring = -1;        ///< index into that body's springs; −1: none this step
    int spring_count = 0;   ///< its springs from `spring` on: 2 for a hold along a plane
    std::vector<std::unique_ptr<contact::PatchBuilder>> builders;
    ContactLoad applied;
    std::vector<contact::LoadShare> applied_shares;
  };
  std::vector<Body> bodies;
  std::vector<Device> devices;
  std::array<contact::LoadShare, 256> shares{};  ///< up to 32 per sphere of an 8-sphere finger
  std::uint64_t step = 0;
  double t = 0.0;  ///< the time the last step reached [s]
  std::uint64_t late_steps = 0;  ///< steps that spanned more than one period (catch_up)
  std::uint64_t materials_version = 0;  ///< of the live material edits last applied
};
/// `live_materials`: the bodies whose material the user may edit (LiveParameters) are
/// stepped through an editable wrapper of their force model.
[[nodiscard]] SimulationState make_simulation_state(const SimulationModel& model,
                                                    const LiveParameters* live_materials = nullptr);

/// The rest surfaces, sized as every snapshot: the initial value of an output.
[[nodiscard]] SurfaceSnapshot rest_surfaces(const SimulationModel& model);

/// The rest nodes, sized as every node snapshot.
[[nodiscard]] NodeSnapshot rest_nodes(const SimulationModel& model);
/// Every body's positions, velocities and contact pushes into a snapshot sized by rest_nodes.
void write_nodes(const SimulationModel& model, const SimulationState& state, double t, NodeSnapshot& s);

/// The step's parts, in SimulationLoop::parts order.
enum SimulationPart : std::size_t { contact_loads, integrate, publish_surfaces, local_models, embedded_surfaces,
                                    shaft_node_search, simulation_part_count };

struct SimulationInputs {
  double t = 0.0;  ///< the time reached after this step [s]
  std::span<const ContactLoad> loads;  ///< per device, the newest push
  /// Material edits (LiveParameters::materials()) and the scene's values they scale.
  const LiveParameters::Materials* materials = nullptr;
  const LiveParameters::Materials* scene_materials = nullptr;
  /// Times the parts when set (the loop's clock; `start` when the step began).
  Nanos (*clock)() = nullptr;
  Nanos start = 0;
};

/// Advances every deformable body one period (none at the first step, which publishes the
/// rest shapes); returns the linear solver iterations. A step that reaches `in.t` more than
/// one and a half periods after the last one (real time, after missed periods) advances the
/// implicit bodies over that time, up to the scene's `catch_up` periods, in as many substeps
/// as one period takes; explicit ones, bound to their time step, one period. Throws
/// std::runtime_error when a body diverges (NaN positions).
int advance_bodies(const SimulationModel& model, SimulationState& state, const SimulationInputs& in,
                   std::span<PartStats> parts);

struct SimulationOutputs {
  std::span<SurfaceSnapshot* const> surfaces;       ///< each gets every body's surface
  std::span<contact::LocalPatch* const> patches;    ///< per device (null: no patch)
  std::span<PartStats> parts;
};

/// Shapes the configuration-space bodies at the tool of the first device without a patch,
/// carries the embedded layers with their hosts, and writes the surfaces and the patches
/// cut around each patch device's tool.
void publish_shapes(const SimulationModel& model, SimulationState& state, const SimulationInputs& in,
                    std::span<const ToolState> tools, const SimulationOutputs& out);

}  // namespace tactus::runtime
