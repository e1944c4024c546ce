#pragma once
// Choosing impostor levels at run time (seed 000 §4.2) and switching a haptic level by
// force (§4.1), as pure functions and plain state structs stepped with (time, force): no
// clock is read here, so the same inputs give the same choices in lockstep and real time.
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "core/math.hpp"

namespace tactus::lod {

/// One level of an object as the selection sees it.
struct LevelOption {
  double cost = 0.0;   ///< what drawing or querying it costs (e.g. seconds per frame), ≥ 0
  double error = 0.0;  ///< its error against the finest level (e.g. Hausdorff), ≥ 0
};

/// An object's levels, coarse to fine, and how much a more accurate level of it is worth.
struct ObjectLevels {
  std::vector<LevelOption> levels;
  double benefit = 0.0;  ///< ≥ 0; graphics_benefit, haptic_benefit or a blend of them
};

struct Selection {
  std::vector<std::size_t> level;  ///< per object, an index into its levels
  double cost = 0.0;               ///< summed cost of the chosen levels
  double weighted_error = 0.0;     ///< Σ benefit × error of the chosen levels (lower is better)
  /// False when even the coarsest levels exceed the budget (every object is then at its
  /// coarsest and `cost` is over the budget).
  bool within_budget = true;
};

/// One level per object, greedy by benefit per cost: everyone starts at its coarsest
/// level; then, as long as some refinement fits the budget, the object whose refinement
/// (to any finer level) removes the most benefit-weighted error per extra cost, benefit ×
/// (error now − error there) / (cost there − cost now), takes it. A refinement that costs
/// nothing more and removes error goes first; one that removes no error is never taken.
/// Ties go to the lower object index, then to the coarser level. Deterministic. Throws
/// InputError for an object without levels, a negative or non-finite cost, error or
/// benefit, or a negative or NaN budget.
[[nodiscard]] Selection select_levels(std::span<const ObjectLevels> objects, double budget);
/// select_levels without its checks (make them once with select_levels or check_levels),
/// written into `out` and reusing its storage: no allocation once out.level has one entry
/// per object, so that the haptic loop may choose every frame.
void select_levels_into(std::span<const ObjectLevels> objects, double budget, Selection& out);
/// The checks of select_levels: throws InputError as it would.
void check_levels(std::span<const ObjectLevels> objects, double budget);

/// Σ benefit × error and Σ cost of a given choice (for comparisons with select_levels).
[[nodiscard]] Selection evaluate_selection(std::span<const ObjectLevels> objects, std::span<const std::size_t> level,
                                           double budget);

/// Graphics benefit: the object's projected radius on screen, viewport_scale × radius /
/// distance from the eye to its centre (the distance taken as at least the radius, so the
/// eye inside the bounding sphere sees it whole). viewport_scale is the focal length in
/// pixels (viewport height / (2 tan(fov_y / 2))) for a benefit in pixels.
[[nodiscard]] double graphics_benefit(const Vec3& center, double radius, const Vec3& eye, double viewport_scale);

/// Haptic benefit: 1 with the tool touching or inside the object (distance ≤ 0), falling
/// linearly to 0 at the influence radius and beyond.
[[nodiscard]] double haptic_benefit(double tool_distance, double influence_radius);

/// Switching an object's haptic level by the force on it (seed 000 §4.1): a force above
/// `raise_force` shifts it one level finer at once; a force below `lower_force` held for
/// `hold_time` shifts it one coarser. The gap between the thresholds and the hold time are
/// the hysteresis, and no two switches come closer than `min_dwell` (which lets a blend
/// finish), so a force hovering at a threshold does not flicker between levels.
struct SwitchParams {
  double raise_force = 2.0;   ///< N
  double lower_force = 1.0;   ///< N, < raise_force
  double hold_time = 0.1;     ///< s below lower_force before a coarser level
  double min_dwell = 0.02;    ///< s from one switch to the next, ≥ the blend's duration
  std::size_t coarsest = 0;   ///< level indices, coarsest ≤ finest
  std::size_t finest = 0;
};

/// Throws InputError for thresholds out of order, negative or non-finite times or levels
/// out of order.
void check_switch_params(const SwitchParams& params);

struct LevelSwitch {
  std::size_t from = 0;
  std::size_t to = 0;
  double time = 0.0;
};

struct ForceThresholdSwitch {
  SwitchParams params;
  std::size_t level = 0;             ///< current level
  std::optional<double> below_since;  ///< when the force last went below lower_force
  std::optional<double> last_switch;  ///< time of the last switch

  /// Starts at `start_level` (clamped to the params' range); checks the params.
  ForceThresholdSwitch(const SwitchParams& switch_params, std::size_t start_level);

  /// One step at time t (non-decreasing from call to call) with the force magnitude on the
  /// object; the switch it makes, if any.
  std::optional<LevelSwitch> step(double t, double force);
};

enum class BlendShape { linear, smoothstep };

/// The force across a level switch: from the switch's time for `duration` seconds the
/// force is (1 − w) × the old level's + w × the new level's, w rising from 0 to 1, so the
/// force stays continuous while the levels' surfaces differ.
struct LevelBlend {
  double duration = 0.005;  ///< s
  BlendShape shape = BlendShape::linear;
  std::optional<LevelSwitch> current;  ///< the switch being blended, if any

  /// Starts blending a switch (a later switch restarts the blend from its own time).
  void start(const LevelSwitch& level_switch) { current = level_switch; }
  /// The new level's weight at time t: 0 before the switch, 1 after the blend (or with
  /// none started).
  [[nodiscard]] double weight(double t) const;
  /// Whether the old level's force is still needed at time t.
  [[nodiscard]] bool active(double t) const { return weight(t) < 1.0; }
  [[nodiscard]] Vec3 blend(double t, const Vec3& old_force, const Vec3& new_force) const;
};

}  // namespace tactus::lod
