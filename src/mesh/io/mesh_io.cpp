#include "mesh/io/mesh_io.hpp"

#include <algorithm>
#include <cctype>
#include <stdexcept>

#include "mesh/io/io_common.hpp"

namespace tactus::mesh {

namespace {

constexpr const char* supported = ".obj .stl .off .ply .msh .node .ele .face .vtk .vtu";

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// Writers trust the mesh they are given, but an out-of-range index would read out of
// bounds, so it is a programming error worth stopping on.
template <std::size_t N>
void check_cells(const std::vector<std::array<Index, N>>& cells, std::size_t n_vertices, const char* what) {
  for (std::size_t i = 0; i < cells.size(); ++i)
    for (const Index v : cells[i])
      if (v < 0 || static_cast<std::size_t>(v) >= n_vertices)
        throw std::invalid_argument(std::string("write_mesh: ") + what + " " + std::to_string(i) +
                                    " has vertex index " + std::to_string(v) + " out of range");
}

std::vector<Index> flatten(const auto& cells) {
  std::vector<Index> out;
  out.reserve(cells.size() * (cells.empty() ? 0 : cells[0].size()));
  for (const auto& c : cells) out.insert(out.end(), c.begin(), c.end());
  return out;
}

// The siblings of a TetGen file share its stem: "bar.1.node", "bar.1.ele", "bar.1.face".
std::filesystem::path sibling(const std::filesystem::path& path, const char* ext) {
  auto p = path;
  p.replace_extension(ext);
  return p;
}

MeshFile read_tetgen(const std::filesystem::path& path) {
  const auto node_path = sibling(path, ".node");
  const auto ele_path = sibling(path, ".ele");
  const auto face_path = sibling(path, ".face");
  std::error_code ec;
  const bool has_ele = std::filesystem::exists(ele_path, ec);
  const bool has_face = std::filesystem::exists(face_path, ec);
  if (!has_ele && !has_face)
    throw InputError(SourceLocation{path.string(), {}, {}, {}},
                     "TetGen mesh needs '" + ele_path.string() + "' or '" + face_path.string() +
                         "' next to the .node file; neither exists");
  const std::string node = io::read_file(node_path);
  std::string ele, face;
  if (has_ele) ele = io::read_file(ele_path);
  if (has_face) face = io::read_file(face_path);
  const std::string_view ele_view = ele, face_view = face;
  return io::parse_tetgen(node, node_path.string(), has_ele ? &ele_view : nullptr, ele_path.string(),
                          has_face ? &face_view : nullptr, face_path.string());
}

}  // namespace

MeshFormat format_from_path(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".obj") return MeshFormat::obj;
  if (ext == ".stl") return MeshFormat::stl;
  if (ext == ".off") return MeshFormat::off;
  if (ext == ".ply") return MeshFormat::ply;
  if (ext == ".msh") return MeshFormat::msh;
  if (ext == ".node" || ext == ".ele" || ext == ".face") return MeshFormat::tetgen;
  if (ext == ".vtk") return MeshFormat::vtk;
  if (ext == ".vtu") return MeshFormat::vtu;
  throw InputError(SourceLocation{path.string(), {}, {}, {}},
                   (ext.empty() ? std::string("mesh file has no extension")
                                : "unknown mesh file extension '" + ext + "'") +
                       "; supported: " + supported);
}

const char* format_name(MeshFormat f) {
  switch (f) {
    case MeshFormat::obj: return "OBJ";
    case MeshFormat::stl: return "STL";
    case MeshFormat::off: return "OFF";
    case MeshFormat::ply: return "PLY";
    case MeshFormat::msh: return "Gmsh MSH";
    case MeshFormat::tetgen: return "TetGen";
    case MeshFormat::vtk: return "VTK legacy";
    case MeshFormat::vtu: return "VTK XML (VTU)";
  }
  return "unknown";
}

MeshFile read_mesh(const std::filesystem::path& path) {
  const MeshFormat format = format_from_path(path);
  const std::string name = path.string();
  switch (format) {
    case MeshFormat::obj: return io::parse_obj(io::read_file(path), name);
    case MeshFormat::stl: return io::parse_stl(io::read_file(path), name);
    case MeshFormat::off: return io::parse_off(io::read_file(path), name);
    case MeshFormat::ply: return io::parse_ply(io::read_file(path), name);
    case MeshFormat::msh: return io::parse_msh(io::read_file(path), name);
    case MeshFormat::tetgen: return read_tetgen(path);
    case MeshFormat::vtk: return io::parse_vtk(io::read_file(path), name);
    case MeshFormat::vtu: return io::parse_vtu(io::read_file(path), name);
  }
  throw std::logic_error("read_mesh: unhandled mesh format");
}

void write_mesh(const std::filesystem::path& path, const TriMesh& mesh, const WriteOptions& options) {
  const MeshFormat format = format_from_path(path);
  check_cells(mesh.triangles, mesh.vertices.size(), "triangle");
  switch (format) {
    case MeshFormat::obj: return io::write_file(path, io::format_obj(mesh));
    case MeshFormat::stl: return io::write_file(path, io::format_stl(mesh, options.binary));
    case MeshFormat::off: return io::write_file(path, io::format_off(mesh));
    case MeshFormat::ply: return io::write_file(path, io::format_ply(mesh, options.binary));
    case MeshFormat::msh: return io::write_file(path, io::format_msh(&mesh, nullptr, options.msh_version));
    case MeshFormat::tetgen:
      // A surface in TetGen form is a .node plus a .face file (what tetgen -p reads as well).
      io::write_file(sibling(path, ".node"), io::format_tetgen_node(mesh.vertices));
      io::write_file(sibling(path, ".face"), io::format_tetgen_face(mesh.triangles, {}));
      return;
    case MeshFormat::vtk:
      return io::write_file(path, io::format_vtk(mesh.vertices, flatten(mesh.triangles), 3, nullptr));
    case MeshFormat::vtu:
      return io::write_file(path, io::format_vtu(mesh.vertices, flatten(mesh.triangles), 3, nullptr));
  }
}

void write_mesh(const std::filesystem::path& path, const TetMesh& mesh, const WriteOptions& options) {
  const MeshFormat format = format_from_path(path);
  check_cells(mesh.tets, mesh.vertices.size(), "tet");
  check_cells(mesh.faces, mesh.vertices.size(), "face");
  if (!mesh.tet_regions.empty() && mesh.tet_regions.size() != mesh.tets.size())
    throw std::invalid_argument("write_mesh: tet_regions must be empty or one per tet");
  if (!mesh.face_markers.empty() && mesh.face_markers.size() != mesh.faces.size())
    throw std::invalid_argument("write_mesh: face_markers must be empty or one per face");
  const std::vector<int>* regions = mesh.tet_regions.empty() ? nullptr : &mesh.tet_regions;
  switch (format) {
    case MeshFormat::msh: return io::write_file(path, io::format_msh(nullptr, &mesh, options.msh_version));
    case MeshFormat::tetgen: {
      const auto text = io::format_tetgen(mesh);
      io::write_file(sibling(path, ".node"), text.node);
      io::write_file(sibling(path, ".ele"), text.ele);
      if (!text.face.empty()) io::write_file(sibling(path, ".face"), text.face);
      return;
    }
    case MeshFormat::vtk: return io::write_file(path, io::format_vtk(mesh.vertices, flatten(mesh.tets), 4, regions));
    case MeshFormat::vtu: return io::write_file(path, io::format_vtu(mesh.vertices, flatten(mesh.tets), 4, regions));
    case MeshFormat::obj:
    case MeshFormat::stl:
    case MeshFormat::off:
    case MeshFormat::ply: break;
  }
  throw InputError(SourceLocation{path.string(), {}, {}, {}},
                   std::string(format_name(format)) +
                       " holds surfaces only; write the tet mesh's boundary as a TriMesh, or use .msh, "
                       ".node/.ele, .vtk or .vtu for a volume");
}

void write_vtu(const std::filesystem::path& path, const std::vector<Vec3>& points, const std::vector<Index>& cells,
               int nodes_per_cell, const VtuFields& fields) {
  if (nodes_per_cell != 1 && nodes_per_cell != 3 && nodes_per_cell != 4)
    throw std::invalid_argument("write_vtu: nodes_per_cell must be 1, 3 or 4");
  const auto per = static_cast<std::size_t>(nodes_per_cell);
  if (cells.size() % per != 0) throw std::invalid_argument("write_vtu: cells is not a whole number of cells");
  for (const Index c : cells)
    if (c < 0 || static_cast<std::size_t>(c) >= points.size()) throw std::invalid_argument("write_vtu: cell index out of range");
  auto check = [](const std::vector<VtuArray>& arrays, std::size_t count) {
    for (const VtuArray& a : arrays)
      if (a.components < 1 || a.values.size() != count * static_cast<std::size_t>(a.components))
        throw std::invalid_argument("write_vtu: array '" + a.name + "' has the wrong size");
  };
  check(fields.point_data, points.size());
  check(fields.cell_data, cells.size() / per);
  io::write_file(path, io::format_vtu(points, cells, nodes_per_cell, nullptr, &fields));
}

}  // namespace tactus::mesh
