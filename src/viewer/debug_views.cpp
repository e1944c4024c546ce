#include "viewer/debug_views.hpp"

#include <algorithm>
#include <limits>

namespace tactus::viewer {

Vec3 surface_normal_near(const FrameView& frame, const Vec3& point) {
  const SurfaceView* best_surface = nullptr;
  std::size_t best_vertex = 0;
  double best = std::numeric_limits<double>::infinity();
  for (const SurfaceView& s : frame.surfaces)
    for (std::size_t v = 0; v < s.positions.size(); ++v)
      if (const double d2 = (s.positions[v] - point).squaredNorm(); d2 < best) {
        best = d2;
        best_surface = &s;
        best_vertex = v;
      }
  if (!best_surface) return Vec3::Zero();
  Vec3 n = Vec3::Zero();
  const auto& p = best_surface->positions;
  for (const mesh::Triangle& t : best_surface->triangles) {
    if (static_cast<std::size_t>(t[0]) != best_vertex && static_cast<std::size_t>(t[1]) != best_vertex &&
        static_cast<std::size_t>(t[2]) != best_vertex)
      continue;
    const Vec3& a = p[static_cast<std::size_t>(t[0])];
    n += (p[static_cast<std::size_t>(t[1])] - a).cross(p[static_cast<std::size_t>(t[2])] - a);  // area-weighted
  }
  const double length = n.norm();
  return length > 0.0 ? Vec3(n / length) : Vec3::Zero();
}

void DebugViews::add(const std::vector<ToolView>& tools, const ViewOptions& view, FrameView& frame) {
  if (view.show_planes)
    for (const ToolView& t : tools) {
      if (!t.seen || !t.touching) continue;
      const Vec3 n = surface_normal_near(frame, t.contact_point);
      if (n.isZero()) continue;
      frame.quads.push_back({t.contact_point, n, 2.0 * std::max(t.radius, 1e-3), Colour(0.3, 0.9, 0.5), 0.4});
    }
  if (view.show_bvh) {
    if (trees_.empty()) {
      trees_.resize(model_.bodies.size());
      for (std::size_t b = 0; b < model_.bodies.size(); ++b)
        if (!model_.bodies[b].surface.triangles.empty())
          trees_[b].build(model_.bodies[b].surface.vertices, model_.bodies[b].surface.triangles);
    }
    static const Colour level_colour(0.85, 0.45, 0.9);
    for (std::size_t b = 0; b < trees_.size() && b < frame.surfaces.size(); ++b) {
      if (trees_[b].empty() || frame.surfaces[b].positions.size() != model_.bodies[b].surface.vertices.size()) continue;
      trees_[b].refit(frame.surfaces[b].positions);
      boxes_.clear();
      trees_[b].node_boxes(view.bvh_levels, boxes_);
      for (const auto& [lo, hi] : boxes_) frame.boxes.push_back({lo, hi, level_colour});
    }
  }
}

}  // namespace tactus::viewer
