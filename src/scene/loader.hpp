#pragma once
// The loader's sections, one file each (private to src/scene). Each reads one named
// table into its Model part, resolving references against what `model` already holds:
// materials, then bodies, devices, tools, algorithms.
#include <string>
#include <string_view>
#include <vector>

#include "scene/model.hpp"
#include "scene/toml_reader.hpp"

namespace tactus::scene::detail {

Material read_material(Reader& r, const std::string& name);
Body read_body(Reader& r, const std::string& name, const Model& model);
Device read_device(Reader& r, const std::string& name);
Tool read_tool(Reader& r, const std::string& name, const Model& model);
Algorithm read_algorithm(Reader& r, const std::string& name, const Model& model);
/// Once every algorithm is read: a two-finger fabric algorithm's partner names it back, on
/// the other side of the fabric (`r` is the algorithm's table; the tools have their own devices).
/// Once every tool is read: a cspace body's `tools` (a two-point space's two tools).
void read_cspace_tools(Reader& r, Model& model, std::size_t body);
void check_partner(const Reader& r, const Model& model, std::size_t algorithm);
precompute::SpaceSettings read_precompute(Reader& r, Model& model);
/// An interpolation method by name (`trilinear`, default, `rbf_cubic`, `rbf_thin_plate`, `polynomial`).
precompute::Interpolation read_interpolation(Reader& r, std::string_view key);
/// bodies.<name>.nodules of a body whose mesh and fixed regions are read (load_nodules.cpp).
std::vector<Nodule> read_nodules(Reader& r, const Body& body);
Feedback read_feedback(Reader& root);
/// The fabric, mesh and clamp of a kind = "cloth" body (load_cloth.cpp).
void read_cloth(Reader& r, Body& body);

/// bodies.<name>.levels and .properties, and [lod] (load_touchables.cpp).
SurfaceLevels read_levels(Reader& r);
SurfacePropertyImages read_properties(Reader& r);
LevelSelection read_level_selection(Reader& root);

/// A path from the scene, resolved against the scene's folder; checks that the file
/// exists (or that file access is allowed at all).
std::filesystem::path resolve_file(Reader& r, std::string_view key, const std::string& value);

/// The index of the item named by r[key] in `items`, or an error naming the undefined
/// `what` with a did-you-mean.
template <class T>
std::size_t resolve_name(Reader& r, std::string_view key, const std::string& value,
                         const std::vector<T>& items, const char* what) {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (items[i].name == value) return i;
    names.push_back(items[i].name);
  }
  std::string msg = std::string("undefined ") + what + " '" + value + "'";
  if (const auto s = suggestion(value, names); !s.empty()) msg += "; " + s;
  else if (names.empty()) msg += " (the scene defines none)";
  r.fail(key, msg);
}

}  // namespace tactus::scene::detail
