#include "haptics/algorithms/multi_surface.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tactus::haptics {

MultiSurfaceForce::MultiSurfaceForce(MultiSurfaceConfig config) : config_(config) {
  if (!(config_.stiffness > 0.0) || !std::isfinite(config_.stiffness))
    throw std::invalid_argument("multi_surface stiffness must be > 0");
  if (!(config_.damping >= 0.0) || !std::isfinite(config_.damping))
    throw std::invalid_argument("multi_surface damping must be ≥ 0");
  if (config_.layers < 1 || config_.layers > kMaxSurfaceLayers)
    throw std::invalid_argument("multi_surface takes 1 to " + std::to_string(kMaxSurfaceLayers) + " layers");
  if (!(config_.blend_time >= 0.0) || !std::isfinite(config_.blend_time))
    throw std::invalid_argument("multi_surface blend_time must be ≥ 0");
  if (!(config_.radius >= 0.0) || !std::isfinite(config_.radius) || !(config_.max_depth > 0.0) ||
      !(config_.behind_tolerance >= 0.0))
    throw std::invalid_argument("multi_surface radius and behind_tolerance must be ≥ 0, max_depth > 0");
  if (!(config_.static_friction >= 0.0) || !(config_.kinetic_friction >= 0.0) ||
      config_.kinetic_friction > config_.static_friction || !std::isfinite(config_.static_friction))
    throw std::invalid_argument("multi_surface friction: need 0 ≤ kinetic_friction ≤ static_friction");
  enabled_.fill(true);
}

MultiSurfaceForce::Plane MultiSurfaceForce::shown(const LayerPlanes& l, double t) const {
  if (!(config_.blend_time > 0.0)) return l.to;
  const double s = std::clamp((t - l.start) / config_.blend_time, 0.0, 1.0);
  if (s >= 1.0) return l.to;
  // The plane whose signed distance is the blend of the two: it turns about the line where
  // they meet, or translates when they are parallel.
  const Vec3 n = (1.0 - s) * l.from.normal + s * l.to.normal;
  const double norm = n.norm();
  if (!(norm > 1e-6)) return l.to;  // opposite normals: no plane between them
  return {n / norm, ((1.0 - s) * l.from.offset + s * l.to.offset) / norm};
}

void MultiSurfaceForce::set_hits(const SurfaceLayerHits& hits, double t) {
  for (std::size_t i = 0; i < config_.layers; ++i) {
    const SurfaceLayerHit& h = hits.layers[i];
    LayerPlanes& l = planes_[i];
    const double n = h.normal.norm();
    if (!h.found || !(n > 0.5) || !h.point.allFinite() || !h.normal.allFinite()) {
      l.valid = false;
      continue;
    }
    const Plane target{h.normal / n, h.normal.dot(h.point) / n + config_.radius};
    if (started_ && target.normal.dot(proxy_) - target.offset < -config_.behind_tolerance) {
      l.valid = false;  // the proxy is not outside this surface
      continue;
    }
    // A layer seen again blends from what is shown now; one seen anew appears at once.
    l.from = l.valid ? shown(l, t) : target;
    l.to = target;
    l.start = t;
    l.valid = true;
    l.hit = h;
  }
}

void MultiSurfaceForce::set_layer_enabled(std::size_t layer, bool enabled) {
  if (layer < kMaxSurfaceLayers) enabled_[layer] = enabled;
}

MultiSurfaceOutput MultiSurfaceForce::evaluate(const Vec3& goal, const Vec3& goal_velocity, double t) const {
  MultiSurfaceOutput out;
  out.proxy = goal;
  if (!goal.allFinite()) {
    out.proxy = proxy_;
    return out;
  }
  for (std::size_t i = 0; i < config_.layers; ++i) {
    const LayerPlanes& l = planes_[i];
    if (!l.valid || !enabled_[i]) continue;
    // The outermost plane the ray hit holds the proxy; deeper ones wait behind it.
    const Plane p = shown(l, t);
    const double depth = -(p.normal.dot(goal) - p.offset);
    if (depth > 0.0 && depth <= config_.max_depth) {
      out.touching = true;
      out.layer = static_cast<int>(i);
      out.depth = depth;
      const Vec3 on_plane = goal + depth * p.normal;
      out.proxy = on_plane;
      const double normal_speed = goal_velocity.allFinite() ? p.normal.dot(goal_velocity) : 0.0;
      out.force = std::max(0.0, config_.stiffness * depth - config_.damping * normal_speed) * p.normal;
      if (config_.static_friction > 0.0 && anchored_ && anchor_layer_ == static_cast<int>(i)) {
        // The anchor, carried onto the plane as shown now (it moves with the tissue's planes).
        const Vec3 anchor = proxy_ - (p.normal.dot(proxy_) - p.offset) * p.normal;
        const Vec3 pull = anchor - on_plane;
        const double normal_force = config_.stiffness * depth;
        const double pull_length = pull.norm();
        if (config_.stiffness * pull_length <= config_.static_friction * normal_force) {
          out.proxy = anchor;
          out.sticking = true;
        } else {
          out.proxy = on_plane + (config_.kinetic_friction * depth) * (pull / pull_length);
        }
        out.force += config_.stiffness * (out.proxy - on_plane);
      }
      out.triangle = l.hit.triangle;
      out.barycentric = l.hit.barycentric;
    }
    break;
  }
  return out;
}

MultiSurfaceOutput MultiSurfaceForce::update(const Vec3& goal, const Vec3& goal_velocity, double t) {
  const MultiSurfaceOutput out = evaluate(goal, goal_velocity, t);
  if (!goal.allFinite()) return out;
  // The next ray: from the proxy along the plane's inward normal while pressing (towards the
  // sphere's contact point, whatever friction holds the proxy off the device's line: a ray
  // tilted by the friction's pull would find another facet, whose tilted plane moves the
  // pull, and the ray, back the next time), else along the tool's motion, so the surfaces
  // ahead are found before contact.
  const Vec3 pressing = goal - out.proxy;
  const double speed = goal_velocity.allFinite() ? goal_velocity.norm() : 0.0;
  if (out.touching) {
    direction_ = -shown(planes_[static_cast<std::size_t>(out.layer)], t).normal;
  } else if (pressing.norm() > 1e-9) {
    direction_ = pressing.normalized();
  } else if (speed > 1e-3) {
    direction_ = goal_velocity / speed;
  }
  proxy_ = out.proxy;
  started_ = true;
  anchored_ = out.touching;
  anchor_layer_ = out.layer;
  return out;
}

}  // namespace tactus::haptics
