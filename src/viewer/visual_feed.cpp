#include "viewer/visual_feed.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <variant>

#include "runtime/devices.hpp"
#include "runtime/haptic_loop.hpp"

namespace tactus::viewer {
namespace {

constexpr std::size_t kMaxSamples = 4000;   // 20 s at 200 per second
constexpr std::uint64_t kSampleEvery = 5;   // of a 1 kHz loop's frames: 200 per second
constexpr std::size_t kMaxEvents = 64;

/// Colours by body index: skin first, then organ-like tones.
Colour body_colour(std::size_t index) {
  static const Colour palette[] = {Colour(0.93, 0.76, 0.66), Colour(0.72, 0.36, 0.32), Colour(0.62, 0.68, 0.82),
                                   Colour(0.85, 0.78, 0.52)};
  return palette[index % std::size(palette)];
}

}  // namespace

void add_contact_pressure(const std::vector<Vec3>& positions, const Vec3& point, double force, double radius,
                          std::vector<double>& pressure) {
  if (!(force > 0.0) || !(radius > 0.0) || !std::isfinite(force)) return;
  pressure.resize(positions.size(), 0.0);
  const double peak = 3.0 * force / (2.0 * std::numbers::pi * radius * radius);
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const double r2 = (positions[v] - point).squaredNorm() / (radius * radius);
    if (r2 < 1.0) pressure[v] += peak * std::sqrt(1.0 - r2);
  }
}

VisualFeed::VisualFeed(const scene::Model& model) : model_(model), devices_(model.devices.size()),
                                                    latest_(model.devices.size()) {
  for (std::size_t i = 0; i < model.devices.size(); ++i) devices_[i].map = runtime::workspace_map(model.devices[i]);
  for (const scene::Tool& tool : model.tools)
    for (std::size_t k = 0; k < tool.devices.size(); ++k) {
      if (tool.devices[k] >= devices_.size()) continue;
      DeviceTool& d = devices_[tool.devices[k]];
      if (const auto* one = std::get_if<scene::SphereTool>(&tool.shape)) {
        d.radius = one->radius;
      } else if (const auto* two = std::get_if<scene::TwoFingersTool>(&tool.shape)) {
        d.radius = two->radius;
      } else if (const auto* set = std::get_if<scene::SphereSetTool>(&tool.shape)) {
        if (set->spheres.empty()) continue;
        d.offset = set->spheres.front().center;
        d.radius = set->spheres.front().radius;
        for (std::size_t s = 1; s < set->spheres.size(); ++s)
          d.extra_spheres.emplace_back(set->spheres[s].center, set->spheres[s].radius);
      } else if (const auto* needle = std::get_if<scene::NeedleTool>(&tool.shape)) {
        d.radius = 0.5 * needle->diameter;
      }
    }
  // Full scale: the device's largest force on a disc half the finger's radius, so a firm
  // press reaches the red end.
  double scale = 0.0;
  for (std::size_t i = 0; i < devices_.size(); ++i)
    if (devices_[i].radius > 0.0)
      scale = std::max(scale, model.devices[i].max_force / (std::numbers::pi * devices_[i].radius * devices_[i].radius));
  if (scale > 0.0) full_scale_ = scale;
}

TripleBuffer<runtime::SurfaceSnapshot>& VisualFeed::surface_buffer(const runtime::SurfaceSnapshot& initial) {
  surfaces_ = std::make_unique<TripleBuffer<runtime::SurfaceSnapshot>>(initial);
  published_surfaces_.store(surfaces_.get(), std::memory_order_release);
  return *surfaces_;
}

void VisualFeed::frame(const runtime::HapticFrame& f) {
  std::lock_guard lock(mutex_);
  if (f.device >= latest_.size()) return;
  latest_[f.device] = f;
  if (f.frame % kSampleEvery == 0 && f.device == 0) {
    samples_.push_back({f.t, f.force.norm(), f.compute_ns * 1e-3});
    if (samples_.size() > kMaxSamples) samples_.pop_front();
  }
}

void VisualFeed::event(const runtime::LoopEvent& e) {
  if (e.kind == runtime::EventKind::note) return;
  std::lock_guard lock(mutex_);
  const std::string device = e.device < model_.devices.size() ? model_.devices[e.device].name : "?";
  events_.push_back(fmt::format("{:8.3f} s  {}  {}  {:.3g}", e.t, device, runtime::event_kind_name(e.kind), e.value));
  if (events_.size() > kMaxEvents) events_.pop_front();
}

std::vector<ToolView> VisualFeed::tools() const {
  std::vector<ToolView> out(devices_.size());
  std::lock_guard lock(mutex_);
  for (std::size_t i = 0; i < devices_.size(); ++i) {
    const DeviceTool& d = devices_[i];
    ToolView& t = out[i];
    t.radius = d.radius;
    if (!latest_[i]) continue;
    const runtime::HapticFrame& f = *latest_[i];
    t.seen = true;
    t.device_position = d.map.to_scene(f.position) + d.map.to_scene(f.orientation) * d.offset;
    t.force = d.map.rotation * f.force;
    t.touching = f.contact != 0 && t.force.norm() > 0.0;
    t.contact_point = f.proxy;
    // The contact holds the sphere on the surface along the force's direction.
    t.proxy_position = t.touching ? Vec3(f.proxy + d.radius * t.force.normalized()) : t.device_position;
  }
  return out;
}

std::vector<PlotSample> VisualFeed::samples() const {
  std::lock_guard lock(mutex_);
  return {samples_.begin(), samples_.end()};
}

std::vector<std::string> VisualFeed::events() const {
  std::lock_guard lock(mutex_);
  return {events_.begin(), events_.end()};
}

FrameView VisualFeed::build() {
  FrameView frame;
  frame.pressure_full_scale = full_scale_;
  const runtime::SurfaceSnapshot* snapshot = nullptr;
  if (auto* surfaces = published_surfaces_.load(std::memory_order_acquire)) {
    surfaces->update();
    snapshot = &surfaces->read();
    frame.t = snapshot->t;
  }
  for (std::size_t b = 0; b < model_.bodies.size(); ++b) {
    const scene::Body& body = model_.bodies[b];
    SurfaceView s;
    s.name = body.name;
    s.colour = body_colour(b);
    s.triangles = body.surface.triangles;
    const bool published = snapshot && b < snapshot->positions.size() &&
                           snapshot->positions[b].size() == body.surface.vertices.size();
    s.positions = published ? snapshot->positions[b] : body.surface.vertices;
    frame.surfaces.push_back(std::move(s));
    for (const scene::Nodule& n : body.nodules)
      frame.spheres.push_back({n.center, n.radius, n.rigid ? Colour(0.55, 0.12, 0.15) : Colour(0.85, 0.45, 0.55), 1.0, true});
  }
  const std::vector<ToolView> tools = this->tools();
  for (std::size_t i = 0; i < tools.size(); ++i) {
    const ToolView& t = tools[i];
    if (!t.seen || t.radius <= 0.0) continue;
    // The finger is see-through so that the pressure under it shows.
    frame.spheres.push_back({t.proxy_position, t.radius, Colour(0.35, 0.55, 0.95), 0.55, false});
    for (const auto& [offset, radius] : devices_[i].extra_spheres) {
      const Vec3 centre = t.proxy_position + devices_[i].map.rotation * (offset - devices_[i].offset);
      frame.spheres.push_back({centre, radius, Colour(0.35, 0.55, 0.95), 0.55, false});
    }
    if (!t.touching) continue;
    // Where the device is (pushed into the tissue) against where the contact holds it.
    if ((t.device_position - t.proxy_position).norm() > 0.1 * t.radius)
      frame.spheres.push_back({t.device_position, t.radius, Colour(0.9, 0.9, 0.95), 0.25, false});
    const double force = t.force.norm();
    // Contact radius from the device's penetration past the held sphere (Hertz: a = √(R d)).
    const double depth = std::max(0.0, (t.device_position - t.proxy_position).norm());
    const double radius = std::clamp(std::sqrt(t.radius * depth), 0.35 * t.radius, t.radius);
    for (SurfaceView& s : frame.surfaces) add_contact_pressure(s.positions, t.contact_point, force, radius, s.pressure);
    // A 1 N force is drawn as long as four finger radii.
    frame.arrows.push_back({t.contact_point, t.force, 4.0 * t.radius, Colour(0.98, 0.85, 0.1)});
  }
  return frame;
}

}  // namespace tactus::viewer
