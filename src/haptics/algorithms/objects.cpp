#include "haptics/algorithms/objects.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace tactus::haptics {

namespace {

constexpr double kCostWindow = 0.1;  ///< [s] between reports of the budget used

double box_distance(const Aabb& box, const Vec3& p) {
  const Vec3 d = (box.min - p).cwiseMax(p - box.max).cwiseMax(0.0);
  return d.norm();
}

/// Whether the segment from → to, grown by radius, can reach the box (by their boxes).
bool may_reach(const Aabb& box, const Vec3& from, const Vec3& to, double radius) {
  const Vec3 lo = from.cwiseMin(to).array() - radius, hi = from.cwiseMax(to).array() + radius;
  return (lo.array() <= box.max.array()).all() && (hi.array() >= box.min.array()).all();
}

std::int32_t encode(std::size_t object, std::int32_t triangle) {
  return triangle < 0 ? -1 : static_cast<std::int32_t>(object) * ObjectsQuery::kObjectStride + triangle;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// The union of the objects

void ObjectsQuery::resize(std::size_t objects) {
  trees_.assign(objects, nullptr);
  boxes_.assign(objects, Aabb{});
}

void ObjectsQuery::set(std::size_t object, const contact::TriangleBvh* tree, const Aabb& box) {
  trees_[object] = tree;
  boxes_[object] = box;
}

void ObjectsQuery::set_plane(bool valid, const Vec3& normal, double offset) {
  plane_ = valid;
  normal_ = normal;
  offset_ = offset;
}

contact::ClosestSurfacePoint ObjectsQuery::closest_point(const Vec3& p) const {
  contact::ClosestSurfacePoint best;
  last_member_ = -1;
  if (!p.allFinite()) return best;
  double best_distance = kInf;
  if (plane_) {
    best = contact::HalfSpaceQuery(normal_, offset_).closest_point(p);
    best_distance = best.distance;
    last_member_ = static_cast<int>(trees_.size());
  }
  for (std::size_t i = 0; i < trees_.size(); ++i) {
    if (!trees_[i] || box_distance(boxes_[i], p) >= best_distance) continue;
    contact::ClosestSurfacePoint c = trees_[i]->closest_point_with_side(p);
    if (!c.found || c.distance >= best_distance) continue;
    // Outside the object's box is outside the object, whatever the side test says there (a
    // coarse level's folds can turn a far point's pseudo-normal around).
    if (c.behind && !boxes_[i].contains(p)) c.behind = false;
    c.triangle = encode(i, c.triangle);
    best = c;
    best_distance = c.distance;
    last_member_ = static_cast<int>(i);
  }
  return best;
}

contact::SweepHit ObjectsQuery::sweep_sphere(const Vec3& from, const Vec3& to, double radius) const {
  contact::SweepHit best;
  if (!from.allFinite() || !to.allFinite() || !(radius >= 0.0)) return best;
  if (plane_) best = contact::HalfSpaceQuery(normal_, offset_).sweep_sphere(from, to, radius);
  for (std::size_t i = 0; i < trees_.size(); ++i) {
    if (!trees_[i] || !may_reach(boxes_[i], from, to, radius)) continue;
    contact::SweepHit h = trees_[i]->sweep_sphere(from, to, radius);
    if (!h.hit || (best.hit && h.time >= best.time)) continue;
    h.triangle = encode(i, h.triangle);
    best = h;
  }
  return best;
}

std::optional<std::array<Vec3, 3>> ObjectsQuery::triangle(std::int32_t t) const {
  if (t < 0) return std::nullopt;
  const auto object = static_cast<std::size_t>(t / kObjectStride);
  if (object >= trees_.size() || !trees_[object]) return std::nullopt;
  return trees_[object]->triangle_corners(t % kObjectStride);
}

// ---------------------------------------------------------------------------------------
// The algorithm

// ---------------------------------------------------------------------------------------
// The levels

double LevelChooser::level_cost(const lod::ImpostorLevel& level) {
  return kQueriesPerFrame * kSecondsPerTreeLevel * level.bvh.depth();
}

LevelChooser::LevelChooser(std::vector<TouchableObject> objects, const ObjectsSettings& settings, double reach)
    : objects_(std::move(objects)), settings_(settings) {
  for (const TouchableObject& o : objects_) {
    if (!o.levels || o.levels->levels.empty()) throw InputError("a touchable object needs at least one level");
    lod::SwitchParams sp{o.raise_force, o.lower_force, o.hold_time, 2.0 * settings_.blend_time, 0,
                         o.levels->levels.size() - 1};
    lod::check_switch_params(sp);
    Aabb box;
    for (const auto& l : o.levels->levels) {
      box.add(l.mesh.bounds().min);
      box.add(l.mesh.bounds().max);
    }
    box.min.array() -= reach;
    box.max.array() += reach;
    boxes_.push_back(box);
  }
}

LevelChooser::State LevelChooser::make_state() const {
  State s;
  s.query.resize(objects_.size());
  s.options.resize(objects_.size());
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    for (const auto& l : objects_[i].levels->levels) {
      s.options[i].levels.push_back({level_cost(l), l.error.hausdorff});
      s.base_cost.push_back(level_cost(l));
    }
    const lod::SwitchParams sp{objects_[i].raise_force, objects_[i].lower_force, objects_[i].hold_time,
                               2.0 * settings_.blend_time, 0, objects_[i].levels->levels.size() - 1};
    s.switches.emplace_back(sp, 0);
  }
  lod::check_levels(s.options, settings_.budget);
  s.selection.level.resize(objects_.size());
  s.level.assign(objects_.size(), 0);
  s.blend.duration = settings_.blend_time;
  return s;
}

void LevelChooser::choose(double t, const Vec3& a, const Vec3& b, const LocalContact& plane, State& s) const {
  const std::size_t n = objects_.size();
  // 1. Each object's benefit: its nearness to the tool. One beyond the influence radius is
  // never queried, so it costs nothing.
  std::size_t flat = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double distance = std::min(box_distance(boxes_[i], a), box_distance(boxes_[i], b));
    const double benefit = lod::haptic_benefit(distance, settings_.influence_radius);
    s.options[i].benefit = benefit;
    for (auto& option : s.options[i].levels) option.cost = benefit > 0.0 ? s.base_cost[flat] : 0.0, ++flat;
  }

  // 2. The touched object follows the force (seed 000 §4.1) from the level it was touched at,
  // and goes first: it may take the budget the others leave at their coarsest. It keeps its
  // switch for a hold time after the contact ends, then returns to the nearness choice.
  if (s.touched >= 0 && s.touched < static_cast<int>(n)) {
    const auto i = static_cast<std::size_t>(s.touched);
    if (s.switch_object != s.touched) {  // a new contact starts at the level it found
      s.switches[i].level = s.level[i];
      s.switches[i].below_since.reset();
      s.switches[i].last_switch.reset();
      s.switch_object = s.touched;
    }
    s.switches[i].step(t, s.force);
    s.last_touch = t;
  } else if (s.switch_object >= 0 && t - s.last_touch > objects_[s.switch_object].hold_time) {
    s.switch_object = -1;
  }
  double budget = settings_.budget;
  std::size_t held_level = 0;
  if (settings_.select && s.switch_object >= 0) {
    const auto held = static_cast<std::size_t>(s.switch_object);
    double others = 0.0;
    for (std::size_t j = 0; j < n; ++j)
      if (j != held) others += s.options[j].levels[0].cost;
    held_level = 0;
    for (std::size_t l = 1; l <= s.switches[held].level && l < s.options[held].levels.size(); ++l)
      if (others + s.options[held].levels[l].cost <= budget) held_level = l;
    // Under the finger the level only goes finer: a coarser level's surface lies elsewhere (a
    // decimated bunny's 0.3 mm away), and switching to it there was felt as a jump (2 N under
    // a Hertz finger) and then switched back by the force. It goes coarser once let go.
    if (s.touched == s.switch_object && s.level[held] > held_level &&
        others + s.options[held].levels[s.level[held]].cost <= budget)
      held_level = s.level[held];
    budget -= s.options[held].levels[held_level].cost - s.options[held].levels[0].cost;
    s.options[held].benefit = 0.0;  // held at its coarsest in the selection, then set below
  }

  // 3. The others by benefit per cost within what is left (seed 000 §4.2).
  lod::select_levels_into(s.options, std::max(budget, 0.0), s.selection);
  if (settings_.select && s.switch_object >= 0) s.selection.level[static_cast<std::size_t>(s.switch_object)] = held_level;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t want = settings_.select ? s.selection.level[i] : s.options[i].levels.size() - 1;
    if (want == s.level[i]) continue;
    if (static_cast<int>(i) == s.touched) {
      s.blend.start({s.level[i], want, t});
      s.blend_object = static_cast<int>(i);
      s.blend_from = s.level[i];
    }
    if (s.pending_count < static_cast<int>(s.pending.size()))
      s.pending[s.pending_count++] = {HapticEvent::Kind::level_switch, static_cast<double>(want), objects_[i].body};
    s.level[i] = want;
  }
  s.cost = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    s.query.set(i, &objects_[i].levels->levels[s.level[i]].bvh, boxes_[i]);
    s.cost += s.options[i].levels[s.level[i]].cost;
  }
  // The budget used, reported as the largest cost of each 100 ms window with anything near.
  s.window_cost = std::max(s.window_cost, s.cost);
  if (t >= s.window_end) {
    if (s.window_cost > 0.0 && s.pending_count < static_cast<int>(s.pending.size()))
      s.pending[s.pending_count++] = {HapticEvent::Kind::level_cost, s.window_cost, -1};
    s.window_cost = 0.0;
    s.window_end = t + kCostWindow;
  }
  s.query.set_plane(settings_.plane && plane.valid, plane.normal, plane.normal.dot(plane.point));
}

bool LevelChooser::blending(double t, const State& s) const {
  return s.blend_object >= 0 && s.blend.active(t);
}

void LevelChooser::old_level(State& s, bool old) const {
  const auto object = static_cast<std::size_t>(s.blend_object);
  const std::size_t level = old ? s.blend_from : s.level[object];
  s.query.set(object, &objects_[object].levels->levels[level].bvh, boxes_[object]);
}

void LevelChooser::finish(double t, int touched, double force, State& s, Rendering& out) const {
  s.touched = touched;
  s.force = force;
  if (!blending(t, s)) s.blend_object = -1;
  if (s.pending_count > 0) {
    out.has_event = true;
    out.event = s.pending[0];
    std::copy(s.pending.begin() + 1, s.pending.begin() + s.pending_count, s.pending.begin());
    --s.pending_count;
  }
}

}  // namespace tactus::haptics
