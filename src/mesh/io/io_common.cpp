#include "mesh/io/io_common.hpp"

#include "core/input_file.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>

#include "core/text.hpp"

namespace tactus::mesh::io {

std::string quote(std::string_view token) {
  constexpr std::size_t max_len = 32;
  std::string out;
  for (std::size_t i = 0; i < token.size() && i < max_len; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      static constexpr char hex[] = "0123456789abcdef";
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  if (token.size() > max_len) out += "...";
  return out;
}

std::string read_file(const std::filesystem::path& path) { return read_input_file(path); }

void write_file(const std::filesystem::path& path, std::string_view data) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw InputError(SourceLocation{path.string(), {}, {}, {}}, "cannot open file for writing");
  out.write(data.data(), static_cast<std::streamsize>(data.size()));
  out.close();
  if (!out) throw InputError(SourceLocation{path.string(), {}, {}, {}}, "error while writing file");
}

bool LineReader::next(std::string_view& line) {
  if (pos_ >= data_.size()) return false;
  const auto end = data_.find('\n', pos_);
  const std::size_t stop = end == std::string_view::npos ? data_.size() : end;
  current_start_ = pos_;
  line = data_.substr(pos_, stop - pos_);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  pos_ = end == std::string_view::npos ? data_.size() : end + 1;
  ++line_no_;
  current_ = line;
  return true;
}

bool LineReader::next_content(std::string_view& line, char comment) {
  while (next(line)) {
    const auto t = text::trim(line);
    if (t.empty()) continue;
    if (comment != 0 && t.front() == comment) continue;
    return true;
  }
  return false;
}

void LineReader::seek(std::size_t pos) {
  pos = std::min(pos, data_.size());
  if (pos > pos_) line_no_ += static_cast<std::uint64_t>(std::count(data_.begin() + static_cast<std::ptrdiff_t>(pos_),
                                                                      data_.begin() + static_cast<std::ptrdiff_t>(pos), '\n'));
  pos_ = pos;
}

void LineReader::fail(const std::string& reason) const {
  if (byte_offsets_) throw InputError(SourceLocation{file_, {}, {}, current_start_}, reason);
  throw InputError(SourceLocation{file_, line_no_ == 0 ? std::optional<std::uint64_t>{1} : line_no_, {}, {}},
                   reason);
}

void LineReader::fail_at(std::string_view token, const std::string& reason) const {
  std::optional<std::uint64_t> column;
  if (token.data() >= current_.data() && token.data() <= current_.data() + current_.size())
    column = static_cast<std::uint64_t>(token.data() - current_.data()) + 1;
  if (byte_offsets_)
    throw InputError(SourceLocation{file_, {}, {}, current_start_ + (column ? *column - 1 : 0)}, reason);
  throw InputError(SourceLocation{file_, line_no_, column, {}}, reason);
}

double LineReader::to_double(std::string_view token, const char* what) const {
  const auto v = text::to_double(token);
  if (!v) fail_at(token, std::string("expected ") + what + ", got '" + quote(token) + "'");
  return *v;
}

double LineReader::coordinate(std::string_view token) const {
  const double v = to_double(token, "a coordinate");
  if (!std::isfinite(v)) fail_at(token, "coordinate is NaN or infinite: '" + quote(token) + "'");
  return v;
}

std::int64_t LineReader::to_int(std::string_view token, const char* what) const {
  const auto v = text::to_int(token);
  if (!v) fail_at(token, std::string("expected ") + what + ", got '" + quote(token) + "'");
  return *v;
}

std::int64_t LineReader::count(std::string_view token, const char* what) const {
  const auto v = text::to_int(token);
  if (!v) fail_at(token, std::string("expected ") + what + " (a count), got '" + quote(token) + "'");
  if (*v < 0) fail_at(token, std::string("negative ") + what + ": " + std::to_string(*v));
  if (*v > INT32_MAX) fail_at(token, std::string(what) + " too large: " + std::to_string(*v));
  return *v;
}

void ByteCursor::fail_at(std::size_t offset, const std::string& reason) const {
  throw InputError(SourceLocation{file_, {}, {}, offset}, reason);
}

void put_double(std::string& out, double value) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, value);
  out.append(buf, r.ptr);
}

void put_int(std::string& out, std::int64_t value) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, value);
  out.append(buf, r.ptr);
}

const char* vtk_cell_name(std::int64_t type) {
  switch (type) {
    case 1: return "vertices";
    case 2: return "poly-vertices";
    case 3: return "lines";
    case 4: return "polylines";
    case 6: return "triangle strips";
    case 7: return "polygons";
    case 8: return "pixels";
    case 9: return "quads";
    case 11: return "voxels";
    case 12: return "hexahedra";
    case 13: return "wedges";
    case 14: return "pyramids";
    case 21: return "quadratic edges";
    case 22: return "quadratic triangles";
    case 23: return "quadratic quads";
    case 24: return "quadratic tetrahedra";
    case 25: return "quadratic hexahedra";
    case 42: return "polyhedra";
    default: return nullptr;
  }
}

std::size_t orient_whole_file(TetMesh& mesh) {
  bool any_negative = false;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const double v = mesh.tet_volume(t);
    if (v > 0.0) return 0;
    if (v < 0.0) any_negative = true;
  }
  if (!any_negative) return 0;
  for (auto& tet : mesh.tets) std::swap(tet[2], tet[3]);
  return mesh.tets.size();
}

std::string skipped_summary(const std::map<std::string, std::size_t>& skipped) {
  std::string out;
  for (const auto& [name, count] : skipped) {
    if (!out.empty()) out.append(", ");
    out.append(std::to_string(count)).append(" ").append(name);
  }
  return out;
}

MeshFile cell_mesh_file(MeshFormat format, std::vector<Vec3> points, TetMesh volume, TriMesh surface,
                        std::string skipped) {
  MeshFile out;
  out.format = format;
  out.skipped = std::move(skipped);
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
