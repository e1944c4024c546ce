#include "runtime/interaction_loop.hpp"

#include <limits>

#include "contact/closest_point.hpp"

namespace tactus::runtime {

InteractionLoop::InteractionLoop(const scene::Model& model, std::vector<InteractionTarget> targets,
                                 TripleBuffer<SurfaceSnapshot>& surfaces)
    : model_(model), targets_(std::move(targets)), surfaces_(surfaces) {
  stats_.name = "interaction";
  stats_.rate = model.rates.interaction;
  for (const auto& b : model.bodies) parts_.push_back({"query " + b.name, {}});
}

void InteractionLoop::step(double t, Nanos deadline, Nanos start, bool real_time) {
  surfaces_.update();
  const SurfaceSnapshot& surfaces = surfaces_.read();
  for (InteractionTarget& target : targets_) {
    target.channels->tool.update();
    const ToolState& tool = target.channels->tool.read();
    LocalContact& out = target.channels->contact.write_buffer();
    out = LocalContact{};
    out.built_at = t;
    out.surface_time = surfaces.t;
    if (tool.valid) {
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t b : target.bodies) {
        const Nanos q0 = now_ns();
        const contact::SurfacePoint p =
            contact::closest_point_on_surface(tool.position, surfaces.positions[b], model_.bodies[b].surface.triangles);
        parts_[b].time.record(now_ns() - q0);
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
      }
    }
    target.channels->contact.publish();
  }
  stats_.record(deadline, start, now_ns() - start, real_time);
}

}  // namespace tactus::runtime
