#pragma once
// The god-object proxy among many rigid objects (seed 000 §4: a room of touchable things),
// queried at the haptic rate on each object's chosen impostor level, with the surface
// material of each object's haptic property images (seed 001, second chapter).
//
// Every frame:
//   1. each object's benefit is its nearness to the tool within the influence radius (an
//      object beyond it is never queried and costs nothing);
//   2. the object the proxy touches follows the force from the level it was touched at
//      (lod::ForceThresholdSwitch: finer above raise_force, coarser below lower_force held for
//      hold_time) and goes first, within what the others leave at their coarsest;
//   3. the others' levels are chosen greedily by benefit per cost within the rest of the
//      frame's budget (lod::select_levels_into);
//   4. the proxy moves against the union of the objects' chosen levels (and the interaction
//      loop's contact plane of the deformable bodies, where there are any), its coupling's
//      stiffness, friction and damping those painted where it touches; a roughness texture tilts and lifts the force (force shading: F_n·(n −
//      ∇h) + k·h·n, with h the texture height of the property image's view);
//   5. across a level switch of the touched object the force blends from the old level's
//      (the proxy moved against the old surface on a copy) to the new one's.
//
// The proxy is carried across a switch, not nested: a finer level may lie outside a coarser
// one (Loop subdivision moves vertices; decimation cuts corners), and a proxy left behind the
// new surface is pushed out through its closest point by the proxy's closed-surface rule.
#include <array>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "contact/bvh.hpp"
#include "contact/proxy.hpp"
#include "contact/surface_query.hpp"
#include "haptics/algorithms/contact_law.hpp"
#include "haptics/algorithms/proxy_coupling.hpp"
#include "haptics/force_algorithm.hpp"
#include "lod/impostors.hpp"
#include "lod/selection.hpp"
#include "property_images/property_images.hpp"

namespace tactus::haptics {

/// One rigid object the proxy may touch.
struct TouchableObject {
  std::int32_t body = -1;  ///< index into Model::bodies
  std::shared_ptr<const lod::ImpostorHierarchy> levels;  ///< coarse to fine; at least one
  /// The surface material; null: the coupling's own stiffness and friction. Shared with whoever
  /// paints it while the run goes on (property_images.hpp: lock-free).
  std::shared_ptr<property_images::PropertyImages> properties;
  double raise_force = 2.0, lower_force = 1.0, hold_time = 0.1;  ///< lod::SwitchParams
};

struct ObjectsSettings {
  double budget = 15e-6;           ///< [s] of each frame for the objects' queries
  double influence_radius = 0.05;  ///< [m]
  double blend_time = 0.005;       ///< [s]
  /// [N/m] the stiffest coupling the device renders stably: painted stiffness is capped here.
  double max_stiffness = std::numeric_limits<double>::infinity();
  /// false: every object at its finest level, never switched.
  bool select = true;
  /// Deformable bodies are touched too, through the interaction loop's contact plane.
  bool plane = false;
};

/// The union of the objects' chosen levels (and a contact plane) as one surface for the proxy.
/// Triangle ids are object · kObjectStride + triangle; the plane's is −1.
class ObjectsQuery final : public contact::SurfaceQuery {
 public:
  static constexpr std::int32_t kObjectStride = 1 << 24;

  void resize(std::size_t objects);
  void set(std::size_t object, const contact::TriangleBvh* tree, const Aabb& box);
  void set_plane(bool valid, const Vec3& normal, double offset);
  [[nodiscard]] contact::ClosestSurfacePoint closest_point(const Vec3& p) const override;
  [[nodiscard]] contact::SweepHit sweep_sphere(const Vec3& from, const Vec3& to, double radius) const override;
  [[nodiscard]] std::optional<std::array<Vec3, 3>> triangle(std::int32_t t) const override;
  /// The member the last closest_point answered from: an object, objects() for the plane, −1 none.
  [[nodiscard]] int last_member() const { return last_member_; }
  [[nodiscard]] std::size_t objects() const { return trees_.size(); }

 private:
  std::vector<const contact::TriangleBvh*> trees_;
  std::vector<Aabb> boxes_;
  bool plane_ = false;
  Vec3 normal_ = Vec3::UnitZ();
  double offset_ = 0.0;
  mutable int last_member_ = -1;
};

class ProxyOnObjects final : public ForceAlgorithm {
 public:
  /// Seconds per BVH level a query is charged by the selection: a deterministic cost, so that
  /// lockstep runs choose alike on every machine (fitted to the levels' measured query times,
  /// docs/lod.md). A frame asks the proxy's surface about four times.
  static constexpr double kSecondsPerTreeLevel = 0.1e-6;
  static constexpr double kQueriesPerFrame = 4.0;
  /// A level's cost in the selection: kQueriesPerFrame × kSecondsPerTreeLevel × its BVH depth.
  [[nodiscard]] static double level_cost(const lod::ImpostorLevel& level);

  /// Throws InputError for an object without levels or switch thresholds out of order.
  ProxyOnObjects(ToolSphere sphere, const contact::ProxyParams& params, std::vector<TouchableObject> objects,
                 const ObjectsSettings& settings);

  [[nodiscard]] std::unique_ptr<AlgorithmState> make_state() const override;
  [[nodiscard]] Rendering render(const FrameInputs& frame, AlgorithmState& state) const override;
  void react(const FrameInputs& frame, const Rendering& rendered, const Reaction& reaction, AlgorithmState& state,
             ContactLoad& load) const override;
  [[nodiscard]] EditableSurface editable_surface() const override { return proxy_surface(params_); }
  void edit_surface(const SurfaceValues& values, AlgorithmState& state) const override;

  [[nodiscard]] std::span<const TouchableObject> objects() const { return objects_; }
  [[nodiscard]] const ObjectsSettings& settings() const { return settings_; }
  /// The level each object renders at and their summed cost, as of the last frame
  /// (for tests and the viewer's debug view; read on the haptic thread or in lockstep only).
  [[nodiscard]] static std::span<const std::size_t> levels_in_use(const AlgorithmState& state);
  [[nodiscard]] static double cost_in_use(const AlgorithmState& state);

 private:
  struct State;

  ToolSphere sphere_;
  contact::ProxyParams params_;
  std::vector<TouchableObject> objects_;
  std::vector<Aabb> boxes_;  ///< each object's finest level, grown by the proxy's radius
  ObjectsSettings settings_;
};

}  // namespace tactus::haptics
