#include "precompute/probe.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace tactus::precompute {

ProbeFrame::ProbeFrame(const Vec3& a) {
  if (!(a.norm() > 0.0) || !a.allFinite()) throw InputError("a probe's axis must be a non-zero direction");
  axis = a.normalized();
  Eigen::Index least = 0;
  axis.cwiseAbs().minCoeff(&least);
  const Vec3 ref = Vec3::Unit(least);
  e1 = (ref - ref.dot(axis) * axis).normalized();
  e2 = axis.cross(e1);
}

Vec3 ProbeFrame::rotation(const Vec2& t) const {
  // Turning the axis towards u = t1·e1 + t2·e2 is a turn about axis × u = t1·e2 − t2·e1.
  return t.x() * e2 - t.y() * e1;
}

Vec3 ProbeFrame::direction(const Vec2& t) const {
  const double angle = t.norm();
  if (angle == 0.0) return axis;
  return std::cos(angle) * axis + std::sin(angle) * (t.x() * e1 + t.y() * e2) / angle;
}

Vec2 ProbeFrame::tilt(const Vec3& d) const {
  if (!d.allFinite()) return Vec2::Zero();
  const Vec2 tangent(d.dot(e1), d.dot(e2));
  const double sine = tangent.norm();
  if (!(sine > 0.0)) return Vec2::Zero();
  return std::atan2(sine, d.dot(axis)) * tangent / sine;
}

Vec2 level_tilt(const ProbeSettings& probe, std::size_t level) {
  if (!probe.enabled()) return Vec2::Zero();
  const auto n = static_cast<std::size_t>(probe.tilt_levels);
  const double step = 2.0 * probe.max_tilt / static_cast<double>(n - 1);
  return {-probe.max_tilt + step * static_cast<double>(level % n),
          -probe.max_tilt + step * static_cast<double>(level / n)};
}

SpaceSettings level_settings(const SpaceSettings& settings, std::size_t level) {
  SpaceSettings s = settings;
  s.tilt = level_tilt(settings.probe, level);
  return s;
}

Vec3 probe_rotation(const SpaceSettings& settings) {
  if (!settings.probe.enabled()) return Vec3::Zero();
  return ProbeFrame(settings.probe.axis).rotation(settings.tilt);
}

ProbeInterpolator::ProbeInterpolator(std::vector<std::shared_ptr<const Space>> levels, Interpolation method)
    : probe_(levels.empty() ? ProbeSettings{} : levels.front()->settings.probe),
      frame_(probe_.enabled() ? probe_.axis : Vec3::UnitZ()) {
  if (!probe_.enabled() || probe_.tilt_levels % 2 == 0 || !(probe_.max_tilt > 0.0))
    throw InputError("a probe space needs an odd number (3 or more) of leans per axis and a positive largest lean");
  if (levels.size() != probe_.level_count())
    throw InputError(fmt::format("a probe space of {} leans per axis has {} levels, not {}", probe_.tilt_levels,
                                 probe_.level_count(), levels.size()));
  const Grid& grid = levels.front()->grid;
  for (std::size_t k = 0; k < levels.size(); ++k) {
    const Space& s = *levels[k];
    const bool same_probe = s.settings.probe.tilt_levels == probe_.tilt_levels &&
                            s.settings.probe.max_tilt == probe_.max_tilt && s.settings.probe.axis == probe_.axis;
    const bool same_grid = s.grid.origin == grid.origin && s.grid.spacing == grid.spacing && s.grid.counts == grid.counts;
    if (!same_probe || !same_grid || !(s.settings.tilt - level_tilt(probe_, k)).isZero(1e-12))
      throw InputError(fmt::format("level {} of the probe space does not belong to it (its {} differs)", k,
                                   !same_probe ? "probe" : !same_grid ? "grid" : "lean"));
  }
  levels_.reserve(levels.size());
  for (auto& level : levels) levels_.emplace_back(std::move(level), method);
}

ProbeInterpolator::Stencil ProbeInterpolator::stencil(const Vec3& direction) const noexcept {
  Stencil out;
  const Vec2 t = frame_.tilt(direction);
  const int n = probe_.tilt_levels;
  const double step = 2.0 * probe_.max_tilt / (n - 1);
  std::array<int, 2> centre{};
  std::array<std::array<double, 3>, 2> w{};
  for (int axis = 0; axis < 2; ++axis) {
    const double u = std::clamp(t[axis], -probe_.max_tilt, probe_.max_tilt);
    // The 3 levels around the lean: the nearest interior level and its two neighbours.
    const double x = (u + probe_.max_tilt) / step;
    const int c = std::clamp(static_cast<int>(std::lround(x)), 1, n - 2);
    const double s = x - c;
    centre[static_cast<std::size_t>(axis)] = c;
    w[static_cast<std::size_t>(axis)] = {0.5 * s * (s - 1.0), 1.0 - s * s, 0.5 * s * (s + 1.0)};
  }
  for (int b = 0; b < 3; ++b)
    for (int a = 0; a < 3; ++a) {
      const auto i = static_cast<std::size_t>(3 * b + a);
      out.level[i] = static_cast<std::size_t>((centre[1] + b - 1) * n + centre[0] + a - 1);
      out.weight[i] = w[0][static_cast<std::size_t>(a)] * w[1][static_cast<std::size_t>(b)];
    }
  return out;
}

Query ProbeInterpolator::force(const Vec3& p, const Vec3& direction) const noexcept {
  return between_leans<false>(p, direction);
}

Query ProbeInterpolator::force_and_torque(const Vec3& p, const Vec3& direction) const noexcept {
  return between_leans<true>(p, direction);
}

template <bool Torque>
Query ProbeInterpolator::between_leans(const Vec3& p, const Vec3& direction) const noexcept {
  const Stencil s = stencil(direction);
  // Every lean shares the grid: p is located and its cell's Hermite weights made once.
  const Interpolator::Located at = levels_.front().locate(p);
  Query out;
  out.valid = true;
  for (std::size_t i = 0; i < s.level.size(); ++i) {
    const Query q = Torque ? levels_[s.level[i]].force_and_torque(p, at) : levels_[s.level[i]].force(p, at);
    out.valid = out.valid && q.valid;
    out.outside = out.outside || q.outside;
    out.fallback = out.fallback || q.fallback;
    out.force += s.weight[i] * q.force;
    if constexpr (Torque) out.torque += s.weight[i] * q.torque;
  }
  if (!out.valid) {
    out.force.setZero();
    out.torque.setZero();
  }
  return out;
}

Query ProbeInterpolator::shape(const Vec3& p, const Vec3& direction, VecX& displacement) const {
  const Stencil s = stencil(direction);
  Query out;
  out.valid = true;
  const auto dofs = levels_.front().space().displacement.rows();
  if (displacement.size() != dofs) displacement.resize(dofs);
  displacement.setZero();
  for (std::size_t i = 0; i < s.level.size(); ++i) {
    const Query q = levels_[s.level[i]].shape(p, scratch_);
    out.valid = out.valid && q.valid;
    out.outside = out.outside || q.outside;
    out.fallback = out.fallback || q.fallback;
    out.force += s.weight[i] * q.force;
    displacement += s.weight[i] * scratch_;
  }
  if (!out.valid) {
    out.force.setZero();
    displacement.setZero();
  }
  return out;
}

}  // namespace tactus::precompute
