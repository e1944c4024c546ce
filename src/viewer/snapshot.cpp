#include "viewer/snapshot.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

#include "core/error.hpp"
#include "runtime/session.hpp"
#include "runtime/simulation_loop.hpp"
#include "viewer/debug_views.hpp"
#include "viewer/offscreen.hpp"
#include "viewer/overlay.hpp"
#include "viewer/renderer.hpp"
#include "viewer/visual_feed.hpp"

namespace tactus::viewer {
namespace {

std::vector<double> parse_numbers(const std::string& text, char separator, const std::string& flag) {
  std::vector<double> out;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t end = std::min(text.find(separator, begin), text.size());
    double value = 0.0;
    const char* first = text.data() + begin;
    const char* last = text.data() + end;
    const auto [ptr, ec] = std::from_chars(first, last, value);
    if (ec != std::errc() || ptr != last || !std::isfinite(value))
      throw InputError(fmt::format("{} '{}': '{}' is not a number", flag, text, std::string(first, last)));
    out.push_back(value);
    if (out.size() > 3) break;
    begin = end + 1;
  }
  return out;
}

}  // namespace

CameraSpec parse_camera(const std::string& text, const std::string& flag) {
  const std::vector<double> v = parse_numbers(text, ',', flag);
  if (v.size() < 2 || v.size() > 3)
    throw InputError(fmt::format("{} '{}': expected AZ,EL or AZ,EL,DIST (degrees, metres)", flag, text));
  if (v[1] <= -90.0 || v[1] >= 90.0)
    throw InputError(fmt::format("{} '{}': the elevation must lie strictly between -90 and 90 degrees", flag, text));
  if (v.size() == 3 && !(v[2] > 0.0 && v[2] <= 1000.0))
    throw InputError(fmt::format("{} '{}': the distance must be in (0, 1000] m", flag, text));
  return {v[0], v[1], v.size() == 3 ? v[2] : 0.0};
}

void parse_size(const std::string& text, const std::string& flag, int& width, int& height) {
  const std::vector<double> v = parse_numbers(text, 'x', flag);
  if (v.size() != 2 || v[0] != std::floor(v[0]) || v[1] != std::floor(v[1]) || v[0] < 16 || v[1] < 16 ||
      v[0] > 8192 || v[1] > 8192)
    throw InputError(fmt::format("{} '{}': expected WIDTHxHEIGHT in pixels, each 16 to 8192", flag, text));
  width = static_cast<int>(v[0]);
  height = static_cast<int>(v[1]);
}

OrbitCamera snapshot_camera(const FrameView& frame, const CameraSpec& spec) {
  OrbitCamera c = OrbitCamera::framing(frame_bounds(frame), spec.azimuth, spec.elevation);
  if (spec.distance > 0.0) c.distance = spec.distance;
  return c;
}

Snapshot render_offscreen(const FrameView& frame, const OrbitCamera& camera, const ViewOptions& view, int width,
                          int height) {
  OffscreenContext context;
  OffscreenTarget target(width, height);
  Renderer renderer;
  target.bind();
  renderer.render(frame, camera, view, width, height);
  Snapshot s;
  s.width = width;
  s.height = height;
  raster::Image image;
  image.width = width;
  image.height = height;
  image.rgb = target.read();
  paint(build_overlay(frame, camera, view, width, height), image);
  s.rgb = std::move(image.rgb);
  s.camera = camera;
  s.frame = frame;
  return s;
}

Snapshot take_snapshot(const scene::Model& model, const SnapshotOptions& options) {
  if (!(options.time >= 0.0) || options.time > 3600.0)
    throw InputError(fmt::format("--at {}: the time must be in [0, 3600] s", options.time));
  VisualFeed feed(model);
  FrameView frame;
  if (options.time > 0.0 && model.devices.empty()) {
    // No device, no haptic loop: the bodies under their scene loads alone, stepped as the
    // run's simulation loop steps them (the same instants as a lockstep run).
    runtime::SimulationLoop simulation(model, {});
    TripleBuffer<runtime::SurfaceSnapshot>& out = feed.surface_buffer(simulation.initial_snapshot());
    simulation.add_output(out);
    const double rate = model.rates.simulation;
    for (std::uint64_t k = 0; static_cast<double>(k) / rate <= options.time + 1e-12; ++k) {
      const Nanos now = now_ns();
      simulation.step(static_cast<double>(k) / rate, now, now, false);
    }
  } else if (options.time > 0.0) {
    runtime::SessionOptions o;
    o.scheduling = runtime::Scheduling::lockstep;
    o.duration = options.time;
    o.max_duration = options.time;
    o.visual = &feed;
    runtime::run_session(model, o);
  }
  frame = feed.build();
  DebugViews(model).add(feed.tools(), options.view, frame);
  return render_offscreen(frame, snapshot_camera(frame, options.camera), options.view, options.width, options.height);
}

}  // namespace tactus::viewer
