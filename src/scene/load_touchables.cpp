// bodies.<name>.levels and bodies.<name>.properties (rigid bodies touched by the proxy in a
// scene of many objects), and the [lod] table.
#include <fmt/format.h>

#include "scene/loader.hpp"

namespace tactus::scene::detail {

namespace {

using property_images::Channel;
using property_images::kChannelCount;
using property_images::kChannelNames;

/// Ranges the scene accepts per channel (property_images::validate checks the rest).
Range channel_range(int c) {
  switch (static_cast<Channel>(c)) {
    case Channel::stiffness: return Range::closed(0.0, property_images::kMaxStiffness);
    case Channel::static_friction:
    case Channel::kinetic_friction: return Range::closed(0.0, property_images::kMaxFriction);
    case Channel::damping: return Range::closed(0.0, property_images::kMaxDamping);
    case Channel::roughness_amplitude: return Range::closed(0.0, property_images::kMaxRoughnessAmplitude);
    case Channel::roughness_wavelength: return Range::closed(0.0, property_images::kMaxRoughnessWavelength);
    case Channel::young_modulus: return Range::closed(0.0, property_images::kMaxYoungModulus);
    case Channel::poisson_ratio: return Range::closed(0.0, property_images::kMaxPoissonRatio);
  }
  return Range::any();
}

/// The channel keys present in `r`, written over `values`; the mask of those present.
property_images::ChannelMask read_channels(Reader& r, property_images::SurfaceProperties& values) {
  property_images::ChannelMask mask = 0;
  for (int c = 0; c < kChannelCount; ++c)
    if (const auto v = r.number(kChannelNames[c], channel_range(c))) {
      values.values[c] = *v;
      mask |= static_cast<property_images::ChannelMask>(1u << c);
    }
  return mask;
}

SourceLocation table_location(const Reader& r) { return location(r.context(), r.table().source()); }

}  // namespace

SurfaceLevels read_levels(Reader& r) {
  SurfaceLevels l;
  l.build.coarse_levels = r.integer("coarse_levels", l.build.coarse_levels, 0, 8);
  l.build.reduction = r.number("reduction", l.build.reduction, Range::open(0.0, 1.0));
  l.build.subdivision_levels = r.integer("subdivision_levels", l.build.subdivision_levels, 0, 2);
  l.raise_force = r.number("raise_force", l.raise_force, Range::open_closed(0.0, 1e3));
  l.lower_force = r.number("lower_force", l.lower_force, Range::closed(0.0, 1e3));
  if (l.lower_force >= l.raise_force)
    r.fail("lower_force", fmt::format("lower_force ({}) must be below raise_force ({}): the gap keeps the level from "
                                      "flickering",
                                      number_text(l.lower_force), number_text(l.raise_force)));
  l.hold_time = r.number("hold_time", l.hold_time, Range::closed(0.0, 10.0));
  if (const auto file = r.string("file")) l.file = resolve_file(r, "file", *file);
  r.finish();
  return l;
}

SurfacePropertyImages read_properties(Reader& r) {
  SurfacePropertyImages p;
  p.where = table_location(r);
  p.resolution = r.integer("resolution", p.resolution, 2, property_images::PropertyImages::kMaxResolution);
  p.base[Channel::stiffness] = 500.0;
  read_channels(r, p.base);
  try {
    property_images::validate(p.base, p.where);
  } catch (const InputError& e) {
    r.fail_here(e.reason());
  }
  if (const auto file = r.string("file")) p.file = resolve_file(r, "file", *file);
  for (Reader& s : r.table_array("paint")) {
    SurfacePropertyImages::Stroke stroke;
    stroke.center = s.required_vec3("center");
    stroke.radius = s.required_number("radius", Range::positive());
    stroke.values = p.base;
    stroke.mask = read_channels(s, stroke.values);
    if (stroke.mask == 0)
      s.fail_here("a stroke paints at least one of stiffness, static_friction, kinetic_friction, damping, "
                  "roughness_amplitude, roughness_wavelength, young_modulus, poisson_ratio");
    try {
      property_images::validate(stroke.values, table_location(s));
    } catch (const InputError& e) {
      s.fail_here(e.reason() + " (a stroke's unpainted channels are the body's)");
    }
    s.finish();
    p.paint.push_back(stroke);
  }
  r.finish();
  return p;
}

LevelSelection read_level_selection(Reader& root) {
  LevelSelection s;
  auto r = root.table("lod");
  if (!r) return s;
  s.haptic_budget = r->number("haptic_budget", s.haptic_budget, Range::open_closed(0.0, 0.1));
  s.influence_radius = r->number("influence_radius", s.influence_radius, Range::open_closed(0.0, 100.0));
  s.blend_time = r->number("blend_time", s.blend_time, Range::closed(0.0, 0.1));
  s.select = r->boolean("select", s.select);
  if (const auto dir = r->string("cache")) {
    if (!r->context().options.allow_file_access) r->fail("cache", "file access is off for this scene");
    s.cache = r->context().base_dir / *dir;
  }
  r->finish();
  return s;
}

}  // namespace tactus::scene::detail
