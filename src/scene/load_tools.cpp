// tools.<name>: the finger or instrument a device moves.
#include <fmt/format.h>

#include "scene/loader.hpp"

namespace tactus::scene::detail {

namespace {

FingerProperties read_finger(Reader& r) {
  FingerProperties f;
  f.mass = r.number("mass", f.mass, Range::positive());
  f.young_modulus = r.number("young_modulus", f.young_modulus, Range::positive());
  f.poisson_ratio = r.number("poisson_ratio", f.poisson_ratio, Range::open(-1.0, 0.5));
  return f;
}

/// The device a tool names, refusing one that already drives another tool.
std::size_t claim_device(Reader& r, std::string_view key, const std::string& device, const Model& model,
                         const std::vector<std::size_t>& claimed_here) {
  const std::size_t d = resolve_name(r, key, device, model.devices, "device");
  for (const Tool& other : model.tools)
    for (const std::size_t od : other.devices)
      if (od == d) r.fail(key, "device '" + device + "' already drives tool '" + other.name + "'");
  for (const std::size_t od : claimed_here)
    if (od == d) r.fail(key, "device '" + device + "' is named twice");
  return d;
}

}  // namespace

Tool read_tool(Reader& r, const std::string& name, const Model& model) {
  Tool t;
  t.name = name;
  enum Type { sphere, sphere_set, needle, two_fingers };
  const Type type = r.choice<Type>("type",
                                   {{"sphere", sphere}, {"sphere_set", sphere_set}, {"needle", needle},
                                    {"two_fingers", two_fingers}},
                                   std::nullopt);
  if (type == two_fingers) {
    const auto devices = r.string_list("devices", {});
    if (devices.size() != 2)
      r.fail_missing("devices", "an array of two device names, one per finger");
    for (const auto& d : devices) t.devices.push_back(claim_device(r, "devices", d, model, t.devices));
  } else {
    const auto device = r.string("device");
    if (!device) r.fail_missing("device", "a device name");
    t.devices.push_back(claim_device(r, "device", *device, model, t.devices));
  }

  switch (type) {
    case sphere: {
      SphereTool s;
      s.radius = r.number("radius", s.radius, Range::positive());
      s.finger = read_finger(r);
      t.shape = s;
      break;
    }
    case sphere_set: {
      SphereSetTool s;
      const int count = r.integer("count", 8, 1, 8);
      if (count != 1 && count != 8) r.fail("count", fmt::format("{} spheres: must be 1 or 8", count));
      const double radius = r.number("radius", 0.004, Range::positive());
      const double spacing = r.number("spacing", radius, Range::positive());
      if (count == 1) {
        s.spheres.push_back({Vec3::Zero(), radius});
      } else {
        // Seed 000's eight spheres filling the fingertip: a 2×2×2 block of centres.
        for (int i = 0; i < 8; ++i)
          s.spheres.push_back({0.5 * spacing * Vec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1), radius});
      }
      s.finger = read_finger(r);
      t.shape = s;
      break;
    }
    case needle: {
      NeedleTool s;
      s.length = r.number("length", s.length, Range::positive());
      s.diameter = r.number("diameter", s.diameter, Range::positive());
      if (s.diameter >= s.length) r.fail("diameter", "must be smaller than the needle's length");
      s.mass = r.number("mass", s.mass, Range::positive());
      t.shape = s;
      break;
    }
    case two_fingers: {
      TwoFingersTool s;
      s.radius = r.number("radius", s.radius, Range::positive());
      s.finger = read_finger(r);
      t.shape = s;
      break;
    }
  }
  r.finish();
  return t;
}

}  // namespace tactus::scene::detail
