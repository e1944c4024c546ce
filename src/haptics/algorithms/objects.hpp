#pragma once
// What the algorithms among many rigid objects share (seed 000 §4: a room of touchable things):
// the objects (impostor levels, property images), the union of their chosen levels as one
// surface, and the choice of each object's level every frame:
//   1. each object's benefit is its nearness to the tool within the influence radius (an
//      object beyond it is never queried and costs nothing);
//   2. the object the tool touches follows the force from the level it was touched at
//      (lod::ForceThresholdSwitch: finer above raise_force, coarser below lower_force held for
//      hold_time, the coarser steps taken only once the tool has let go) and goes first,
//      within what the others leave at their coarsest;
//   3. the others' levels are chosen greedily by benefit per cost within the rest of the
//      frame's budget (lod::select_levels_into);
//   4. a switch of the touched object starts a blend: for blend_time the algorithm renders the
//      old level too (the query pointed at it for a trial) and sends the blend of the two.
#include <array>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "contact/bvh.hpp"
#include "contact/surface_query.hpp"
#include "haptics/force_algorithm.hpp"
#include "lod/impostors.hpp"
#include "lod/selection.hpp"
#include "property_images/property_images.hpp"

namespace tactus::haptics {

/// One rigid object a tool may touch.
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

/// The union of the objects' chosen levels (and a contact plane) as one surface for a tool.
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
  /// The member the last closest_point answered from: an object, the object count for the
  /// plane, −1 none.
  [[nodiscard]] int last_member() const { return last_member_; }

 private:
  std::vector<const contact::TriangleBvh*> trees_;
  std::vector<Aabb> boxes_;
  bool plane_ = false;
  Vec3 normal_ = Vec3::UnitZ();
  double offset_ = 0.0;
  mutable int last_member_ = -1;
};

/// Each object's level, frame by frame (the steps above), and the events that report them.
class LevelChooser {
 public:
  /// Seconds per BVH level a query is charged by the selection: a deterministic cost, so that
  /// lockstep runs choose alike on every machine (fitted to the levels' measured query times,
  /// docs/lod.md). A frame asks the surface about four times.
  static constexpr double kSecondsPerTreeLevel = 0.1e-6;
  static constexpr double kQueriesPerFrame = 4.0;
  /// A level's cost in the selection: kQueriesPerFrame × kSecondsPerTreeLevel × its BVH depth.
  [[nodiscard]] static double level_cost(const lod::ImpostorLevel& level);

  /// `reach`: how far from its origin the tool touches (the objects' boxes grow by it). Throws
  /// InputError for an object without levels or switch thresholds out of order.
  LevelChooser(std::vector<TouchableObject> objects, const ObjectsSettings& settings, double reach);

  struct State {
    ObjectsQuery query;
    std::vector<double> base_cost;  ///< per object and level, in the options' order
    std::vector<lod::ObjectLevels> options;
    lod::Selection selection;
    std::vector<std::size_t> level;  ///< rendered, per object
    std::vector<lod::ForceThresholdSwitch> switches;
    int touched = -1;         ///< last frame: object index, the object count for the plane, −1 none
    double force = 0.0;       ///< the force rendered last frame [N]
    int switch_object = -1;   ///< the object whose switch follows the force
    double last_touch = 0.0;  ///< when it was last touched [s]
    double cost = 0.0;        ///< of the levels rendered (objects beyond the influence radius cost nothing)
    double window_cost = 0.0, window_end = 0.0;  ///< the largest cost in the current 100 ms
    lod::LevelBlend blend;
    int blend_object = -1;
    std::size_t blend_from = 0;
    std::array<HapticEvent, 32> pending{};  ///< level changes waiting to be reported, one a frame
    int pending_count = 0;
  };
  [[nodiscard]] State make_state() const;

  /// This frame's levels from the tool's points `a` and `b` (its goal and where the contact
  /// holds it) and last frame's touch and force; points the query at them and at `plane` (the
  /// deformable bodies' contact plane, where settings().plane).
  void choose(double t, const Vec3& a, const Vec3& b, const LocalContact& plane, State& s) const;
  /// Whether the touched object's switch is being blended at t.
  [[nodiscard]] bool blending(double t, const State& s) const;
  /// Points the query at the blended object's old level (true) or back at its new one.
  void old_level(State& s, bool old) const;
  /// After rendering: what was touched and the force sent, and one pending event into `out`.
  void finish(double t, int touched, double force, State& s, Rendering& out) const;

  [[nodiscard]] std::span<const TouchableObject> objects() const { return objects_; }
  [[nodiscard]] const ObjectsSettings& settings() const { return settings_; }
  /// An object's level in use and the object of an encoded triangle id (ObjectsQuery).
  [[nodiscard]] const lod::ImpostorLevel& level_of(const State& s, std::size_t object) const {
    return objects_[object].levels->levels[s.level[object]];
  }

 private:
  std::vector<TouchableObject> objects_;
  std::vector<Aabb> boxes_;  ///< each object's levels together, grown by the reach
  ObjectsSettings settings_;
};

}  // namespace tactus::haptics
