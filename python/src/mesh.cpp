// tactus.read_mesh / tactus.write_mesh: the engine's mesh readers and writers
// (mesh/io/mesh_io.hpp). What read_mesh returns views the mesh the reader built, kept alive
// by its arrays; write_mesh copies the arrays it is given.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <optional>

#include "bindings.hpp"
#include "core/error.hpp"
#include "mesh/io/mesh_io.hpp"

namespace tactus::python {
namespace {

py::dict read(const std::filesystem::path& path) {
  auto file = std::make_shared<mesh::MeshFile>();
  {
    py::gil_scoped_release release;
    *file = mesh::read_mesh(path);
  }
  // The arrays hold a capsule that owns the file's meshes.
  py::capsule owner(new std::shared_ptr<mesh::MeshFile>(file),
                    [](void* p) { delete static_cast<std::shared_ptr<mesh::MeshFile>*>(p); });
  py::dict out;
  out["format"] = std::string(mesh::format_name(file->format));
  out["skipped"] = file->skipped;
  out["flipped_tets"] = file->flipped_tets;
  if (file->surface) {
    py::dict s;
    s["vertices"] = vec3_view(file->surface->vertices, owner);
    s["triangles"] = index_view(file->surface->triangles, owner);
    out["surface"] = s;
  } else {
    out["surface"] = py::none();
  }
  if (file->volume) {
    const mesh::TetMesh& v = *file->volume;
    py::dict d;
    d["vertices"] = vec3_view(v.vertices, owner);
    d["tets"] = index_view(v.tets, owner);
    d["regions"] = v.tet_regions.empty() ? py::object(py::none()) : py::object(vector_view(v.tet_regions, owner));
    d["faces"] = index_view(v.faces, owner);
    d["face_markers"] = v.face_markers.empty() ? py::object(py::none()) : py::object(vector_view(v.face_markers, owner));
    out["volume"] = d;
  } else {
    out["volume"] = py::none();
  }
  return out;
}

std::vector<Vec3> points_of(const py::array_t<double, py::array::c_style | py::array::forcecast>& a) {
  if (a.ndim() != 2 || a.shape(1) != 3) throw py::value_error("vertices must be an (n, 3) array");
  std::vector<Vec3> out(static_cast<std::size_t>(a.shape(0)));
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i) out[static_cast<std::size_t>(i)] = Vec3(r(i, 0), r(i, 1), r(i, 2));
  return out;
}

template <std::size_t K>
std::vector<std::array<mesh::Index, K>> cells_of(const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& a,
                                                 std::size_t vertices, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != static_cast<py::ssize_t>(K))
    throw py::value_error(std::string(what) + " must be an (n, " + std::to_string(K) + ") array of vertex indices");
  std::vector<std::array<mesh::Index, K>> out(static_cast<std::size_t>(a.shape(0)));
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    for (std::size_t k = 0; k < K; ++k) {
      const std::int64_t index = r(i, static_cast<py::ssize_t>(k));
      if (index < 0 || static_cast<std::size_t>(index) >= vertices)
        throw py::index_error(std::string(what) + " row " + std::to_string(i) + " names vertex " + std::to_string(index) +
                              " of " + std::to_string(vertices));
      out[static_cast<std::size_t>(i)][k] = static_cast<mesh::Index>(index);
    }
  return out;
}

void write(const std::filesystem::path& path, const py::object& vertices, const py::object& tets,
           const py::object& triangles, const py::object& regions, bool binary, int msh_version) {
  mesh::WriteOptions options;
  options.binary = binary;
  options.msh_version = msh_version;
  const std::vector<Vec3> points = points_of(vertices.cast<py::array_t<double, py::array::c_style | py::array::forcecast>>());
  if (tets.is_none() == triangles.is_none()) throw py::value_error("give either tets (a volume) or triangles (a surface)");
  if (!tets.is_none()) {
    mesh::TetMesh m;
    m.vertices = points;
    m.tets = cells_of<4>(tets.cast<py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>>(), points.size(), "tets");
    for (std::size_t t = 0; t < m.tets.size(); ++t)
      if (!(m.tet_volume(t) > 0.0))
        throw py::value_error("tet " + std::to_string(t) + " is inverted or flat (signed volume " +
                              std::to_string(m.tet_volume(t)) + " m^3): tets are positively oriented");
    if (!regions.is_none()) {
      m.tet_regions = regions.cast<std::vector<int>>();
      if (m.tet_regions.size() != m.tets.size())
        throw py::value_error(std::to_string(m.tet_regions.size()) + " regions for " + std::to_string(m.tets.size()) + " tets");
    }
    py::gil_scoped_release release;
    mesh::write_mesh(path, m, options);
    return;
  }
  if (!regions.is_none()) throw py::value_error("regions label tets; a surface has none");
  mesh::TriMesh m;
  m.vertices = points;
  m.triangles = cells_of<3>(triangles.cast<py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>>(),
                            points.size(), "triangles");
  py::gil_scoped_release release;
  mesh::write_mesh(path, m, options);
}

}  // namespace

void bind_mesh(py::module_& m) {
  m.def("read_mesh", &read, py::arg("path"),
        "Reads a mesh file (.obj .stl .off .ply .msh .node/.ele/.face .vtk .vtu; the format from the\n"
        "extension) with the engine's readers. Returns a dict: format, skipped (what the reader left\n"
        "out), flipped_tets, surface (None or {vertices (n, 3) [m], triangles (m, 3) int32}) and volume\n"
        "(None or {vertices, tets (m, 4) int32, regions (m,) or None, faces, face_markers or None}).\n"
        "The arrays are read-only views of the mesh the reader built, kept alive by each array.\n"
        "A bad file raises InputError with its file, line (or byte offset) and reason.");
  m.def("write_mesh", &write, py::arg("path"), py::arg("vertices"), py::arg("tets") = py::none(),
        py::arg("triangles") = py::none(), py::arg("regions") = py::none(), py::arg("binary") = false,
        py::arg("msh_version") = 41,
        "Writes a volume (tets, optional regions per tet) or a surface (triangles) in the format of\n"
        "the extension: vertices (n, 3) [m], cells as vertex indices. binary: STL and PLY; msh_version:\n"
        "22 or 41. Tets must be positively oriented. Raises ValueError or IndexError for bad arrays and\n"
        "InputError where the file cannot be written.");
}

}  // namespace tactus::python
