#include "precompute/pair.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.hpp"
#include "precompute/probe.hpp"

namespace tactus::precompute {

SpaceSettings pair_point(const SpaceSettings& settings, int finger) {
  SpaceSettings s = settings;
  if (finger != s.finger) {
    std::swap(s.contact_node, s.pair.node);
    std::swap(s.patch_nodes, s.pair.patch_nodes);
    std::swap(s.bounds_min, s.pair.bounds_min);
    std::swap(s.bounds_max, s.pair.bounds_max);
    s.finger = finger;
  }
  s.held_node = -1;
  s.held_at.setZero();
  s.held_patch.clear();
  return s;
}

Grid pair_grid(const SpaceSettings& settings, int finger, const VecX& rest) {
  const SpaceSettings s = pair_point(settings, finger);
  return Grid::through(rest.segment<3>(3 * static_cast<Eigen::Index>(s.contact_node)), s.bounds_min, s.bounds_max,
                       s.spacing);
}

std::vector<SpaceSettings> space_levels(const SpaceSettings& settings, const VecX& rest) {
  std::vector<SpaceSettings> out;
  if (settings.probe.enabled()) {
    for (std::size_t k = 0; k < settings.probe.level_count(); ++k) out.push_back(level_settings(settings, k));
    return out;
  }
  if (!settings.pair.enabled()) return {settings};
  out = {pair_point(settings, 0), pair_point(settings, 1)};
  for (int finger = 0; finger < 2; ++finger) {
    const SpaceSettings own = pair_point(settings, finger);
    const Grid other = pair_grid(settings, 1 - finger, rest);
    for (std::size_t j = 0; j < other.size(); ++j) {
      SpaceSettings s = own;
      s.held_node = own.pair.node;
      s.held_patch = own.pair.patch_nodes;
      s.held_at = other.point(j);
      out.push_back(std::move(s));
    }
  }
  return out;
}

namespace {

bool same_grid(const Grid& a, const Grid& b) {
  return a.origin == b.origin && a.spacing == b.spacing && a.counts == b.counts;
}

}  // namespace

PairInterpolator::PairInterpolator(std::vector<std::shared_ptr<const Space>> levels, Interpolation method) {
  if (levels.size() < 2 || !levels[0]->settings.pair.enabled())
    throw InputError("a two-point space has the two points' own levels first, and these levels hold no second point");
  const std::array<const Space*, 2> own{levels[0].get(), levels[1].get()};
  const std::size_t expected = 2 + own[0]->grid.size() + own[1]->grid.size();
  if (levels.size() != expected)
    throw InputError(fmt::format("a two-point space of {} + {} grid points has {} levels; these are {}",
                                 own[0]->grid.size(), own[1]->grid.size(), expected, levels.size()));
  for (std::size_t k = 0; k < levels.size(); ++k) {
    const Space& s = *levels[k];
    // Level k's point, and the other's grid point it holds the other at (none for 0 and 1).
    const int finger = k < 2 ? static_cast<int>(k) : k < 2 + own[1]->grid.size() ? 0 : 1;
    const Space& mine = *own[static_cast<std::size_t>(finger)];
    const Space& theirs = *own[static_cast<std::size_t>(1 - finger)];
    const std::size_t held = k < 2 ? 0 : finger == 0 ? k - 2 : k - 2 - own[1]->grid.size();
    const char* differs = nullptr;
    if (s.settings.finger != finger || s.settings.contact_node != mine.settings.contact_node ||
        s.settings.pair.node != theirs.settings.contact_node)
      differs = "points";
    else if (!same_grid(s.grid, mine.grid))
      differs = "grid";
    else if (k < 2 ? s.settings.held_node >= 0
                   : s.settings.held_node != s.settings.pair.node ||
                         !(s.settings.held_at - theirs.grid.point(held)).isZero(1e-12))
      differs = "held point";
    if (differs)
      throw InputError(
          fmt::format("level {} of the two-point space does not belong to it (its {} differ)", k, differs));
  }
  levels_.reserve(levels.size());
  for (auto& level : levels) levels_.emplace_back(std::move(level), method);
}

bool PairInterpolator::in_box(int finger, const Vec3& p) const {
  const Grid& g = grid(finger);
  return (p.array() >= g.lower().array()).all() && (p.array() <= g.upper().array()).all();
}

PairInterpolator::Stencil PairInterpolator::stencil(int finger, const Vec3* other,
                                                    std::array<bool, 3> quadratic) const noexcept {
  Stencil out;
  if (!other || !other->allFinite() || !in_box(1 - finger, *other)) {
    out.level[0] = static_cast<std::size_t>(finger);
    out.weight[0] = 1.0;
    out.count = 1;
    return out;
  }
  const Grid& g = grid(1 - finger);
  const std::size_t base = finger == 0 ? 2 : 2 + grid(1).size();
  const Vec3 u = (*other - g.origin) / g.spacing;
  // Per axis the first level index and the weights: the 3 levels around the nearest interior
  // one (Lagrange), or the 2 of the cell (linear); a single level where the grid has one.
  std::array<int, 3> first{}, count{}, block{};  // block: the first level of the 3 × 3 × 3 block
  std::array<std::array<double, 3>, 3> w{};
  for (std::size_t a = 0; a < 3; ++a) {
    const double x = u[static_cast<Eigen::Index>(a)];
    const int n = g.counts[a];
    block[a] = n >= 3 ? std::clamp(static_cast<int>(std::lround(x)), 1, n - 2) - 1 : 0;
    if (n == 1) {
      first[a] = 0;
      count[a] = 1;
      w[a] = {1.0, 0.0, 0.0};
    } else if (quadratic[a] && n >= 3) {
      const int c = std::clamp(static_cast<int>(std::lround(x)), 1, n - 2);
      const double t = x - c;
      first[a] = c - 1;
      count[a] = 3;
      w[a] = {0.5 * t * (t - 1.0), 1.0 - t * t, 0.5 * t * (t + 1.0)};
    } else {
      const int c = std::clamp(static_cast<int>(std::floor(x)), 0, n - 2);
      const double t = std::clamp(x - c, 0.0, 1.0);
      first[a] = c;
      count[a] = 2;
      w[a] = {1.0 - t, t, 0.0};
    }
  }
  for (int k = 0; k < count[2]; ++k)
    for (int j = 0; j < count[1]; ++j)
      for (int i = 0; i < count[0]; ++i) {
        const double weight = w[0][static_cast<std::size_t>(i)] * w[1][static_cast<std::size_t>(j)] *
                              w[2][static_cast<std::size_t>(k)];
        if (weight == 0.0) continue;
        const auto e = static_cast<std::size_t>(out.count++);
        out.level[e] = base + g.index(first[0] + i, first[1] + j, first[2] + k);
        out.weight[e] = weight;
        out.slot[e] = (first[0] + i - block[0]) + 3 * (first[1] + j - block[1]) + 9 * (first[2] + k - block[2]);
      }
  return out;
}

template <class LevelQuery>
PairInterpolator::Combined PairInterpolator::combine(const Stencil& s, bool renormalize, LevelQuery query) const {
  Combined out;
  for (int i = 0; i < s.count; ++i) {
    const auto e = static_cast<std::size_t>(i);
    const Query q = query(s, e);
    out.query.outside = out.query.outside || q.outside;
    if (!q.valid) {
      out.query.across_levels = true;
      if (!renormalize) return {};
      continue;
    }
    out.query.fallback = out.query.fallback || q.fallback;
    out.query.force += s.weight[e] * q.force;
    out.kept += s.weight[e];
  }
  out.query.valid = renormalize ? out.kept > 0.0 : true;
  if (!out.query.valid) out.query.force.setZero();
  if (renormalize && out.query.valid) out.query.force /= out.kept;
  return out;
}

Query PairInterpolator::force(int finger, const Vec3& p, const Vec3* other) const noexcept {
  // Each level's query at p is made at most once: every stencil tried below draws on the same
  // 3 × 3 × 3 levels around the other point. The point's levels share its grid: p is located
  // and its cell's Hermite weights made once for all of them.
  const Interpolator::Located at = alone(finger).locate(p);
  std::array<Query, 27> asked;
  std::array<bool, 27> done{};
  auto level_force = [&](const Stencil& s, std::size_t e) {
    const auto slot = static_cast<std::size_t>(s.slot[e]);
    if (!done[slot]) {
      asked[slot] = levels_[s.level[e]].force(p, at);
      done[slot] = true;
    }
    return asked[slot];
  };
  const Combined quadratic = combine(stencil(finger, other, kQuadratic), false, level_force);
  if (quadratic.query.valid) return quadratic.query;
  // A level around the other point has no value at p. Before trilinear across levels: the
  // stencil linear along one axis (the two levels of the other point's cell there), then
  // along two, quadratic along the rest, where every level of it has a value.
  constexpr std::array<std::array<bool, 3>, 6> kLowered{
      {{false, true, true}, {true, false, true}, {true, true, false}, {false, false, true}, {false, true, false},
       {true, false, false}}};
  for (const auto& orders : kLowered) {
    Combined lowered = combine(stencil(finger, other, orders), false, level_force);
    if (!lowered.query.valid) continue;
    lowered.query.levels_lowered = true;
    return lowered.query;
  }
  Query q = combine(stencil(finger, other, kLinear), true, level_force).query;
  q.across_levels = true;
  return q;
}

Query PairInterpolator::shape(int finger, const Vec3& p, const Vec3* other, VecX& displacement) const {
  const auto dofs = levels_.front().space().displacement.rows();
  if (displacement.size() != dofs) displacement.resize(dofs);
  auto level_shape = [&](const Stencil& s, std::size_t e) {
    const Query q = levels_[s.level[e]].shape(p, scratch_);
    if (q.valid) displacement += s.weight[e] * scratch_;
    return q;
  };
  // Trilinear across levels: 8 levels' shapes, not 27 (the shape is drawn, not felt; 27
  // Hermite shapes of the organ took 1.5 ms a simulation step and crowded the haptic loops).
  displacement.setZero();
  const Combined c = combine(stencil(finger, other, kLinear), true, level_shape);
  if (!c.query.valid) {
    displacement.setZero();
    return c.query;
  }
  displacement /= c.kept;
  return c.query;
}

}  // namespace tactus::precompute
