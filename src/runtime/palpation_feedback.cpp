#include "runtime/palpation_feedback.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <variant>

#include "compile/device_setup.hpp"

namespace tactus::runtime {
namespace {

/// The finger radius of a device's tool: a sphere's radius, or the disc a sphere set covers.
std::optional<double> finger_radius(const scene::Model& model, std::size_t device) {
  for (const scene::Tool& tool : model.tools) {
    if (std::find(tool.devices.begin(), tool.devices.end(), device) == tool.devices.end()) continue;
    if (const auto* s = std::get_if<scene::SphereTool>(&tool.shape)) return s->radius;
    if (const auto* f = std::get_if<scene::TwoFingersTool>(&tool.shape)) return f->radius;
    if (const auto* set = std::get_if<scene::SphereSetTool>(&tool.shape)) {
      double r = 0.0;
      for (const auto& sphere : set->spheres) r = std::max(r, sphere.center.head<2>().norm() + sphere.radius);
      return r;
    }
  }
  return std::nullopt;
}

std::string seconds_or_never(const std::optional<double>& t) {
  return t ? fmt::format("{:.3f} s", *t) : std::string("never");
}

}  // namespace

std::optional<PalpationTracker> PalpationTracker::for_model(const scene::Model& model) {
  PalpationTracker t;
  for (const scene::Body& body : model.bodies) {
    if (body.nodules.empty()) continue;
    const mesh::TriMesh& s = body.surface;
    const std::size_t first = t.patch_.size();
    for (const Vec3& v : s.vertices) t.patch_.push_back({v.head<2>(), 0.0, false});
    for (const auto& tri : s.triangles) {
      const Vec3& a = s.vertices[static_cast<std::size_t>(tri[0])];
      const Vec3& b = s.vertices[static_cast<std::size_t>(tri[1])];
      const Vec3& c = s.vertices[static_cast<std::size_t>(tri[2])];
      const double third = (b - a).cross(c - a).norm() / 6.0;
      for (int k = 0; k < 3; ++k) t.patch_[first + static_cast<std::size_t>(tri[static_cast<std::size_t>(k)])].area += third;
    }
    for (const scene::Nodule& n : body.nodules) {
      t.spots_.push_back({n.center.head<2>(), n.radius});
      t.feedback_.nodules.push_back({body.name, n.name, std::nullopt});
    }
  }
  if (t.spots_.empty()) return std::nullopt;
  for (const auto& p : t.patch_) t.patch_area_ += p.area;
  for (std::size_t d = 0; d < model.devices.size(); ++d) {
    Finger f;
    if (const auto r = finger_radius(model, d)) {
      f.tracked = true;
      f.radius = *r;
      f.map = compile::workspace_map(model.devices[d]);
    }
    t.fingers_.push_back(f);
  }
  t.feedback_.safe_force = model.feedback.safe_force;
  t.haptic_period_ = 1.0 / model.rates.haptic;
  return t;
}

void PalpationTracker::add(const HapticFrame& frame) {
  feedback_.end_time = std::max(feedback_.end_time, frame.t);
  if (frame.device >= fingers_.size() || !fingers_[frame.device].tracked || !frame.contact) return;
  const Finger& finger = fingers_[frame.device];
  const double force = frame.force.norm();
  ++feedback_.contact_frames;
  force_sum_ += force;
  feedback_.peak_force = std::max(feedback_.peak_force, force);
  if (feedback_.safe_force > 0.0 && force > feedback_.safe_force) {
    ++feedback_.over_limit_frames;
    if (!feedback_.first_over_limit) feedback_.first_over_limit = frame.t;
  }
  const Vec2 center = finger.map.to_scene(frame.position).head<2>();
  const double r2 = finger.radius * finger.radius;
  for (PatchNode& node : patch_)
    if (!node.covered && (node.position - center).squaredNorm() <= r2) node.covered = true;
  for (std::size_t i = 0; i < spots_.size(); ++i)
    if (!feedback_.nodules[i].time && (spots_[i].center - center).norm() <= spots_[i].radius)
      feedback_.nodules[i].time = frame.t;
}

PalpationFeedback PalpationTracker::result() const {
  PalpationFeedback out = feedback_;
  double covered = 0.0;
  for (const auto& node : patch_)
    if (node.covered) covered += node.area;
  out.coverage = patch_area_ > 0.0 ? covered / patch_area_ : 0.0;
  out.mean_force = out.contact_frames ? force_sum_ / static_cast<double>(out.contact_frames) : 0.0;
  out.over_limit_time = static_cast<double>(out.over_limit_frames) * haptic_period_;
  return out;
}

std::vector<Event> feedback_events(const PalpationFeedback& f) {
  const double t = f.end_time;
  std::vector<Event> out;
  auto note = [&](double value, std::string text) { out.push_back(Event{t, EventKind::note, 0, value, std::move(text)}); };
  note(f.coverage, "palpation coverage (fraction of the patch area)");
  for (const auto& n : f.nodules)
    note(n.time ? *n.time : -1.0, fmt::format("palpation first contact over nodule {}.{} [s] (-1: never)", n.body, n.nodule));
  note(f.peak_force, "palpation peak force [N]");
  note(f.mean_force, "palpation mean force in contact [N]");
  if (f.safe_force > 0.0) {
    note(f.safe_force, "palpation safe force [N]");
    note(f.over_limit_time, "palpation time above the safe force [s]");
  }
  return out;
}

std::string format_feedback(const PalpationFeedback& f) {
  std::string out = "palpation feedback:\n";
  out += fmt::format("  coverage: {:.1f}% of the patch area was under the finger\n", 100.0 * f.coverage);
  for (const auto& n : f.nodules)
    out += fmt::format("  first contact over nodule {}.{}: {}\n", n.body, n.nodule, seconds_or_never(n.time));
  out += fmt::format("  force in contact: peak {:.3f} N, mean {:.3f} N over {} frames\n", f.peak_force, f.mean_force,
                     f.contact_frames);
  if (f.safe_force > 0.0) {
    if (f.over_limit_frames == 0)
      out += fmt::format("  safe force {:.3f} N: never exceeded\n", f.safe_force);
    else
      out += fmt::format("  safe force {:.3f} N: EXCEEDED for {:.3f} s ({} frames), first at {}\n", f.safe_force,
                         f.over_limit_time, f.over_limit_frames, seconds_or_never(f.first_over_limit));
  }
  return out;
}

std::string feedback_json(const PalpationFeedback& f) {
  auto number_or_null = [](const std::optional<double>& v) { return v ? fmt::format("{}", *v) : std::string("null"); };
  std::string nodules;
  for (std::size_t i = 0; i < f.nodules.size(); ++i)
    nodules += fmt::format("{}{{\"body\": \"{}\", \"nodule\": \"{}\", \"first_contact_s\": {}}}", i ? ", " : "",
                           f.nodules[i].body, f.nodules[i].nodule, number_or_null(f.nodules[i].time));
  return fmt::format("{{\"coverage\": {}, \"nodules\": [{}], \"contact_frames\": {}, \"peak_force_n\": {}, "
                     "\"mean_force_n\": {}, \"safe_force_n\": {}, \"over_limit_frames\": {}, \"over_limit_time_s\": {}, "
                     "\"first_over_limit_s\": {}}}",
                     f.coverage, nodules, f.contact_frames, f.peak_force, f.mean_force, f.safe_force,
                     f.over_limit_frames, f.over_limit_time, number_or_null(f.first_over_limit));
}

}  // namespace tactus::runtime
