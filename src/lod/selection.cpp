#include "lod/selection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"

namespace tactus::lod {
namespace {

bool non_negative(double x) { return std::isfinite(x) && x >= 0.0; }

void check_objects(std::span<const ObjectLevels> objects, double budget) {
  if (!(budget >= 0.0)) throw InputError("lod: the budget must be ≥ 0, got " + std::to_string(budget));
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const std::string which = "lod: object " + std::to_string(i);
    if (objects[i].levels.empty()) throw InputError(which + " has no levels");
    if (!non_negative(objects[i].benefit))
      throw InputError(which + ": benefit must be finite and ≥ 0, got " + std::to_string(objects[i].benefit));
    for (std::size_t l = 0; l < objects[i].levels.size(); ++l) {
      const LevelOption& o = objects[i].levels[l];
      if (!non_negative(o.cost) || !non_negative(o.error))
        throw InputError(which + " level " + std::to_string(l) + ": cost and error must be finite and ≥ 0");
    }
  }
}

}  // namespace

void check_levels(std::span<const ObjectLevels> objects, double budget) { check_objects(objects, budget); }

Selection evaluate_selection(std::span<const ObjectLevels> objects, std::span<const std::size_t> level,
                             double budget) {
  Selection s;
  s.level.assign(level.begin(), level.end());
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const LevelOption& o = objects[i].levels.at(level[i]);
    s.cost += o.cost;
    s.weighted_error += objects[i].benefit * o.error;
  }
  s.within_budget = s.cost <= budget;
  return s;
}

Selection select_levels(std::span<const ObjectLevels> objects, double budget) {
  check_objects(objects, budget);
  Selection s;
  select_levels_into(objects, budget, s);
  return s;
}

void select_levels_into(std::span<const ObjectLevels> objects, double budget, Selection& out) {
  std::vector<std::size_t>& level = out.level;
  level.resize(objects.size());  // no allocation once it has this size
  std::fill(level.begin(), level.end(), std::size_t{0});
  double cost = 0.0;
  for (const ObjectLevels& o : objects) cost += o.levels[0].cost;
  const bool fits = cost <= budget;
  while (fits) {
    // The best refinement that fits: highest ratio; ties to the lower object, then level
    // (strict comparisons in ascending order keep the first).
    double best_ratio = -1.0;
    std::size_t best_object = 0, best_level = 0;
    for (std::size_t i = 0; i < objects.size(); ++i) {
      const LevelOption& now = objects[i].levels[level[i]];
      for (std::size_t l = level[i] + 1; l < objects[i].levels.size(); ++l) {
        const LevelOption& there = objects[i].levels[l];
        const double gain = objects[i].benefit * (now.error - there.error);
        const double extra = there.cost - now.cost;
        if (!(gain > 0.0) || cost + extra > budget) continue;
        const double ratio = extra > 0.0 ? gain / extra : std::numeric_limits<double>::infinity();
        if (ratio > best_ratio) {
          best_ratio = ratio;
          best_object = i;
          best_level = l;
        }
      }
    }
    if (best_ratio < 0.0) break;
    cost += objects[best_object].levels[best_level].cost - objects[best_object].levels[level[best_object]].cost;
    level[best_object] = best_level;
  }
  out.cost = 0.0;
  out.weighted_error = 0.0;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    out.cost += objects[i].levels[level[i]].cost;
    out.weighted_error += objects[i].benefit * objects[i].levels[level[i]].error;
  }
  out.within_budget = fits;
}

double graphics_benefit(const Vec3& center, double radius, const Vec3& eye, double viewport_scale) {
  if (!(radius > 0.0)) return 0.0;
  const double distance = std::max((center - eye).norm(), radius);
  return viewport_scale * radius / distance;
}

double haptic_benefit(double tool_distance, double influence_radius) {
  if (tool_distance <= 0.0) return 1.0;
  if (!(influence_radius > 0.0)) return 0.0;
  return std::clamp(1.0 - tool_distance / influence_radius, 0.0, 1.0);
}

void check_switch_params(const SwitchParams& p) {
  if (!(std::isfinite(p.raise_force) && std::isfinite(p.lower_force) && p.lower_force >= 0.0 &&
        p.lower_force < p.raise_force))
    throw InputError("lod: the switch needs 0 ≤ lower_force < raise_force (the hysteresis), got " +
                     std::to_string(p.lower_force) + " and " + std::to_string(p.raise_force));
  if (!non_negative(p.hold_time) || !non_negative(p.min_dwell))
    throw InputError("lod: the switch's hold_time and min_dwell must be finite and ≥ 0");
  if (p.coarsest > p.finest) throw InputError("lod: the switch's coarsest level is above its finest");
}

ForceThresholdSwitch::ForceThresholdSwitch(const SwitchParams& switch_params, std::size_t start_level)
    : params(switch_params), level(start_level) {
  check_switch_params(params);
  level = std::clamp(level, params.coarsest, params.finest);
}

std::optional<LevelSwitch> ForceThresholdSwitch::step(double t, double force) {
  if (force < params.lower_force) {
    if (!below_since) below_since = t;
  } else {
    below_since.reset();
  }
  const bool dwelt = !last_switch || t - *last_switch >= params.min_dwell;
  if (!dwelt) return std::nullopt;
  std::optional<LevelSwitch> made;
  if (force > params.raise_force && level < params.finest) {
    made = LevelSwitch{level, level + 1, t};
  } else if (below_since && t - *below_since >= params.hold_time && level > params.coarsest) {
    made = LevelSwitch{level, level - 1, t};
    below_since = t;  // the next coarser step waits another hold time
  }
  if (made) {
    level = made->to;
    last_switch = t;
  }
  return made;
}

double LevelBlend::weight(double t) const {
  if (!current) return 1.0;
  if (t < current->time) return 0.0;
  if (!(duration > 0.0)) return 1.0;
  const double x = std::clamp((t - current->time) / duration, 0.0, 1.0);
  return shape == BlendShape::linear ? x : x * x * (3.0 - 2.0 * x);
}

Vec3 LevelBlend::blend(double t, const Vec3& old_force, const Vec3& new_force) const {
  const double w = weight(t);
  return (1.0 - w) * old_force + w * new_force;
}

}  // namespace tactus::lod
