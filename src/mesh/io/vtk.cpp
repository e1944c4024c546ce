// VTK output for viewing (ParaView): legacy ASCII .vtk and XML .vtu, both an
// unstructured grid of triangles (cell type 5) or tetrahedra (cell type 10), with the
// region labels as cell data when there are any; .vtu also of points (cell type 1) with
// named point and cell arrays (a run's time series, `tactus run --vtk`).
#include <fmt/format.h>

#include "mesh/io/io_common.hpp"

namespace tactus::mesh::io {

namespace {

int cell_type(int nodes_per_cell) { return nodes_per_cell == 1 ? 1 : nodes_per_cell == 3 ? 5 : 10; }

void put_points(std::string& out, const std::vector<Vec3>& vertices) {
  for (const auto& v : vertices) {
    for (int k = 0; k < 3; ++k) {
      if (k) out += ' ';
      put_double(out, v[k]);
    }
    out += '\n';
  }
}

}  // namespace

std::string format_vtk(const std::vector<Vec3>& vertices, const std::vector<Index>& cells, int nodes_per_cell,
                       const std::vector<int>* labels) {
  const auto per = static_cast<std::size_t>(nodes_per_cell);
  const std::size_t m = cells.size() / per;
  std::string out = "# vtk DataFile Version 3.0\nTactus mesh\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS ";
  out += std::to_string(vertices.size()) + " double\n";
  put_points(out, vertices);
  out += "CELLS " + std::to_string(m) + ' ' + std::to_string(m * (per + 1)) + '\n';
  for (std::size_t c = 0; c < m; ++c) {
    out += std::to_string(per);
    for (std::size_t k = 0; k < per; ++k) {
      out += ' ';
      put_int(out, cells[c * per + k]);
    }
    out += '\n';
  }
  out += "CELL_TYPES " + std::to_string(m) + '\n';
  for (std::size_t c = 0; c < m; ++c) out += std::to_string(cell_type(nodes_per_cell)) + '\n';
  if (labels) {
    out += "CELL_DATA " + std::to_string(m) + "\nSCALARS region int 1\nLOOKUP_TABLE default\n";
    for (const int l : *labels) out += std::to_string(l) + '\n';
  }
  return out;
}

void put_arrays(std::string& out, const char* section, const std::vector<VtuArray>& arrays) {
  if (arrays.empty()) return;
  out += fmt::format("<{}>\n", section);
  for (const VtuArray& a : arrays) {
    out += fmt::format("<DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">\n", a.name,
                       a.components);
    const auto per = static_cast<std::size_t>(std::max(a.components, 1));
    for (std::size_t i = 0; i < a.values.size(); ++i) {
      put_double(out, a.values[i]);
      out += (i + 1) % per == 0 ? '\n' : ' ';
    }
    out += "</DataArray>\n";
  }
  out += fmt::format("</{}>\n", section);
}

std::string format_vtu(const std::vector<Vec3>& vertices, const std::vector<Index>& cells, int nodes_per_cell,
                       const std::vector<int>* labels, const VtuFields* fields) {
  const auto per = static_cast<std::size_t>(nodes_per_cell);
  const std::size_t m = cells.size() / per;
  std::string out =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "<UnstructuredGrid>\n<Piece NumberOfPoints=\"";
  out += std::to_string(vertices.size()) + "\" NumberOfCells=\"" + std::to_string(m) + "\">\n";
  out += "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  put_points(out, vertices);
  out += "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (std::size_t c = 0; c < m; ++c) {
    for (std::size_t k = 0; k < per; ++k) {
      if (k) out += ' ';
      put_int(out, cells[c * per + k]);
    }
    out += '\n';
  }
  out += "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t c = 1; c <= m; ++c) out += std::to_string(c * per) + '\n';
  out += "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t c = 0; c < m; ++c) out += std::to_string(cell_type(nodes_per_cell)) + '\n';
  out += "</DataArray>\n</Cells>\n";
  if (fields) {
    put_arrays(out, "PointData", fields->point_data);
    put_arrays(out, "CellData", fields->cell_data);
  }
  if (labels) {
    out += "<CellData Scalars=\"region\">\n<DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n";
    for (const int l : *labels) out += std::to_string(l) + '\n';
    out += "</DataArray>\n</CellData>\n";
  }
  out += "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  return out;
}

}  // namespace tactus::mesh::io
