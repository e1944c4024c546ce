#include "viewer/touchables_view.hpp"

#include <algorithm>
#include <chrono>

#include "lod/selection.hpp"
#include "property_images/property_file.hpp"
#include "viewer/renderer.hpp"
#include "viewer/scene_target.hpp"

namespace tactus::viewer {

PaintBrush::PaintBrush() {
  values[property_images::Channel::stiffness] = 1000.0;
  values[property_images::Channel::static_friction] = 0.5;
  values[property_images::Channel::kinetic_friction] = 0.4;
  values[property_images::Channel::damping] = 1.0;
  values[property_images::Channel::roughness_amplitude] = 1e-4;
  values[property_images::Channel::roughness_wavelength] = 0.003;
  values[property_images::Channel::young_modulus] = 5e4;
  values[property_images::Channel::poisson_ratio] = 0.45;
}

LevelCosts level_triangles(const compile::Touchables& touchables) {
  LevelCosts costs(touchables.objects.size());
  for (std::size_t b = 0; b < touchables.objects.size(); ++b)
    if (const auto& object = touchables.objects[b])
      for (const auto& l : object->levels->levels) costs[b].push_back(static_cast<double>(l.mesh.triangles.size()));
  return costs;
}

LevelCosts measure_level_draw_times(const compile::Touchables& touchables, const ViewOptions& options, int repeats) {
  // A renderer of its own (the window's sizes its floor from the first frame it draws), no
  // floor and no shadow pass (whose light is framed on each frame's bounds, so its fill would
  // vary from object to object): what is timed is the level's own pass.
  Renderer renderer;
  ViewOptions alone = options;
  alone.floor = false;
  alone.shadows = false;
  SceneTarget target;
  constexpr int kWidth = 320, kHeight = 200;
  const auto frame_ms = [&](const FrameView& frame, const OrbitCamera& camera) {
    std::vector<double> times;
    for (int i = 0; i < std::max(repeats, 1); ++i) {
      const auto start = std::chrono::steady_clock::now();
      target.bind(kWidth, kHeight);
      renderer.render(frame, camera, alone, kWidth, kHeight);
      glFinish();
      times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    // The least: other threads only ever add to a draw's time.
    return *std::min_element(times.begin(), times.end());
  };
  LevelCosts costs(touchables.objects.size());
  for (std::size_t b = 0; b < touchables.objects.size(); ++b) {
    const auto& object = touchables.objects[b];
    if (!object) continue;
    const auto& levels = object->levels->levels;
    const Aabb box = levels.back().mesh.bounds();
    // Seen from far enough to cover a few hundred pixels: what a level costs is its geometry
    // (building, sending and transforming its triangles); the pixels it covers in the scene
    // go with the resolution, which the frame budget sets apart.
    OrbitCamera camera = OrbitCamera::framing(box);
    camera.distance *= 8.0;
    FrameView empty;
    const double base = frame_ms(empty, camera);
    for (const auto& l : levels) {
      FrameView frame;
      SurfaceView& s = frame.surfaces.emplace_back();
      s.positions = l.mesh.vertices;
      s.triangles = l.mesh.triangles;
      s.static_id = &l.mesh;  // as the window draws it: from the renderer's cache after the first frame
      costs[b].push_back(std::max(frame_ms(frame, camera) - base, 1e-3));
    }
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return costs;
}

std::vector<std::int32_t> choose_graphics_levels(const compile::Touchables& touchables, const Vec3& eye,
                                                 double viewport_scale, const LevelCosts& cost, double budget) {
  std::vector<lod::ObjectLevels> options;
  std::vector<std::size_t> bodies;
  for (std::size_t b = 0; b < touchables.objects.size(); ++b) {
    const auto& object = touchables.objects[b];
    if (!object) continue;
    const Aabb box = object->levels->levels.back().mesh.bounds();
    lod::ObjectLevels o;
    o.benefit = lod::graphics_benefit(box.center(), 0.5 * box.size().norm(), eye, viewport_scale);
    const auto& levels = object->levels->levels;
    for (std::size_t l = 0; l < levels.size(); ++l)
      o.levels.push_back({b < cost.size() && l < cost[b].size() ? cost[b][l] : 0.0, levels[l].error.hausdorff});
    options.push_back(std::move(o));
    bodies.push_back(b);
  }
  std::vector<std::int32_t> levels(touchables.objects.size(), -1);
  if (options.empty()) return levels;
  const lod::Selection chosen = lod::select_levels(options, budget);
  for (std::size_t i = 0; i < bodies.size(); ++i) levels[bodies[i]] = static_cast<std::int32_t>(chosen.level[i]);
  return levels;
}

void show_levels(const compile::Touchables& touchables, std::span<const std::int32_t> levels, bool colour_by_level,
                 FrameView& frame) {
  for (std::size_t b = 0; b < touchables.objects.size() && b < frame.surfaces.size(); ++b) {
    const auto& object = touchables.objects[b];
    if (!object) continue;
    const auto& all = object->levels->levels;
    const std::int32_t wanted = b < levels.size() ? std::max(levels[b], 0) : 0;
    const auto level = std::min(static_cast<std::size_t>(wanted), all.size() - 1);
    SurfaceView& s = frame.surfaces[b];
    s.positions = all[level].mesh.vertices;
    s.triangles = all[level].mesh.triangles;
    s.static_id = &all[level].mesh;  // a rigid object's level never moves: the renderer keeps it
    s.pressure.clear();
    if (colour_by_level)
      s.colour = pressure_colour(all.size() > 1 ? static_cast<double>(level) / static_cast<double>(all.size() - 1) : 1.0);
  }
}

std::string paint_at(const compile::Touchables& touchables, const scene::Model& model, const Vec3& point,
                     const PaintBrush& brush) {
  double nearest = brush.radius;
  const haptics::TouchableObject* target = nullptr;
  for (const auto& object : touchables.objects) {
    if (!object || !object->properties) continue;
    const auto c = object->levels->levels.back().bvh.closest_point(point, nearest);
    if (c.triangle >= 0 && c.distance <= nearest) {
      nearest = c.distance;
      target = &*object;
    }
  }
  if (!target) return {};
  target->properties->paint(point, brush.radius, brush.values, brush.mask);
  return model.bodies[static_cast<std::size_t>(target->body)].name;
}

std::vector<std::filesystem::path> save_property_images(const compile::Touchables& touchables,
                                                        const scene::Model& model, const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> files;
  for (const auto& object : touchables.objects) {
    if (!object || !object->properties) continue;
    const std::filesystem::path file =
        folder / (model.bodies[static_cast<std::size_t>(object->body)].name + ".properties.h5");
    property_images::write_property_images(file, *object->properties);
    files.push_back(file);
  }
  return files;
}

}  // namespace tactus::viewer
