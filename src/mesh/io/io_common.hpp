#pragma once
// Helpers shared by the mesh readers and writers (internal to src/mesh/io): a line
// reader that counts lines, a binary cursor that knows its byte offset, bounded
// reservation for counts read from untrusted headers, and number formatting.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "mesh/io/mesh_io.hpp"

namespace tactus::mesh::io {

/// A token made safe to quote in a message: at most 32 characters, non-printable
/// bytes as `\xNN`.
std::string quote(std::string_view token);

/// Reads a whole file; throws InputError naming the file if it cannot be opened.
std::string read_file(const std::filesystem::path& path);
/// Writes a whole file; throws InputError if it cannot be written.
void write_file(const std::filesystem::path& path, std::string_view data);

/// Text split into lines; line numbers are 1-based. A trailing carriage return is dropped.
class LineReader {
 public:
  LineReader(std::string_view data, std::string file) : data_(data), file_(std::move(file)) {}

  /// The next line, or false at end of data.
  bool next(std::string_view& line);
  /// The next line that is neither blank nor a comment starting with `comment`
  /// (after leading blanks); `comment` 0 skips blank lines only.
  bool next_content(std::string_view& line, char comment);

  [[nodiscard]] std::uint64_t line() const { return line_no_; }
  [[nodiscard]] std::size_t remaining() const { return data_.size() - pos_; }
  /// Byte offset of the start of the next line.
  [[nodiscard]] std::size_t offset() const { return pos_; }
  [[nodiscard]] const std::string& file() const { return file_; }

  /// Moves to byte `pos` (past a binary block), counting the lines skipped.
  void seek(std::size_t pos);
  /// From now on errors name byte offsets rather than lines (a binary file's text parts).
  void report_byte_offsets() { byte_offsets_ = true; }

  [[noreturn]] void fail(const std::string& reason) const;
  /// Fails pointing at `token`, which must be a view into the current line.
  [[noreturn]] void fail_at(std::string_view token, const std::string& reason) const;

  /// Strict numbers: "expected <what>, got '<token>'".
  [[nodiscard]] double to_double(std::string_view token, const char* what = "a number") const;
  /// A finite coordinate; NaN or infinity is an error.
  [[nodiscard]] double coordinate(std::string_view token) const;
  [[nodiscard]] std::int64_t to_int(std::string_view token, const char* what = "an integer") const;
  /// A count in [0, 2^31 - 1].
  [[nodiscard]] std::int64_t count(std::string_view token, const char* what) const;

 private:
  std::string_view data_;
  std::string file_;
  std::size_t pos_ = 0;
  std::uint64_t line_no_ = 0;
  std::string_view current_;
  std::size_t current_start_ = 0;  ///< byte offset of the current line
  bool byte_offsets_ = false;
};

/// A T from its bytes at `p`, stored in byte order `order`.
template <class T>
T load_bytes(const char* p, std::endian order) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  if (order != std::endian::native) std::reverse(bytes, bytes + sizeof(T));
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

/// Appends `value`'s bytes in byte order `order`.
template <class T>
void append_bytes(std::string& out, T value, std::endian order) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if (order != std::endian::native) std::reverse(bytes, bytes + sizeof(T));
  out.append(reinterpret_cast<const char*>(bytes), sizeof(T));
}

/// Reads from a byte buffer (little endian unless told otherwise); every failure names
/// the byte offset.
class ByteCursor {
 public:
  ByteCursor(std::string_view data, std::string file, std::size_t pos = 0,
             std::endian order = std::endian::little)
      : data_(data), file_(std::move(file)), pos_(pos), order_(order) {}

  [[nodiscard]] std::size_t pos() const { return pos_; }
  [[nodiscard]] std::size_t remaining() const { return data_.size() - pos_; }
  [[nodiscard]] const std::string& file() const { return file_; }

  [[noreturn]] void fail(const std::string& reason) const { fail_at(pos_, reason); }
  [[noreturn]] void fail_at(std::size_t offset, const std::string& reason) const;

  /// Throws "truncated file: ..." unless `n` more bytes are there.
  void need(std::size_t n, const std::string& context) const {
    if (remaining() < n)
      fail("truncated file: " + context + " needs " + std::to_string(n) + " bytes, only " +
           std::to_string(remaining()) + " left");
  }

  template <class T>
  T read(const std::string& context) {
    need(sizeof(T), context);
    const T value = load_bytes<T>(data_.data() + pos_, order_);
    pos_ += sizeof(T);
    return value;
  }
  void skip(std::size_t n, const std::string& context) {
    need(n, context);
    pos_ += n;
  }

 private:
  std::string_view data_;
  std::string file_;
  std::size_t pos_;
  std::endian order_;
};

/// Appends `value` little endian.
template <class T>
void put_le(std::string& out, T value) {
  append_bytes(out, value, std::endian::little);
}

/// Shortest text that reads back to exactly `value`.
void put_double(std::string& out, double value);
void put_int(std::string& out, std::int64_t value);

/// A header's count must not decide an allocation: reserve no more than the bytes left
/// could possibly describe.
template <class T>
void reserve_bounded(std::vector<T>& v, std::uint64_t count, std::size_t bytes_left,
                     std::size_t min_bytes_each) {
  const std::uint64_t cap = bytes_left / std::max<std::size_t>(min_bytes_each, 1) + 1;
  v.reserve(static_cast<std::size_t>(std::min(count, cap)));
}

/// TetMesh wants positive tets. A file whose tets are all negative follows the opposite
/// convention, so all are flipped (swapping the last two vertices); a file with a mix is
/// left as it is so that validate() can report the inverted ones. Returns how many were
/// flipped (all or none).
std::size_t orient_whole_file(TetMesh& mesh);

/// What VTK's cell type `type` is called in plural ("quads"), or null for one without a
/// name here; for the `skipped` summary of the VTK readers.
const char* vtk_cell_name(std::int64_t type);

/// "1942 lines, 12 quads": what a VTK reader left out, by kind.
std::string skipped_summary(const std::map<std::string, std::size_t>& skipped);

/// A VTK file's cells as a MeshFile: its tetrahedra as the volume (oriented as a whole) and
/// its triangles as the surface, both on `points`; `skipped` from skipped_summary.
MeshFile cell_mesh_file(MeshFormat format, std::vector<Vec3> points, TetMesh volume, TriMesh surface,
                        std::string skipped);

/// Internal entry points working on memory; `file` names the source in errors.
MeshFile parse_obj(std::string_view data, const std::string& file);
MeshFile parse_stl(std::string_view data, const std::string& file);
MeshFile parse_off(std::string_view data, const std::string& file);
MeshFile parse_ply(std::string_view data, const std::string& file);
MeshFile parse_msh(std::string_view data, const std::string& file);
MeshFile parse_vtk(std::string_view data, const std::string& file);
MeshFile parse_vtu(std::string_view data, const std::string& file);
/// TetGen: `ele` or `face` may be absent (nullptr). Without .ele the result is a surface
/// from .face.
MeshFile parse_tetgen(std::string_view node, const std::string& node_file, const std::string_view* ele,
                      const std::string& ele_file, const std::string_view* face,
                      const std::string& face_file);

std::string format_obj(const TriMesh& mesh);
std::string format_stl(const TriMesh& mesh, bool binary);
std::string format_off(const TriMesh& mesh);
std::string format_ply(const TriMesh& mesh, bool binary);
/// Either mesh may be null; a volume writes its labelled faces as triangles.
std::string format_msh(const TriMesh* surface, const TetMesh* volume, int version);
struct TetGenText {
  std::string node, ele, face;  ///< face empty when there is nothing to write
};
TetGenText format_tetgen(const TetMesh& mesh);
std::string format_tetgen_node(const std::vector<Vec3>& vertices);
std::string format_tetgen_face(const std::vector<Triangle>& faces, const std::vector<int>& markers);
std::string format_vtk(const std::vector<Vec3>& vertices, const std::vector<Index>& cells, int nodes_per_cell,
                       const std::vector<int>* labels);
/// nodes_per_cell 1 (points), 3 or 4; `fields`, when given, its point and cell arrays
/// (not together with labels).
std::string format_vtu(const std::vector<Vec3>& vertices, const std::vector<Index>& cells, int nodes_per_cell,
                       const std::vector<int>* labels, const VtuFields* fields = nullptr);

}  // namespace tactus::mesh::io
