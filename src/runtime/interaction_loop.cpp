#include "runtime/interaction_loop.hpp"

#include <limits>

#include "contact/closest_point.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "mesh/half_edge.hpp"

namespace tactus::runtime {

InteractionLoop::InteractionLoop(const scene::Model& model, std::vector<InteractionTarget> targets,
                                 TripleBuffer<SurfaceSnapshot>& surfaces)
    : model_(model), targets_(std::move(targets)), surfaces_(surfaces) {
  stats_.name = "interaction";
  stats_.rate = model.rates.interaction;
  for (const InteractionTarget& target : targets_) {
    parts_.push_back({target.device + ": query per body", {}});
    parts_.push_back({target.device + ": interaction", {}});
  }
  parts_.push_back({"refit trees", {}});
  trees_.resize(model.bodies.size());
  for (const InteractionTarget& target : targets_) {
    auto& per_body = curvature_.emplace_back(model.bodies.size());
    if (target.curvature_rings <= 0) continue;
    for (std::size_t b : target.bodies) {
      try {
        const mesh::HalfEdgeMesh topology(model.bodies[b].surface);
        per_body[b] = std::make_unique<mesh::CurvatureEstimator>(topology, target.curvature_rings);
      } catch (const InputError& e) {
        log::warn("body '{}': no curvature estimate on its surface ({}); contact treats it as flat",
                  model.bodies[b].name, e.reason());
      }
    }
  }
}

void InteractionLoop::publish_needle_crossings(std::size_t k, const InteractionTarget& target, const ToolState& tool) {
  haptics::NeedleSurfaces& out = target.channels->needle.write_buffer();
  out = haptics::NeedleSurfaces{};
  const double axis_norm = tool.axis.norm();
  if (tool.valid && axis_norm > 0.0 && tool.position.allFinite() && tool.axis.allFinite()) {
    const Vec3 axis = tool.axis / axis_norm;
    // From behind the hub to a reach ahead of the tip: every surface the shaft is in or
    // is about to meet.
    const Vec3 from = tool.position - (target.needle_length + target.reach) * axis;
    const Vec3 to = tool.position + target.reach * axis;
    for (std::size_t i = 0; i < target.bodies.size() && i < haptics::kMaxNeedleLayers; ++i) {
      const std::size_t b = target.bodies[i];
      const Nanos q0 = now_ns();
      trees_[b].segment(from, to, hits_);
      parts_[2 * k].time.record(now_ns() - q0);
      haptics::NeedleLayerSurface& layer = out.layers[i];
      for (const contact::RayHit& h : hits_) {
        if (!layer.entry_found) {
          if (!h.entering) continue;  // leaving a body the ray started in
          layer.entry_found = true;
          layer.entry = h.point;
          layer.entry_triangle = h.triangle;
          layer.entry_barycentric = h.barycentric;
          layer.entry_normal = h.normal;
        } else if (!h.entering) {
          layer.exit_found = true;
          layer.exit = h.point;
          break;
        }
      }
    }
  }
  target.channels->needle.publish();
}

void InteractionLoop::step(double /*t*/, Nanos deadline, Nanos start, bool real_time) {
  surfaces_.update();
  const SurfaceSnapshot& surfaces = surfaces_.read();
  if (surfaces.step != tree_step_) {
    const Nanos r0 = now_ns();
    for (std::size_t b = 0; b < trees_.size(); ++b) {
      if (trees_[b].empty() || trees_[b].needs_rebuild())
        trees_[b].build(surfaces.positions[b], model_.bodies[b].surface.triangles);
      else
        trees_[b].refit(surfaces.positions[b]);
    }
    tree_step_ = surfaces.step;
    parts_.back().time.record(now_ns() - r0);
  }
  for (std::size_t k = 0; k < targets_.size(); ++k) {
    InteractionTarget& target = targets_[k];
    const Nanos handling0 = now_ns();
    target.channels->tool.update();
    const ToolState& tool = target.channels->tool.read();
    LocalContact& out = target.channels->contact.write_buffer();
    out = LocalContact{};
    out.surface_time = surfaces.t;
    if (target.needle_length > 0.0) {
      publish_needle_crossings(k, target, tool);
    } else if (tool.valid) {
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t b : target.bodies) {
        const Nanos q0 = now_ns();
        const contact::SurfacePoint p = trees_[b].closest_point(tool.position);
        parts_[2 * k].time.record(now_ns() - q0);
        if (p.triangle < 0 || p.distance >= best) continue;
        best = p.distance;
        // Outside the tissue the plane faces the tool (smooth over edges and corners);
        // inside, the face normal says which way is out.
        const Vec3 to_tool = tool.position - p.point;
        const bool outside = to_tool.dot(p.normal) > 0.0 && p.distance > 1e-12;
        out.valid = p.distance <= target.reach || !outside;
        out.body = static_cast<std::int32_t>(b);
        out.triangle = p.triangle;
        out.point = p.point;
        out.normal = outside ? Vec3(to_tool / p.distance) : p.normal;
        out.barycentric = p.barycentric;
        out.mean_curvature = 0.0;
        if (const auto& estimator = curvature_[k][b]) {
          const mesh::VertexCurvature c = estimator->estimate_at_point(surfaces.positions[b], p.triangle, p.barycentric);
          if (c.valid) out.mean_curvature = c.kmean;
        }
      }
    }
    target.channels->contact.publish();
    parts_[2 * k + 1].time.record(now_ns() - handling0);
  }
  stats_.record(deadline, start, now_ns() - start, real_time);
}

}  // namespace tactus::runtime
