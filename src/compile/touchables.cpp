#include "compile/touchables.hpp"

#include <fmt/format.h>

#include "core/log.hpp"
#include "lod/impostor_cache.hpp"
#include "property_images/property_file.hpp"

namespace tactus::compile {

namespace {

std::shared_ptr<const lod::ImpostorHierarchy> levels_of(const scene::Model& m, const scene::Body& b) {
  // A body without [levels] has one: its own surface.
  lod::ImpostorParams params;
  params.coarse_levels = 0;
  params.subdivision_levels = 0;
  if (b.levels) params = b.levels->build;
  if (b.levels && !b.levels->file.empty())  // named by the scene: used as it is, or refused
    return std::make_shared<const lod::ImpostorHierarchy>(lod::load_impostor_cache(b.levels->file, b.surface, params));
  if (m.level_selection.cache.empty()) return std::make_shared<const lod::ImpostorHierarchy>(lod::build_impostors(b.surface, params));
  std::string why;
  auto h = lod::load_or_build_impostors(m.level_selection.cache, b.surface, params, &why);
  if (!why.empty()) log::info("body '{}': impostor levels built ({})", b.name, why);
  return std::make_shared<const lod::ImpostorHierarchy>(std::move(h));
}

std::shared_ptr<property_images::PropertyImages> images_of(const scene::Model& m, const scene::Body& b) {
  const scene::SurfacePropertyImages& p = *b.properties;
  // Pixels hold the body's own E and ν unless the scene sets others: a painted patch then
  // filters into real values at its edge, never into 0 ("unset").
  using property_images::Channel;
  property_images::SurfaceProperties base = p.base;
  if (base[Channel::young_modulus] == 0.0 && b.material) {
    base[Channel::young_modulus] = m.materials[*b.material].young_modulus;
    base[Channel::poisson_ratio] = m.materials[*b.material].poisson_ratio;
  }
  auto images = std::make_shared<property_images::PropertyImages>(
      p.file.empty() ? property_images::PropertyImages::build(b.surface, p.resolution, base, p.where)
                     : property_images::read_property_images(p.file, b.surface.content_hash()));
  for (const auto& stroke : p.paint) images->paint(stroke.center, stroke.radius, stroke.values, stroke.mask);
  return images;
}

}  // namespace

bool Touchables::any() const {
  for (const auto& o : objects)
    if (o) return true;
  return false;
}

bool is_touchable(const scene::Body& b) {
  return b.kind == scene::BodyKind::rigid && (b.levels || b.properties);
}

Touchables load_touchables(const scene::Model& m) {
  Touchables t;
  t.objects.resize(m.bodies.size());
  for (std::size_t i = 0; i < m.bodies.size(); ++i) {
    const scene::Body& b = m.bodies[i];
    if (!is_touchable(b)) continue;
    haptics::TouchableObject o;
    o.body = static_cast<std::int32_t>(i);
    try {
      o.levels = levels_of(m, b);
      if (b.properties) o.properties = images_of(m, b);
    } catch (const InputError& e) {
      // The file's own location when the error has one (a property image file), else the scene.
      const SourceLocation where = e.where().file.empty() ? SourceLocation{m.source, {}, {}, {}} : e.where();
      throw InputError(where, fmt::format("body '{}': {}", b.name, e.reason()));
    }
    if (b.levels) {
      o.raise_force = b.levels->raise_force;
      o.lower_force = b.levels->lower_force;
      o.hold_time = b.levels->hold_time;
    }
    t.objects[i] = std::move(o);
  }
  return t;
}

}  // namespace tactus::compile
