// devices.<name>: what moves a tool (scripted paths, a simulated hand, a recording, a
// network bridge), its limits and its workspace.
#include <numbers>
#include <fmt/format.h>

#include "scene/loader.hpp"

namespace tactus::scene::detail {

namespace {

Vec3 unit(Reader& r, std::string_view key, const Vec3& fallback) {
  const Vec3 v = r.vec3(key, fallback);
  if (v.norm() < 1e-12) r.fail(key, "must not be the zero vector");
  return v.normalized();
}

Trajectory read_trajectory(Reader& t) {
  enum Type { waypoints, raster, press, circle, needle_line };
  const Type type = t.choice<Type>("type",
                                   {{"waypoints", waypoints}, {"raster", raster}, {"press", press},
                                    {"circle", circle}, {"needle_line", needle_line}},
                                   std::nullopt);
  switch (type) {
    case waypoints: {
      WaypointsPath p;
      auto points = t.table_array("points");
      if (points.empty()) t.fail_missing("points", "an array of {time, position} tables");
      for (Reader& w : points) {
        Waypoint wp;
        wp.time = w.required_number("time", Range::non_negative());
        wp.position = w.required_vec3("position");
        wp.direction = unit(w, "direction", wp.direction);
        w.finish();
        if (!p.points.empty() && wp.time <= p.points.back().time)
          w.fail("time", "waypoint times must increase strictly");
        p.points.push_back(wp);
      }
      p.loop = t.boolean("loop", false);
      return p;
    }
    case raster: {
      RasterPath p;
      p.min = t.required_vec2("min");
      p.max = t.required_vec2("max");
      if (!(p.min.array() < p.max.array()).all()) t.fail("max", "must exceed min on both axes");
      p.z = t.required_number("z");
      p.spacing = t.number("spacing", p.spacing, Range::positive());
      p.speed = t.number("speed", p.speed, Range::positive());
      p.approach = t.number("approach", p.approach, Range::non_negative());
      return p;
    }
    case press: {
      PressPath p;
      p.position = t.required_vec3("position");
      p.direction = unit(t, "direction", p.direction);
      p.depth = t.required_number("depth", Range::positive());
      p.speed = t.number("speed", p.speed, Range::positive());
      p.hold = t.number("hold", p.hold, Range::non_negative());
      p.repeat = t.integer("repeat", p.repeat, 1, 1000000);
      return p;
    }
    case circle: {
      CirclePath p;
      p.center = t.required_vec3("center");
      p.normal = unit(t, "normal", p.normal);
      p.radius = t.required_number("radius", Range::positive());
      p.period = t.number("period", p.period, Range::positive());
      return p;
    }
    case needle_line: {
      NeedleLinePath p;
      p.entry = t.required_vec3("entry");
      p.target = t.required_vec3("target");
      if ((p.target - p.entry).norm() < 1e-9) t.fail("target", "must differ from entry");
      p.speed = t.number("speed", p.speed, Range::positive());
      return p;
    }
  }
  t.fail_here("unreachable trajectory type");
}

Tremor read_tremor(Reader& r) {
  Tremor tr;
  if (auto t = r.table("tremor")) {
    tr.amplitude = t->number("amplitude", tr.amplitude, Range::non_negative());
    tr.frequency = t->number("frequency", tr.frequency, Range::positive());
    t->finish();
  }
  return tr;
}

Trajectory required_trajectory(Reader& r) {
  auto t = r.table("trajectory");
  if (!t) r.fail_missing("trajectory", "a table");
  Trajectory traj = read_trajectory(*t);
  t->finish();
  return traj;
}

bool is_ipv4(const std::string& s) {
  int parts = 0;
  std::size_t i = 0;
  while (i <= s.size()) {
    std::size_t j = s.find('.', i);
    if (j == std::string::npos) j = s.size();
    const std::string part = s.substr(i, j - i);
    if (part.empty() || part.size() > 3 || part.find_first_not_of("0123456789") != std::string::npos ||
        std::stoi(part) > 255)
      return false;
    ++parts;
    i = j + 1;
  }
  return parts == 4;
}

}  // namespace

Device read_device(Reader& r, const std::string& name) {
  Device d;
  d.name = name;
  enum Type { scripted, simulated_operator, replay, network, openhaptics, dhd };
  const Type type = r.choice<Type>("type",
                                   {{"scripted", scripted}, {"simulated_operator", simulated_operator},
                                    {"replay", replay}, {"network", network}, {"openhaptics", openhaptics},
                                    {"dhd", dhd}},
                                   std::nullopt);
  switch (type) {
    case scripted: {
      ScriptedDevice s;
      s.trajectory = required_trajectory(r);
      s.tremor = read_tremor(r);
      d.source = s;
      break;
    }
    case simulated_operator: {
      SimulatedOperatorDevice s;
      s.target = required_trajectory(r);
      s.tremor = read_tremor(r);
      s.hand_mass = r.number("hand_mass", s.hand_mass, Range::positive());
      s.hand_stiffness = r.number("hand_stiffness", s.hand_stiffness, Range::positive());
      s.hand_damping = r.number("hand_damping", s.hand_damping, Range::non_negative());
      d.source = s;
      break;
    }
    case replay: {
      ReplayDevice s;
      s.file = resolve_file(r, "file", r.required_string("file"));
      d.source = s;
      break;
    }
    case network: {
      NetworkDevice s;
      s.address = r.string("address", s.address);
      if (!is_ipv4(s.address)) r.fail("address", "'" + s.address + "' is not an IPv4 address like 127.0.0.1");
      s.port = r.integer("port", s.port, 1, 65535);
      s.timeout = r.number("timeout", s.timeout, Range::open_closed(0.0, 10.0));
      d.source = s;
      break;
    }
    case openhaptics: {
      OpenHapticsDevice s;
      s.device_name = r.string("device_name", "");
      d.source = s;
      break;
    }
    case dhd: {
      DhdDevice s;
      s.index = r.integer("index", s.index, -1, 255);
      d.source = s;
      break;
    }
  }
  d.max_force = r.number("max_force", d.max_force, Range::open_closed(0.0, 1000.0));
  d.max_stiffness = r.number("max_stiffness", d.max_stiffness, Range::positive());
  d.max_damping = r.number("max_damping", d.max_damping, Range::positive());
  d.workspace.min = Vec3::Constant(-0.2);
  d.workspace.max = Vec3::Constant(0.2);
  if (auto w = r.table("workspace")) {
    d.workspace.min = w->required_vec3("min");
    d.workspace.max = w->required_vec3("max");
    w->finish();
    if (!(d.workspace.min.array() < d.workspace.max.array()).all())
      r.fail("workspace", "max must exceed min on every axis");
  }
  d.scale = r.number("scale", d.scale, Range::positive());
  d.offset = r.vec3("offset", d.offset);
  if (auto rot = r.table("rotation")) {
    const Vec3 axis = rot->required_vec3("axis");
    const double degrees = rot->number("degrees", 0.0, Range::closed(-360.0, 360.0));
    rot->finish();
    if (!(axis.norm() > 0.0)) r.fail("rotation", "the rotation axis must not be zero");
    d.rotation = Quat(Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis.normalized()));
  }
  r.finish();
  return d;
}

}  // namespace tactus::scene::detail
