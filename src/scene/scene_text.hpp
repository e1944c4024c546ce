#pragma once
// Scene text as a TOML table and back, for tools that change a scene's values before it is
// compiled (the Python module's Model.with_changes): the `base` chain merged in, and TOML
// text that parse_scene reads back to the same scene.
#include <toml++/toml.h>

#include <string>
#include <string_view>

#include "scene/scene.hpp"

namespace tactus::scene {

/// The scene's table with its `[scene] base` chain merged in (the `base` key removed). Its
/// nodes keep the positions they were read at. InputError as parse_scene.
toml::table flatten_scene(std::string_view toml_text, const std::string& source_name, const LoadOptions& options = {});

/// `over`'s keys into `base`, as a scene's `base` is merged: tables merge key by key, anything
/// else replaces or adds the key.
void merge_tables(toml::table& base, const toml::table& over);

/// TOML text of a scene table. The loader takes named tables (bodies, devices, ...) in the
/// order of their keys' positions, so sub-tables are written in that order (keys without a
/// position, added by a tool, after the others); every other value as toml++ writes it
/// (doubles with 17 significant digits, which read back to the same value), arrays of tables
/// inline.
std::string format_scene(const toml::table& root);

}  // namespace tactus::scene
