#pragma once
// The interaction step, a function of its model, state and inputs: for every device, where
// its tool is closest to the newest deformed surfaces (the local contact plane the haptic
// step renders until the next one) or, for a needle, where its line crosses each layer.
// InteractionLoop wraps it with the channels, the clock and the statistics.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "contact/bvh.hpp"
#include "core/clock.hpp"
#include "haptics/algorithms/needle.hpp"
#include "haptics/exchange.hpp"
#include "mesh/curvature.hpp"
#include "runtime/exchange.hpp"
#include "runtime/loop_stats.hpp"
#include "scene/model.hpp"

namespace tactus::runtime {

/// One device's part in the interaction step.
struct InteractionTarget {
  std::string device;               ///< the device's name, for the timing report
  std::vector<std::size_t> bodies;  ///< bodies this device's algorithm touches
  double reach = 0.0;  ///< a surface farther than this from the tool origin gives no contact [m]
  /// q-ring size of the curvature vote at the contact point; 0 = no curvature needed.
  int curvature_rings = 0;
  /// > 0: a needle this long [m]; `bodies` are its layers, and instead of a closest point
  /// the step finds where the needle's line crosses each layer (haptics::NeedleSurfaces).
  double needle_length = 0.0;
};

/// What the step reads and never changes.
struct InteractionModel {
  const scene::Model* scene = nullptr;  ///< the bodies' triangles
  std::vector<InteractionTarget> targets;
  /// Per target and body: the curvature estimator, where the target's algorithm needs one
  /// and the body's surface is a manifold.
  std::vector<std::vector<std::unique_ptr<const mesh::CurvatureEstimator>>> curvature;
  /// Per body: some target touches it here. The others' trees are never built:
  /// the touchable objects of a scene of many are queried by the haptic loop itself.
  std::vector<bool> queried;
};
/// Warns (and leaves the body flat) where a surface has no curvature estimate.
[[nodiscard]] InteractionModel make_interaction_model(const scene::Model& scene, std::vector<InteractionTarget> targets);

/// What the step changes: one tree per body, refitted to each new simulation step (rebuilt
/// when refits have degraded it), so that a query costs about a microsecond.
struct InteractionState {
  std::vector<contact::TriangleBvh> trees;
  std::uint64_t tree_step = ~std::uint64_t{0};
  std::vector<contact::RayHit> hits;  ///< reused by the needle queries
};
[[nodiscard]] InteractionState make_interaction_state(const InteractionModel& model);

struct InteractionInputs {
  const SurfaceSnapshot* surfaces = nullptr;  ///< the newest deformed surfaces
  std::span<const ToolState> tools;  ///< per target
  /// Times the parts for the statistics when set (the loop's clock); the step reads no other.
  Nanos (*clock)() = nullptr;
};

/// Written in place, per target: the contact plane, and for a needle its layer crossings.
/// `parts`, when not empty, receives the parts' times: per target "query per body" and
/// "interaction", then "refit trees" (InteractionLoop::parts).
struct InteractionOutputs {
  std::span<haptics::LocalContact* const> contacts;
  std::span<haptics::NeedleSurfaces* const> needles;
  std::span<PartStats> parts;
};

void interaction_step(const InteractionModel& model, InteractionState& state, const InteractionInputs& in,
                      const InteractionOutputs& out);

}  // namespace tactus::runtime
