#pragma once
// Reading and writing meshes. The format comes from the file extension:
//   .obj .stl .off .ply            surface (read + write)
//   .msh (Gmsh)                    surface or volume: read 1.0, ASCII 2.x / 4.0 / 4.1 and
//                                  binary 2.2 / 4.1; write ASCII 2.2 and 4.1
//   .node/.ele/.face (TetGen)      volume (read + write); name any of the three
//   .vtk (legacy, ASCII or binary)  volume and/or surface (read + write); tetrahedra and
//                                  triangles are read, other cells counted in `skipped`
//   .vtu (VTK XML)                 volume and/or surface (read + write): ascii, base64 and
//                                  appended arrays, zlib, UInt32/UInt64 headers, either byte
//                                  order; tetrahedra and triangles read as for .vtk
// Every reader throws tactus::InputError naming the file, the line (byte offset for
// binary files) and what is wrong; indices are checked before a mesh is returned.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mesh/file_numbering.hpp"
#include "mesh/tet_mesh.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::mesh {

enum class MeshFormat { obj, stl, off, ply, msh, tetgen, vtk, vtu };

/// What a file held: a surface, a volume, or (Gmsh) both.
struct MeshFile {
  MeshFormat format{};
  std::optional<TriMesh> surface;
  std::optional<TetMesh> volume;
  /// What the reader left out, e.g. "1942 lines, 12 quads" (VTK cells of other types);
  /// empty when it read everything.
  std::string skipped;
  /// How the file numbers the surface's and the volume's vertices and elements, with the
  /// line each element was read on (OBJ, OFF, TetGen, ASCII MSH); empty for the others.
  FileNumbering surface_numbering, volume_numbering;
  /// Tetrahedra turned over on reading because the whole file uses the mirrored corner
  /// order (see orient_whole_file); 0 when none were.
  std::size_t flipped_tets = 0;
};

struct WriteOptions {
  bool binary = false;             ///< STL and PLY: binary (little endian) instead of ASCII
  int msh_version = 41;            ///< Gmsh: 22 or 41
};

/// Format from the extension; throws InputError for an unknown one.
MeshFormat format_from_path(const std::filesystem::path& path);
const char* format_name(MeshFormat f);

MeshFile read_mesh(const std::filesystem::path& path);
void write_mesh(const std::filesystem::path& path, const TriMesh& mesh, const WriteOptions& = {});
void write_mesh(const std::filesystem::path& path, const TetMesh& mesh, const WriteOptions& = {});

/// A named array of a .vtu, `components` values per point or per cell.
struct VtuArray {
  std::string name;
  int components = 1;
  std::vector<double> values;
};
struct VtuFields {
  std::vector<VtuArray> point_data, cell_data;
};
/// An unstructured grid of points (nodes_per_cell 1), triangles (3) or tetrahedra (4) with
/// point and cell arrays, as VTK XML with ASCII data (doubles in their shortest form that
/// reads back to the same double). Throws InputError naming the file when it cannot be
/// written.
void write_vtu(const std::filesystem::path& path, const std::vector<Vec3>& points, const std::vector<Index>& cells,
               int nodes_per_cell, const VtuFields& fields);

}  // namespace tactus::mesh
