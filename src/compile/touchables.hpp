#pragma once
// The rigid bodies of a scene of many objects, compiled once for every device that touches
// them: each one's impostor levels (lod/, cached on disk when the scene's [lod] names a
// folder) and its haptic property images (property_images/, cast or read, then painted with
// the scene's strokes). Shared: a stroke painted during the run is felt by every device.
#include <memory>
#include <optional>
#include <vector>

#include "haptics/algorithms/proxy_on_objects.hpp"
#include "scene/model.hpp"

namespace tactus::compile {

struct Touchables {
  /// Per scene body: its object when it is rigid with `levels` or `properties`.
  std::vector<std::optional<haptics::TouchableObject>> objects;
  [[nodiscard]] bool any() const;
};

/// Throws InputError naming the body (and the file, for a property image file) when a level
/// or an image cannot be built or read: an open surface, a file for another mesh, a pixel out
/// of range.
[[nodiscard]] Touchables load_touchables(const scene::Model& model);

/// Whether body `b` is one of the scene's touchable objects.
[[nodiscard]] bool is_touchable(const scene::Body& body);

}  // namespace tactus::compile
