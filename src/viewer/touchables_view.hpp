#pragma once
// The viewer's side of a scene of many objects: each touchable object drawn at the impostor
// level the haptic loop renders, coloured by level (a debug view), and the paint brush that
// writes property images where the tool touches, saved on request (seed 001's authoring: select
// a region, assign values, feel them at once, store them).
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "compile/touchables.hpp"
#include "scene/model.hpp"
#include "viewer/frame.hpp"

namespace tactus::viewer {

/// What drawing each level of each touchable object costs, per scene body (empty for bodies
/// that are not objects), coarse to fine: a measured time [ms], or triangles.
using LevelCosts = std::vector<std::vector<double>>;

/// Each level's triangle count (the cost where no draw time is measured).
[[nodiscard]] LevelCosts level_triangles(const compile::Touchables& touchables);

/// Each level's draw time [ms] through the viewer's renderer with `options`: the least of
/// `repeats` frames holding the level alone, seen small, without floor or shadow pass (sent,
/// transformed, shaded and finished: its geometry's cost, since the pixels go with the
/// resolution), less the least of an empty frame, at least 1 µs. Needs a current OpenGL
/// context.
[[nodiscard]] LevelCosts measure_level_draw_times(const compile::Touchables& touchables, const ViewOptions& options,
                                                  int repeats = 5);

/// The graphics impostors (seed 000 §4.2): one level per touchable object, greedy by projected
/// size on screen per unit of `cost`, the chosen levels' costs summing to at most `budget`
/// (the coarsest levels are always drawn); per body (−1 for bodies that are not objects).
[[nodiscard]] std::vector<std::int32_t> choose_graphics_levels(const compile::Touchables& touchables, const Vec3& eye,
                                                               double viewport_scale, const LevelCosts& cost,
                                                               double budget);

/// Replaces each touchable object's surface in `frame` by the level in `levels` (per body;
/// bodies without an entry, or −1, are drawn at their coarsest), coloured from blue (coarsest)
/// to red (finest) when `colour_by_level`.
void show_levels(const compile::Touchables& touchables, std::span<const std::int32_t> levels, bool colour_by_level,
                 FrameView& frame);

/// What the brush writes: the channels in `mask` of `values`, within `radius` of the tool.
struct PaintBrush {
  bool on = false;  ///< paints while the tool touches an object with property images
  double radius = 0.01;  ///< [m]
  property_images::SurfaceProperties values;
  property_images::ChannelMask mask = property_images::mask_of(property_images::Channel::stiffness);
  PaintBrush();
};

/// Paints the object with property images whose surface passes nearest `point` (within the
/// brush's radius); returns its body's name, or empty when none is that near.
std::string paint_at(const compile::Touchables& touchables, const scene::Model& model, const Vec3& point,
                     const PaintBrush& brush);

/// Writes every object's property images to `folder`/BODY.properties.h5; returns the files.
/// Throws InputError naming a file that cannot be written.
std::vector<std::filesystem::path> save_property_images(const compile::Touchables& touchables,
                                                        const scene::Model& model, const std::filesystem::path& folder);

}  // namespace tactus::viewer
