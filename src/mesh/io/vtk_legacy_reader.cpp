// Reading legacy VTK files (.vtk): ASCII or BINARY (big endian), versions 2.0 to 5.1,
// DATASET UNSTRUCTURED_GRID (tetrahedra and triangles kept, other cells counted and left
// out) or POLYDATA (polygons fanned into triangles, triangle strips split). The region
// labels Tactus writes as cell data are read; other point and cell data, field data and
// metadata are skipped.
#include <charconv>
#include <map>

#include "mesh/io/io_common.hpp"

namespace tactus::mesh::io {
namespace {

/// Text lines, whitespace-separated tokens and big-endian binary blocks over one buffer.
/// Errors name the line in ASCII files and the byte offset in binary ones.
class VtkCursor {
 public:
  VtkCursor(std::string_view data, std::string file) : data_(data), file_(std::move(file)) {}

  bool binary = false;

  [[noreturn]] void fail(const std::string& reason) const {
    if (binary_seen_) throw InputError(SourceLocation{file_, {}, {}, pos_}, reason);
    throw InputError(SourceLocation{file_, last_line_, {}, {}}, reason);
  }
  [[nodiscard]] bool at_end() const { return pos_ >= data_.size(); }

  /// The next line (without '\n' and a trailing '\r'); empty at the end.
  std::string_view line() {
    const std::size_t end = std::min(data_.find('\n', pos_), data_.size());
    std::string_view l = data_.substr(pos_, end - pos_);
    last_line_ = line_;
    if (end < data_.size()) ++line_;
    pos_ = std::min(end + 1, data_.size());
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    return l;
  }
  /// The next line that holds a word; empty at the end.
  std::string_view content_line() {
    while (!at_end()) {
      const std::string_view l = line();
      if (std::any_of(l.begin(), l.end(), [](char c) { return !std::isspace(static_cast<unsigned char>(c)); })) return l;
    }
    return {};
  }
  /// The next whitespace-separated token (ASCII data); fails at the end.
  std::string_view token(const char* what) {
    while (pos_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[pos_]))) {
      if (data_[pos_] == '\n') ++line_;
      ++pos_;
    }
    last_line_ = line_;
    if (pos_ >= data_.size()) fail(std::string("truncated file: expected ") + what);
    const std::size_t start = pos_;
    while (pos_ < data_.size() && !std::isspace(static_cast<unsigned char>(data_[pos_]))) ++pos_;
    return data_.substr(start, pos_ - start);
  }
  double ascii_double(const char* what) {
    const std::string_view t = token(what);
    double v = 0.0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size() || !std::isfinite(v))
      fail(std::string("expected ") + what + ", got '" + quote(t) + "'");
    return v;
  }
  std::int64_t ascii_int(const char* what) {
    const std::string_view t = token(what);
    std::int64_t v = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size()) fail(std::string("expected ") + what + ", got '" + quote(t) + "'");
    return v;
  }
  /// A big-endian T (a 4- or 8-byte integer or floating point number).
  template <class T>
  T big_endian(const char* what) {
    binary_seen_ = true;
    if (data_.size() - pos_ < sizeof(T))
      fail(std::string("truncated file: ") + what + " needs " + std::to_string(sizeof(T)) + " bytes, only " +
           std::to_string(data_.size() - pos_) + " left");
    const T value = load_bytes<T>(data_.data() + pos_, std::endian::big);
    pos_ += sizeof(T);
    return value;
  }
  /// After a binary block: the newline that ends it, if there.
  void end_binary_block() {
    if (pos_ < data_.size() && data_[pos_] == '\n') ++pos_;
  }
  [[nodiscard]] std::size_t remaining() const { return data_.size() - pos_; }

 private:
  std::string_view data_;
  std::string file_;
  std::size_t pos_ = 0;
  std::uint64_t line_ = 1;       ///< the line the cursor is on
  std::uint64_t last_line_ = 1;  ///< the line of the last line or token read (where errors point)
  bool binary_seen_ = false;  ///< past the first binary block, lines no longer count
};

std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const std::size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

std::int64_t header_count(VtkCursor& in, std::string_view token, const char* what) {
  std::int64_t v = -1;
  const auto r = std::from_chars(token.data(), token.data() + token.size(), v);
  if (r.ec != std::errc() || r.ptr != token.data() + token.size() || v < 0 || v > 0x7fffffff)
    in.fail(std::string("expected ") + what + " (a count), got '" + quote(token) + "'");
  return v;
}

/// One number of a data array of `type` (VTK's names), ASCII or binary.
double number(VtkCursor& in, const std::string& type, const char* what) {
  if (!in.binary) return in.ascii_double(what);
  if (type == "FLOAT") {
    const float v = in.big_endian<float>(what);
    if (!std::isfinite(v)) in.fail(std::string(what) + " is not finite");
    return v;
  }
  if (type == "DOUBLE") {
    const double v = in.big_endian<double>(what);
    if (!std::isfinite(v)) in.fail(std::string(what) + " is not finite");
    return v;
  }
  if (type == "INT" || type == "VTKTYPEINT32") return in.big_endian<std::int32_t>(what);
  if (type == "VTKTYPEINT64" || type == "LONG" || type == "VTKIDTYPE") return static_cast<double>(in.big_endian<std::int64_t>(what));
  in.fail("unsupported data type '" + quote(type) + "' (float, double, int, vtktypeint32 or vtktypeint64)");
}

std::int64_t integer(VtkCursor& in, const std::string& type, const char* what) {
  if (!in.binary) return in.ascii_int(what);
  if (type == "INT" || type == "VTKTYPEINT32") return in.big_endian<std::int32_t>(what);
  if (type == "VTKTYPEINT64" || type == "LONG" || type == "VTKIDTYPE") return in.big_endian<std::int64_t>(what);
  in.fail("unsupported index type '" + quote(type) + "' (int, vtktypeint32 or vtktypeint64)");
}

/// Cells as lists of point indices: the legacy layout (count, then indices, per cell) or,
/// from version 5.1, OFFSETS and CONNECTIVITY arrays.
std::vector<std::vector<std::int64_t>> read_cells(VtkCursor& in, const std::vector<std::string_view>& header,
                                                  const char* keyword) {
  if (header.size() != 3) in.fail(std::string(keyword) + " needs two counts");
  const std::int64_t first = header_count(in, header[1], "the number of cells");
  const std::int64_t second = header_count(in, header[2], "the size of the cell list");
  std::vector<std::vector<std::int64_t>> cells;
  // Version 5.1 announces its arrays on the next line ("OFFSETS <type>"); the legacy layout
  // starts with numbers.
  VtkCursor probe = in;
  const std::vector<std::string_view> next = words(probe.content_line());
  if (!next.empty() && upper(next[0]) == "OFFSETS") {
    in = probe;
    if (next.size() != 2) in.fail("OFFSETS needs a data type");
    const std::string offset_type = upper(next[1]);
    // first = number of offsets (cells + 1), second = connectivity size.
    if (first < 1) in.fail(std::string(keyword) + ": 5.1 layout needs at least one offset");
    std::vector<std::int64_t> offsets;
    reserve_bounded(offsets, static_cast<std::uint64_t>(first), in.remaining(), 1);
    for (std::int64_t i = 0; i < first; ++i) offsets.push_back(integer(in, offset_type, "an offset"));
    if (in.binary) in.end_binary_block();
    const std::vector<std::string_view> conn = words(in.content_line());
    if (conn.size() != 2 || upper(conn[0]) != "CONNECTIVITY") in.fail("expected CONNECTIVITY <type> after the offsets");
    const std::string conn_type = upper(conn[1]);
    std::vector<std::int64_t> connectivity;
    reserve_bounded(connectivity, static_cast<std::uint64_t>(second), in.remaining(), 1);
    for (std::int64_t i = 0; i < second; ++i) connectivity.push_back(integer(in, conn_type, "a point index"));
    if (in.binary) in.end_binary_block();
    reserve_bounded(cells, static_cast<std::uint64_t>(first - 1), in.remaining() + 1, 1);
    for (std::int64_t c = 0; c + 1 < first; ++c) {
      const std::int64_t a = offsets[static_cast<std::size_t>(c)], b = offsets[static_cast<std::size_t>(c + 1)];
      if (a < 0 || b < a || b > second) in.fail("cell " + std::to_string(c) + "'s offsets " + std::to_string(a) + ".." +
                                               std::to_string(b) + " lie outside the connectivity (" +
                                               std::to_string(second) + ")");
      cells.emplace_back(connectivity.begin() + a, connectivity.begin() + b);
    }
    return cells;
  }
  // Legacy: `first` cells, `second` integers in all (each cell's count included).
  std::int64_t left = second;
  reserve_bounded(cells, static_cast<std::uint64_t>(first), in.remaining(), 2);
  for (std::int64_t c = 0; c < first; ++c) {
    const std::int64_t n = integer(in, "INT", "a cell's point count");
    if (n < 0 || n + 1 > left)
      in.fail("cell " + std::to_string(c) + " has " + std::to_string(n) + " points, more than the " +
              std::to_string(left) + " integers its header leaves");
    left -= n + 1;
    std::vector<std::int64_t> cell;
    cell.reserve(static_cast<std::size_t>(std::min<std::int64_t>(n, 64)));
    for (std::int64_t k = 0; k < n; ++k) cell.push_back(integer(in, "INT", "a point index"));
    cells.push_back(std::move(cell));
  }
  if (left != 0) in.fail(std::string(keyword) + " header says " + std::to_string(second) + " integers, the cells hold " +
                         std::to_string(second - left));
  if (in.binary) in.end_binary_block();
  return cells;
}

/// Skips a FIELD block: "FIELD <name> <arrays>", then per array "<name> <components>
/// <tuples> <type>" and its values.
void skip_field(VtkCursor& in, const std::vector<std::string_view>& header) {
  if (header.size() != 3) in.fail("FIELD needs a name and a number of arrays");
  const std::int64_t arrays = header_count(in, header[2], "the number of arrays");
  for (std::int64_t a = 0; a < arrays; ++a) {
    const std::vector<std::string_view> w = words(in.content_line());
    if (w.size() != 4) in.fail("a FIELD array needs '<name> <components> <tuples> <type>'");
    const std::int64_t values = header_count(in, w[1], "the number of components") * header_count(in, w[2], "the number of tuples");
    const std::string type = upper(w[3]);
    for (std::int64_t v = 0; v < values; ++v) (void)number(in, type, "a field value");
    if (in.binary) in.end_binary_block();
    VtkCursor probe = in;
    const std::vector<std::string_view> next = words(probe.content_line());
    if (!next.empty() && upper(next[0]) == "METADATA") {
      in = probe;
      while (!in.at_end() && in.line().find_first_not_of(" \t") != std::string_view::npos) {
      }
    }
  }
}

/// CELL_DATA: the integer scalars named "region" (what Tactus writes), one per cell, if
/// they come before any other attribute; reading stops at the first other one.
std::vector<std::int64_t> read_cell_regions(VtkCursor& in, const std::vector<std::string_view>& header) {
  if (header.size() != 2) in.fail("CELL_DATA needs a count");
  const std::int64_t n = header_count(in, header[1], "the number of cells");
  const std::vector<std::string_view> w = words(in.content_line());
  if (w.size() < 3 || w.size() > 4 || upper(w[0]) != "SCALARS" || w[1] != "region") return {};
  const std::string type = upper(w[2]);
  if (type != "INT" && type != "VTKTYPEINT32" && type != "VTKTYPEINT64" && type != "LONG") return {};
  if (w.size() == 4 && w[3] != "1") return {};
  const std::vector<std::string_view> table = words(in.content_line());
  if (table.empty() || upper(table[0]) != "LOOKUP_TABLE") in.fail("SCALARS needs a LOOKUP_TABLE line");
  std::vector<std::int64_t> regions;
  reserve_bounded(regions, static_cast<std::uint64_t>(n), in.remaining(), 2);
  for (std::int64_t c = 0; c < n; ++c) {
    const std::int64_t r = integer(in, type, "a region label");
    if (r < INT32_MIN || r > INT32_MAX) in.fail("region label " + std::to_string(r) + " out of range");
    regions.push_back(r);
  }
  return regions;
}

}  // namespace

MeshFile parse_vtk(std::string_view data, const std::string& file) {
  VtkCursor in(data, file);
  if (in.line().rfind("# vtk DataFile Version", 0) != 0)
    in.fail("not a legacy VTK file: the first line must be '# vtk DataFile Version x.y'");
  (void)in.line();  // the title
  const std::vector<std::string_view> encoding = words(in.content_line());
  if (encoding.size() != 1 || (upper(encoding[0]) != "ASCII" && upper(encoding[0]) != "BINARY"))
    in.fail("the third line must be ASCII or BINARY");
  in.binary = upper(encoding[0]) == "BINARY";
  const std::vector<std::string_view> dataset = words(in.content_line());
  if (dataset.size() != 2 || upper(dataset[0]) != "DATASET") in.fail("expected 'DATASET <type>'");
  const std::string kind = upper(dataset[1]);
  if (kind != "UNSTRUCTURED_GRID" && kind != "POLYDATA")
    in.fail("DATASET " + quote(dataset[1]) + " holds no cells to read; UNSTRUCTURED_GRID and POLYDATA are read");

  std::vector<Vec3> points;
  bool have_points = false;
  std::vector<std::vector<std::int64_t>> cells;   // UNSTRUCTURED_GRID
  std::vector<std::int64_t> types;
  std::vector<std::vector<std::int64_t>> polygons, strips;  // POLYDATA
  std::vector<std::int64_t> regions;  // per cell, from CELL_DATA "region"
  std::map<std::string, std::size_t> skipped;  // cells left out, by kind
  for (std::string_view l = in.content_line(); !l.empty(); l = in.content_line()) {
    const std::vector<std::string_view> w = words(l);
    const std::string key = upper(w[0]);
    if (key == "CELL_DATA" && kind == "UNSTRUCTURED_GRID") {
      regions = read_cell_regions(in, w);
      break;  // attributes: nothing of the mesh follows
    }
    if (key == "POINT_DATA" || key == "CELL_DATA") break;
    if (key == "POINTS") {
      if (w.size() != 3) in.fail("POINTS needs a count and a data type");
      const std::int64_t n = header_count(in, w[1], "the number of points");
      const std::string type = upper(w[2]);
      reserve_bounded(points, static_cast<std::uint64_t>(n), in.remaining(), in.binary ? 12 : 6);
      for (std::int64_t i = 0; i < n; ++i) {
        Vec3 p;
        for (int k = 0; k < 3; ++k) p[k] = number(in, type, "a coordinate");
        points.push_back(p);
      }
      if (in.binary) in.end_binary_block();
      have_points = true;
    } else if (key == "CELLS" && kind == "UNSTRUCTURED_GRID") {
      cells = read_cells(in, w, "CELLS");
    } else if (key == "CELL_TYPES" && kind == "UNSTRUCTURED_GRID") {
      if (w.size() != 2) in.fail("CELL_TYPES needs a count");
      const std::int64_t n = header_count(in, w[1], "the number of cell types");
      reserve_bounded(types, static_cast<std::uint64_t>(n), in.remaining(), 2);
      for (std::int64_t i = 0; i < n; ++i) types.push_back(integer(in, "INT", "a cell type"));
      if (in.binary) in.end_binary_block();
    } else if (key == "POLYGONS" && kind == "POLYDATA") {
      polygons = read_cells(in, w, "POLYGONS");
    } else if (key == "TRIANGLE_STRIPS" && kind == "POLYDATA") {
      strips = read_cells(in, w, "TRIANGLE_STRIPS");
    } else if ((key == "VERTICES" || key == "LINES") && kind == "POLYDATA") {
      skipped[key == "VERTICES" ? "vertices" : "lines"] += read_cells(in, w, key.c_str()).size();
    } else if (key == "METADATA") {
      // Key-value blocks VTK 8 and later write after an array, ended by a blank line.
      while (!in.at_end() && in.line().find_first_not_of(" 	") != std::string_view::npos) {
      }
    } else if (key == "FIELD") {
      skip_field(in, w);  // dataset field data (a time, a cycle): no cells
    } else {
      in.fail("unexpected '" + quote(w[0]) + "' in a " + kind + " dataset");
    }
  }
  if (!have_points) in.fail("no POINTS section");
  const auto index = [&](std::int64_t i) {
    if (i < 0 || i >= static_cast<std::int64_t>(points.size()))
      in.fail("point index " + std::to_string(i) + " out of range (" + std::to_string(points.size()) + " points)");
    return static_cast<Index>(i);
  };

  TetMesh volume;
  TriMesh surface;
  if (kind == "UNSTRUCTURED_GRID") {
    if (cells.size() != types.size())
      in.fail(std::to_string(cells.size()) + " cells but " + std::to_string(types.size()) + " cell types");
    if (!regions.empty() && regions.size() != cells.size())
      in.fail(std::to_string(cells.size()) + " cells but " + std::to_string(regions.size()) + " region labels");
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const auto& cell = cells[c];
      if (types[c] == 10 && cell.size() == 4) {
        volume.tets.push_back({index(cell[0]), index(cell[1]), index(cell[2]), index(cell[3])});
        if (!regions.empty()) volume.tet_regions.push_back(static_cast<int>(regions[c]));
      } else if (types[c] == 5 && cell.size() == 3) {
        surface.triangles.push_back({index(cell[0]), index(cell[1]), index(cell[2])});
      } else if (types[c] == 10 || types[c] == 5) {
        in.fail("cell " + std::to_string(c) + " of type " + std::to_string(types[c]) + " has " +
                std::to_string(cell.size()) + " points");
      } else {
        const char* name = vtk_cell_name(types[c]);
        ++skipped[name ? std::string(name) : "cells of type " + std::to_string(types[c])];
      }
    }
  } else {
    for (const auto& polygon : polygons) {
      if (polygon.size() < 3) {
        ++skipped["degenerate polygons"];
        continue;
      }
      // Fanned from the first corner: exact for triangles, right for the convex polygons
      // surface meshes hold.
      for (std::size_t k = 1; k + 1 < polygon.size(); ++k)
        surface.triangles.push_back({index(polygon[0]), index(polygon[k]), index(polygon[k + 1])});
    }
    for (const auto& strip : strips)
      for (std::size_t k = 0; k + 2 < strip.size(); ++k) {
        // Every other triangle of a strip is wound the other way round.
        const Index a = index(strip[k]), b = index(strip[k + 1]), c = index(strip[k + 2]);
        if (k % 2 == 0) surface.triangles.push_back({a, b, c});
        else surface.triangles.push_back({b, a, c});
      }
  }
  if (volume.tets.empty() && surface.triangles.empty()) {
    std::string held;
    for (const auto& [name, count] : skipped) held += (held.empty() ? "" : ", ") + std::to_string(count) + " " + name;
    in.fail("no tetrahedra or triangles to read" + (held.empty() ? std::string() : " (the file holds " + held + ")"));
  }
  MeshFile out;
  out.format = MeshFormat::vtk;
  for (const auto& [name, count] : skipped)
    out.skipped += (out.skipped.empty() ? "" : ", ") + std::to_string(count) + " " + name;
  if (!volume.tets.empty()) {
    volume.vertices = points;
    out.flipped_tets = orient_whole_file(volume);
    out.volume = std::move(volume);
  }
  if (!surface.triangles.empty()) {
    surface.vertices = std::move(points);
    out.surface = std::move(surface);
  }
  return out;
}

}  // namespace tactus::mesh::io
