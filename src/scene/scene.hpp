#pragma once
// Scene files (TOML, docs/scene-format.md) → an immutable Model.
// Every problem in a scene is a tactus::InputError at the file:line:column of the
// offending value, with the key path in the message.
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

#include "scene/model.hpp"

namespace tactus::scene {

struct LoadOptions {
  /// Folder that relative mesh and replay paths resolve against. Empty: the folder of
  /// source_name (parse_scene) or of the scene file (load_scene).
  std::filesystem::path base_dir;
  /// false: any key naming a file (mesh, replay) is an error and nothing is read from
  /// disk; for fuzzing and for validating untrusted text.
  bool allow_file_access = true;
  /// Upper bound on the cells a mesh generator may be asked for, so that a typo like
  /// resolution = 40000 is an error rather than an hour of meshing.
  std::size_t max_generated_cells = 20'000'000;
};

/// Reads and validates a scene file.
Model load_scene(const std::filesystem::path& path, const LoadOptions& options = {});

/// Parses scene text; `source_name` is the file name used in messages and, unless
/// options.base_dir is set, the anchor for relative paths.
Model parse_scene(std::string_view toml_text, const std::string& source_name,
                  const LoadOptions& options = {});

/// The built-in default scene (scenes/default.toml, compiled in and parsed by the same
/// loader).
Model default_scene();
/// Its TOML text.
std::string_view default_scene_text();

/// A human-readable multi-line summary (rates, materials, bodies with mesh counts,
/// bounds, volume and fixed nodes, tools, devices, algorithms, recording). `real_time`
/// false leaves out the real-time settings, which a lockstep run does not use.
std::string summarize(const Model& model, bool real_time = true);

}  // namespace tactus::scene
