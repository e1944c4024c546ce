#include "viewer/visual_feed.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <variant>

#include "compile/device_setup.hpp"
#include "runtime/devices.hpp"
#include "runtime/haptic_loop.hpp"

namespace tactus::viewer {
namespace {

constexpr std::size_t kMaxSamples = 4000;   // 20 s at 200 per second
constexpr std::uint64_t kSampleEvery = 5;   // of a 1 kHz loop's frames: 200 per second
constexpr std::size_t kMaxEvents = 64;
constexpr double kFabricStrainScale = 0.05;  // a fabric red at 5 % strain: a firm pull on a woven cloth

/// An arrow reaches `kArrowCap` of the scene's largest side at `kArrowCapForce`; harder
/// pushes draw no longer (their value is written at the tip).
constexpr double kArrowCap = 0.22, kArrowCapForce = 4.0;

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
                                                    latest_(model.devices.size()), needles_(model.devices.size()) {
  for (std::size_t i = 0; i < model.devices.size(); ++i) {
    devices_[i].name = model.devices[i].name;
    devices_[i].map = compile::workspace_map(model.devices[i]);
  }
  for (std::size_t ti = 0; ti < model.tools.size(); ++ti) {
    const scene::Tool& tool = model.tools[ti];
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
        d.needle = true;
        d.needle_length = needle->length;
        const scene::Device& device = model.devices[tool.devices[k]];
        if (const scene::NeedleLinePath* line = compile::needle_line(device)) {
          const Vec3 along = d.map.to_scene(line->target) - d.map.to_scene(line->entry);
          if (along.norm() > 0.0) d.needle_axis = along.normalized();
        }
        for (const scene::Algorithm& a : model.algorithms)
          if (const auto* p = std::get_if<scene::NeedleParams>(&a.params); p && a.enabled && a.tool == ti)
            for (const haptics::NeedleLayer& l : p->layers)
              d.layer_names.push_back(l.body < model.bodies.size() ? model.bodies[l.body].name : "?");
      }
    }
  }
  // Full scale: the device's largest force on a disc half the finger's radius, so a firm
  // press reaches the red end. A needle's tip is no pressing disc: its tiny radius would set
  // a scale no finger ever reaches.
  double scale = 0.0;
  for (std::size_t i = 0; i < devices_.size(); ++i)
    if (devices_[i].radius > 0.0 && !devices_[i].needle)
      scale = std::max(scale, model.devices[i].max_force / (std::numbers::pi * devices_[i].radius * devices_[i].radius));
  if (scale > 0.0) full_scale_ = scale;
  Aabb box{Vec3::Constant(std::numeric_limits<double>::infinity()), Vec3::Constant(-std::numeric_limits<double>::infinity())};
  for (const scene::Body& b : model.bodies)
    for (const Vec3& p : b.surface.vertices) {
      box.min = box.min.cwiseMin(p);
      box.max = box.max.cwiseMax(p);
    }
  if ((box.min.array() <= box.max.array()).all()) extent_ = std::max((box.max - box.min).maxCoeff(), 1e-3);
  for (const scene::Body& b : model.bodies) regions_.push_back(region_colours(model, b));
}

Vec3 VisualFeed::needle_axis(std::size_t device, const runtime::HapticFrame& f) const {
  const DeviceTool& d = devices_[device];
  if (d.needle_axis) return *d.needle_axis;
  // A handle's needle points along its −z (as the haptic loop takes it).
  const Vec3 axis = d.map.to_scene(f.orientation) * Vec3(0, 0, -1);
  return axis.norm() > 1e-9 && axis.allFinite() ? Vec3(axis.normalized()) : Vec3(0, 0, -1);
}

TripleBuffer<runtime::SurfaceSnapshot>& VisualFeed::surface_buffer(const runtime::SurfaceSnapshot& initial) {
  surfaces_ = std::make_unique<TripleBuffer<runtime::SurfaceSnapshot>>(initial);
  published_surfaces_.store(surfaces_.get(), std::memory_order_release);
  return *surfaces_;
}

void VisualFeed::frame(const runtime::HapticFrame& f) {
  std::lock_guard lock(mutex_);
  if (f.device >= latest_.size()) return;
  const bool was_touching = latest_[f.device] && latest_[f.device]->contact;
  latest_[f.device] = f;
  if (f.frame % kSampleEvery == 0 && f.device == 0) {
    samples_.push_back({f.t, f.force.norm(), f.compute_ns * 1e-3});
    if (samples_.size() > kMaxSamples) samples_.pop_front();
  }
  if (devices_[f.device].needle && f.contact && !was_touching) {
    // A new entry starts a new site: its depth from where the tip first touched, its layers.
    needles_[f.device].entry = devices_[f.device].map.to_scene(f.position);
    needles_[f.device].passed.clear();
  }
}

void VisualFeed::event(const runtime::LoopEvent& e) {
  if (e.kind == runtime::EventKind::note) return;
  std::lock_guard lock(mutex_);
  if (e.kind == runtime::EventKind::level_switch) {
    if (e.detail >= 0 && static_cast<std::size_t>(e.detail) < model_.bodies.size()) {
      if (levels_.size() != model_.bodies.size()) levels_.assign(model_.bodies.size(), -1);
      levels_[static_cast<std::size_t>(e.detail)] = static_cast<std::int32_t>(e.value);
    }
    return;  // many a second as the tool moves: the list keeps the safety and contact events
  }
  if (e.kind == runtime::EventKind::level_cost) return;
  if (e.kind == runtime::EventKind::rupture && e.device < needles_.size() && e.detail >= 0)
    needles_[e.device].passed.push_back(e.detail);
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
    t.name = d.name;
    t.needle = d.needle;
    t.layer_count = d.layer_names.size();
    if (!latest_[i]) continue;
    const runtime::HapticFrame& f = *latest_[i];
    t.seen = true;
    t.device_position = d.map.to_scene(f.position) + d.map.to_scene(f.orientation) * d.offset;
    t.force = d.map.rotation * f.force;
    t.touching = f.contact != 0 && t.force.norm() > 0.0;
    t.contact_point = f.proxy;
    // The contact holds the sphere on the surface along the force's direction.
    t.proxy_position = t.touching ? Vec3(f.proxy + d.radius * t.force.normalized()) : t.device_position;
    if (d.needle) {
      t.needle_axis = needle_axis(i, f);
      t.needle_depth = f.contact ? std::max(0.0, (t.device_position - needles_[i].entry).dot(t.needle_axis)) : 0.0;
      for (const std::int32_t layer : needles_[i].passed)
        t.layers_passed.push_back(static_cast<std::size_t>(layer) < d.layer_names.size()
                                      ? d.layer_names[static_cast<std::size_t>(layer)]
                                      : "?");
      // The needle's tip is where the device is: the contact does not hold it outside.
      t.proxy_position = t.device_position;
    }
  }
  return out;
}

std::vector<PlotSample> VisualFeed::samples() const {
  std::lock_guard lock(mutex_);
  return {samples_.begin(), samples_.end()};
}

std::vector<std::int32_t> VisualFeed::levels() const {
  std::lock_guard lock(mutex_);
  return levels_;
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
  std::vector<bool> hosts(model_.bodies.size(), false);
  for (const scene::Body& body : model_.bodies)
    if (body.host && *body.host < hosts.size()) hosts[*body.host] = true;
  std::vector<std::string> names;
  for (const scene::Body& body : model_.bodies) names.push_back(body.name);
  const std::vector<Colour> colours = body_colours(names);
  for (std::size_t b = 0; b < model_.bodies.size(); ++b) {
    const scene::Body& body = model_.bodies[b];
    SurfaceView s;
    s.name = body.name;
    s.colour = colours[b];
    s.recessed = hosts[b];
    s.triangles = body.surface.triangles;
    const bool published = snapshot && b < snapshot->positions.size() &&
                           snapshot->positions[b].size() == body.surface.vertices.size();
    s.positions = published ? snapshot->positions[b] : body.surface.vertices;
    if (!regions_[b].triangles.empty()) {
      s.triangle_colours = regions_[b].triangles;
      s.legend = regions_[b].legend;
    } else if (body.kind == scene::BodyKind::cloth) {
      // A fabric shows how far it is stretched: blue at rest, red at kFabricStrainScale.
      strain_colours(body.surface.vertices, s.positions, s.triangles, kFabricStrainScale, s.triangle_colours);
      s.legend = {{fmt::format("{}: strain 0", body.name), pressure_colour(0.0)},
                  {fmt::format("{}: strain {:g} %", body.name, 100.0 * kFabricStrainScale), pressure_colour(1.0)}};
    }
    frame.surfaces.push_back(std::move(s));
    for (const scene::Nodule& n : body.nodules)
      frame.spheres.push_back({n.center, n.radius, n.rigid ? Colour(0.55, 0.12, 0.15) : Colour(0.85, 0.45, 0.55), 1.0, true});
  }
  const std::vector<ToolView> tools = this->tools();
  for (std::size_t i = 0; i < tools.size(); ++i) {
    const ToolView& t = tools[i];
    if (!t.seen) {
      frame.status.push_back({fmt::format("{}: waiting for its first frame", t.name), Colour(0.85, 0.85, 0.85)});
      continue;
    }
    if (t.radius <= 0.0) continue;
    const double force = t.force.norm();
    const Colour arrow_colour = i == 0 ? Colour(0.98, 0.85, 0.1) : Colour(0.3, 0.95, 0.95);
    const std::string value = fmt::format("{} {:.2f} N", t.name, force);
    if (t.needle) {
      frame.needles.push_back({t.device_position, t.needle_axis, devices_[i].needle_length, t.radius});
      std::string line = fmt::format("{}: depth {:.1f} mm", value, 1e3 * t.needle_depth);
      if (t.layer_count > 0) {
        line += fmt::format(", {} of {} layers passed", t.layers_passed.size(), t.layer_count);
        for (std::size_t k = 0; k < t.layers_passed.size(); ++k) line += (k ? ", " : ": ") + t.layers_passed[k];
      }
      frame.status.push_back({line, arrow_colour});
    } else {
      frame.status.push_back({value, arrow_colour});
      // The finger is see-through so that the pressure under it shows.
      frame.spheres.push_back({t.proxy_position, t.radius, Colour(0.35, 0.55, 0.95), 0.55, false});
      for (const auto& [offset, radius] : devices_[i].extra_spheres) {
        const Vec3 centre = t.proxy_position + devices_[i].map.rotation * (offset - devices_[i].offset);
        frame.spheres.push_back({centre, radius, Colour(0.35, 0.55, 0.95), 0.55, false});
      }
    }
    if (!t.touching) continue;
    if (!t.needle) {
      // Where the device is (pushed into the tissue) against where the contact holds it.
      if ((t.device_position - t.proxy_position).norm() > 0.1 * t.radius)
        frame.spheres.push_back({t.device_position, t.radius, Colour(0.9, 0.9, 0.95), 0.25, false});
      // Contact radius from the device's penetration past the held sphere (Hertz: a = √(R d)).
      const double depth = std::max(0.0, (t.device_position - t.proxy_position).norm());
      const double radius = std::clamp(std::sqrt(t.radius * depth), 0.35 * t.radius, t.radius);
      for (SurfaceView& s : frame.surfaces) add_contact_pressure(s.positions, t.contact_point, force, radius, s.pressure);
    }
    // The same scale for every device, set by the scene's size and capped.
    frame.arrows.push_back({t.contact_point, t.force, kArrowCap * extent_ / kArrowCapForce, kArrowCap * extent_,
                            arrow_colour, value});
  }
  return frame;
}

}  // namespace tactus::viewer
