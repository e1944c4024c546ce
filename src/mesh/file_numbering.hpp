#pragma once
// How the file a mesh was read from numbers its vertices and elements, so that messages
// about the mesh can use the file's numbers and lines rather than the 0-based positions
// in memory. Filled by the text readers; empty vectors mean "not known".
#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "mesh/tri_mesh.hpp"

namespace tactus::mesh {

struct FileNumbering {
  FileNumbering() = default;
  FileNumbering(std::string word, std::int64_t base, std::vector<std::int64_t> tags = {})
      : element_word(std::move(word)), vertex_base(base), vertex_tags(std::move(tags)) {}

  /// What the file calls an element ("face" in OBJ and OFF, "element" in Gmsh).
  std::string element_word;
  /// The file's number of vertex 0 when vertices are numbered in order (OBJ 1, OFF 0,
  /// TetGen its first index).
  std::int64_t vertex_base = 0;
  /// Per vertex, the file's tag where it tags them freely (Gmsh node tags).
  std::vector<std::int64_t> vertex_tags;
  /// Per triangle or tetrahedron: the number of the element it came from in the file (a
  /// polygon split into triangles gives them all its number) and the line it was read on.
  std::vector<std::int64_t> element_number;
  std::vector<std::uint32_t> element_line;

  [[nodiscard]] std::int64_t vertex(Index v) const {
    if (v >= 0 && static_cast<std::size_t>(v) < vertex_tags.size()) return vertex_tags[static_cast<std::size_t>(v)];
    return vertex_base + v;
  }
  /// Records element `number` read on `line`.
  void add_element(std::int64_t number, std::uint64_t line) {
    element_number.push_back(number);
    element_line.push_back(static_cast<std::uint32_t>(std::min<std::uint64_t>(line, UINT32_MAX)));
  }
};

}  // namespace tactus::mesh
