#include "haptics/algorithms/needle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace tactus::haptics {
namespace {

/// Distance of p from the line through `point` along unit `axis`.
double off_line(const Vec3& p, const Vec3& point, const Vec3& axis) {
  const Vec3 rel = p - point;
  return (rel - rel.dot(axis) * axis).norm();
}

}  // namespace

NeedleInsertion::NeedleInsertion(NeedleConfig config) : config_(std::move(config)) {
  if (config_.layers.size() > kMaxNeedleLayers)
    throw std::invalid_argument("a needle renders at most " + std::to_string(kMaxNeedleLayers) + " layers");
  if (!(config_.length > 0.0)) throw std::invalid_argument("needle length must be > 0");
  if (!(config_.lateral_stiffness >= 0.0) || !(config_.stick_speed > 0.0) || !(config_.engage_slack >= 0.0) ||
      !(config_.new_site_distance >= 0.0))
    throw std::invalid_argument("needle lateral_stiffness, stick_speed, engage_slack and new_site_distance must be ≥ 0");
  for (const NeedleLayer& l : config_.layers)
    if (!(l.rupture_force > 0.0) || !(l.stiffness > 0.0) || !(l.viscous_friction >= 0.0) ||
        !(l.coulomb_friction >= 0.0))
      throw std::invalid_argument("needle layer: rupture_force and stiffness must be > 0, frictions ≥ 0");
  if (config_.planned) {
    const Vec3 span = (*config_.planned)[1] - (*config_.planned)[0];
    if (!(span.norm() > 0.0) || !span.allFinite())
      throw std::invalid_argument("needle planned path: entry and target must differ");
    planned_axis_ = span.normalized();
  }
}

void NeedleInsertion::engage(const Vec3& tip, const Vec3& axis, const NeedleSurfaces& surfaces) {
  // The layer the needle meets first is the one whose surface the tip is farthest past
  // (a deeper surface is reached later along the axis); a layer the tip has already left
  // through its far side is not in the way.
  int best = -1;
  double best_past = -1.0;
  for (std::size_t i = 0; i < config_.layers.size(); ++i) {
    if (layers_[i].stage != NeedleStage::untouched) continue;
    const NeedleLayerSurface& s = surfaces.layers[i];
    if (!s.entry_found) continue;
    const double past = axis.dot(tip - s.entry);
    if (past < 0.0) continue;
    if (s.exit_found && axis.dot(tip - s.exit) > 0.0) continue;
    if (past > best_past) {
      best_past = past;
      best = static_cast<int>(i);
    }
  }
  if (best < 0) return;
  const NeedleLayerSurface& s = surfaces.layers[static_cast<std::size_t>(best)];
  LayerState& layer = layers_[static_cast<std::size_t>(best)];
  layer.stage = NeedleStage::deforming;
  // Met late (the interaction result was stale, or a layer above tore with the tip already
  // past this surface): the spring starts near the tip, not with a force step.
  layer.anchor = s.entry + std::max(0.0, best_past - config_.engage_slack) * axis;
  layer.triangle = s.entry_triangle;
  layer.barycentric = s.entry_barycentric;
  deforming_ = best;
}

void NeedleInsertion::leave_site_if_moved(const Vec3& tip, const Vec3& axis) {
  if (!punctured_ || deforming_ >= 0) return;
  for (std::size_t i = 0; i < config_.layers.size(); ++i)
    if (layers_[i].stage == NeedleStage::ruptured && axis.dot(tip - layers_[i].anchor) > 0.0) return;
  if (off_line(tip, path_point_, path_axis_) <= config_.new_site_distance) return;
  layers_ = {};
  punctured_ = false;
}

NeedleOutput NeedleInsertion::update(const Vec3& tip, const Vec3& axis, const Vec3& velocity,
                                     const NeedleSurfaces& surfaces, double t) {
  NeedleOutput out;
  if (!tip.allFinite() || !axis.allFinite() || !velocity.allFinite()) return out;
  const double axial_speed = axis.dot(velocity);
  leave_site_if_moved(tip, axis);

  // Before rupture: one layer at a time resists the tip (the needle cannot reach a deeper
  // layer through one that has not torn).
  if (deforming_ < 0) engage(tip, axis, surfaces);
  touched_ = touched_ || deforming_ >= 0;
  if (deforming_ >= 0) {
    const auto i = static_cast<std::size_t>(deforming_);
    LayerState& layer = layers_[i];
    const NeedleLayer& params = config_.layers[i];
    const double depth = axis.dot(tip - layer.anchor);
    if (depth < 0.0) {
      layer.stage = NeedleStage::untouched;  // pulled back before it tore
      deforming_ = -1;
    } else {
      const double spring = params.stiffness * depth;
      if (spring >= params.rupture_force) {
        // Loss of resistance: the spring is gone from this frame on.
        layer.stage = NeedleStage::ruptured;
        deforming_ = -1;
        const NeedleRupture r{i, t, spring, layer.anchor};
        if (rupture_count_ < ruptures_.size()) ruptures_[rupture_count_++] = r;
        out.rupture = r;
        if (!punctured_) {
          punctured_ = true;
          path_point_ = layer.anchor;
          path_axis_ = axis;
        }
      } else {
        out.spring_force = spring;
        out.force -= spring * axis;
        out.touching = true;
        out.load_layer = deforming_;
        out.load_triangle = layer.triangle;
        out.load_barycentric = layer.barycentric;
        out.load_point = layer.anchor;
      }
    }
  }

  // After rupture: friction along the shaft, per layer, in proportion to the length inside.
  const double length = config_.length;
  const double coulomb_sign = axial_speed / std::max(std::abs(axial_speed), config_.stick_speed);
  double friction = 0.0;
  double deepest_entry = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < config_.layers.size(); ++i) {
    const LayerState& layer = layers_[i];
    if (layer.stage != NeedleStage::ruptured) continue;
    const NeedleLayerSurface& s = surfaces.layers[i];
    const double past_entry = axis.dot(tip - layer.anchor);
    if (past_entry <= 0.0) continue;  // retracted out of it: the hole no longer grips
    const double past_exit = s.exit_found ? axis.dot(tip - s.exit) : -1.0;
    const double inside = std::clamp(past_entry, 0.0, length) - std::clamp(past_exit, 0.0, length);
    if (!(inside > 0.0)) continue;
    const NeedleLayer& params = config_.layers[i];
    friction += inside * (params.viscous_friction * axial_speed + params.coulomb_friction * coulomb_sign);
    out.touching = true;
    // Without a deforming layer, the reaction goes to the layer the tip entered last.
    if (deforming_ < 0 && past_entry < deepest_entry) {
      deepest_entry = past_entry;
      out.load_layer = static_cast<int>(i);
      out.load_triangle = layer.triangle;
      out.load_barycentric = layer.barycentric;
      out.load_point = layer.anchor;
    }
  }
  out.axial_friction = -friction;
  out.force -= friction * axis;

  // Lateral correction towards the puncture path, stiffer the deeper the shaft is in.
  if (punctured_) {
    const Vec3 rel = tip - path_point_;
    const double along = rel.dot(path_axis_);
    const double inserted = std::clamp(along, 0.0, length);
    if (inserted > 0.0) {
      const Vec3 lateral = rel - along * path_axis_;
      out.lateral_force = -config_.lateral_stiffness * (inserted / length) * lateral;
      out.force += out.lateral_force;
      out.shaft = true;
      out.shaft_from = path_point_;
      out.lateral_deviation = config_.planned ? off_line(tip, (*config_.planned)[0], planned_axis_) : lateral.norm();
      last_deviation_ = out.lateral_deviation;
      max_deviation_ = std::max(max_deviation_, out.lateral_deviation);
    }
  }
  return out;
}

}  // namespace tactus::haptics
