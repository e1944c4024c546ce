// NRRD label images: a text header ("NRRD000N", "field: value" lines, a blank line), then
// the voxels, raw or gzip, in the same file or a detached "data file".
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/input_file.hpp"
#include "imaging/label_image.hpp"
#include "imaging/voxel_data.hpp"

namespace tactus::imaging {
namespace {

struct Field {
  std::string value;
  std::uint64_t line = 0;
};

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return std::string(s);
}

class Reader {
 public:
  Reader(std::string file, std::map<std::string, Field> fields) : file_(std::move(file)), fields_(std::move(fields)) {}

  [[nodiscard]] const Field* find(const std::string& key) const {
    const auto it = fields_.find(key);
    return it == fields_.end() ? nullptr : &it->second;
  }
  const Field& need(const std::string& key) const {
    const Field* f = find(key);
    if (!f) throw InputError(SourceLocation{file_, {}, {}, {}}, "the header has no '" + key + "' field");
    return *f;
  }
  [[noreturn]] void fail(const Field& f, const std::string& reason) const {
    throw InputError(SourceLocation{file_, f.line, {}, {}}, reason);
  }
  /// Numbers separated by blanks, commas or parentheses; "none"/"nan" read as NaN.
  std::vector<double> numbers(const Field& f, const std::string& key) const {
    std::string s = f.value;
    for (char& c : s)
      if (c == ',' || c == '(' || c == ')') c = ' ';
    std::istringstream in(s);
    std::vector<double> out;
    std::string token;
    while (in >> token) {
      const std::string l = lower(token);
      if (l == "none" || l == "nan") {
        out.push_back(std::nan(""));
        continue;
      }
      char* end = nullptr;
      const double v = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0') fail(f, key + ": '" + token + "' is not a number");
      out.push_back(v);
    }
    return out;
  }

 private:
  std::string file_;
  std::map<std::string, Field> fields_;
};

detail::VoxelType voxel_type(const Reader& r) {
  const Field& f = r.need("type");
  static const std::map<std::string, detail::VoxelType> types = {
      {"uchar", detail::VoxelType::u8},          {"unsigned char", detail::VoxelType::u8},
      {"uint8", detail::VoxelType::u8},          {"uint8_t", detail::VoxelType::u8},
      {"signed char", detail::VoxelType::i8},    {"int8", detail::VoxelType::i8},
      {"int8_t", detail::VoxelType::i8},         {"short", detail::VoxelType::i16},
      {"short int", detail::VoxelType::i16},     {"signed short", detail::VoxelType::i16},
      {"signed short int", detail::VoxelType::i16}, {"int16", detail::VoxelType::i16},
      {"int16_t", detail::VoxelType::i16},       {"ushort", detail::VoxelType::u16},
      {"unsigned short", detail::VoxelType::u16}, {"unsigned short int", detail::VoxelType::u16},
      {"uint16", detail::VoxelType::u16},        {"uint16_t", detail::VoxelType::u16},
      {"int", detail::VoxelType::i32},           {"signed int", detail::VoxelType::i32},
      {"int32", detail::VoxelType::i32},         {"int32_t", detail::VoxelType::i32},
      {"uint", detail::VoxelType::u32},          {"unsigned int", detail::VoxelType::u32},
      {"uint32", detail::VoxelType::u32},        {"uint32_t", detail::VoxelType::u32},
      {"float", detail::VoxelType::f32},         {"double", detail::VoxelType::f64}};
  const auto it = types.find(lower(f.value));
  if (it == types.end()) r.fail(f, "type '" + f.value + "' is not supported for labels (8, 16, 32-bit integers, float, double)");
  return it->second;
}

}  // namespace

LabelImage read_nrrd(const std::filesystem::path& path) { return detail::parse_nrrd(read_input_file(path), path); }

LabelImage detail::parse_nrrd(std::string_view data, const std::filesystem::path& path) {
  const std::string file = path.string();
  if (data.compare(0, 4, "NRRD") != 0)
    throw InputError(SourceLocation{file, 1, {}, {}}, "the first line does not start with 'NRRD': not a NRRD file");

  std::map<std::string, Field> fields;
  std::size_t pos = 0;
  std::uint64_t line_no = 0;
  bool blank_seen = false;
  while (pos < data.size()) {
    const std::size_t eol = data.find('\n', pos);
    const std::string_view line(data.data() + pos, (eol == std::string::npos ? data.size() : eol) - pos);
    pos = eol == std::string::npos ? data.size() : eol + 1;
    ++line_no;
    if (line_no == 1) continue;
    const std::string text = trim(line);
    if (text.empty()) {
      blank_seen = true;
      break;
    }
    if (text[0] == '#') continue;
    if (text.find(":=") != std::string::npos) continue;  // key/value pairs: not needed
    const std::size_t colon = text.find(": ");
    if (colon == std::string::npos)
      throw InputError(SourceLocation{file, line_no, {}, {}}, "expected 'field: value'");
    fields[lower(text.substr(0, colon))] = Field{trim(std::string_view(text).substr(colon + 2)), line_no};
  }
  Reader r(file, fields);

  LabelImage image;
  image.source = file;
  const Field& dimension = r.need("dimension");
  if (r.numbers(dimension, "dimension") != std::vector<double>{3.0})
    r.fail(dimension, "dimension is " + dimension.value + "; a label image has 3");
  const Field& sizes = r.need("sizes");
  const auto n = r.numbers(sizes, "sizes");
  if (n.size() != 3) r.fail(sizes, "sizes: expected 3 numbers");
  for (int a = 0; a < 3; ++a) {
    if (!(n[a] >= 1.0 && n[a] <= 1e6 && n[a] == std::round(n[a])))
      r.fail(sizes, fmt::format("sizes: axis {} has {} voxels; it must be a positive integer", a + 1, n[a]));
    image.size[a] = static_cast<std::size_t>(n[a]);
  }
  const detail::VoxelType type = voxel_type(r);

  // Units: "space units" per axis; mm when absent (what imaging tools write).
  double unit = 1e-3;
  if (const Field* u = r.find("space units")) {
    std::string s = u->value;
    for (char& c : s)
      if (c == '"') c = ' ';
    std::istringstream in(s);
    std::string word, first;
    while (in >> word) {
      if (first.empty()) first = word;
      if (word != first) r.fail(*u, "space units: axes in different units are not supported");
    }
    if (first == "mm") unit = 1e-3;
    else if (first == "m") unit = 1.0;
    else if (first == "cm") unit = 1e-2;
    else if (first == "um" || first == "µm") unit = 1e-6;
    else r.fail(*u, "space units: '" + first + "' is not a length unit (m, cm, mm, um)");
  }

  Mat3 axes = Mat3::Identity();
  std::string where_spacing = "spacings";
  if (const Field* dirs = r.find("space directions")) {
    where_spacing = fmt::format("line {} (space directions)", dirs->line);
    const auto v = r.numbers(*dirs, "space directions");
    if (v.size() != 9) r.fail(*dirs, "space directions: expected three vectors of three numbers");
    for (int c = 0; c < 3; ++c)
      for (int row = 0; row < 3; ++row) axes(row, c) = v[3 * c + row];
    if (!axes.allFinite()) r.fail(*dirs, "space directions: a vector is 'none' or not finite");
    for (int c = 0; c < 3; ++c)
      if (!(axes.col(c).norm() > 0.0)) r.fail(*dirs, fmt::format("space directions: axis {} has zero length", c + 1));
  } else if (const Field* sp = r.find("spacings")) {
    const auto v = r.numbers(*sp, "spacings");
    if (v.size() != 3) r.fail(*sp, "spacings: expected 3 numbers");
    for (int a = 0; a < 3; ++a)
      if (!(std::isfinite(v[a]) && v[a] > 0.0))
        r.fail(*sp, fmt::format("spacings: axis {} has spacing {}; it must be finite and positive", a + 1, v[a]));
    axes = Vec3(v[0], v[1], v[2]).asDiagonal();
  }
  Vec3 origin = Vec3::Zero();
  if (const Field* o = r.find("space origin")) {
    const auto v = r.numbers(*o, "space origin");
    if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
      r.fail(*o, "space origin: expected three finite numbers");
    origin = Vec3(v[0], v[1], v[2]);
  }
  if (const Field* space = r.find("space")) {
    const std::string s = lower(space->value);
    if (s == "left-posterior-superior" || s == "lps") {
      axes.row(0) *= -1.0;  // LPS → RAS, the frame NIfTI uses
      axes.row(1) *= -1.0;
      origin[0] = -origin[0];
      origin[1] = -origin[1];
    } else if (s != "right-anterior-superior" && s != "ras" && s != "scanner-xyz" && s != "3d-right-handed") {
      r.fail(*space, "space '" + space->value + "' is not supported (RAS, LPS, scanner-xyz, 3D-right-handed)");
    }
  }
  for (int c = 0; c < 3; ++c) {
    image.spacing[c] = axes.col(c).norm() * unit;
    image.direction.col(c) = axes.col(c).normalized();
  }
  image.origin = origin * unit;
  detail::check_geometry(image, where_spacing);

  bool big_endian = false;
  if (const Field* e = r.find("endian")) {
    if (e->value == "big") big_endian = true;
    else if (e->value != "little") r.fail(*e, "endian: expected 'little' or 'big'");
  }
  const Field& encoding = r.need("encoding");
  const std::string enc = lower(encoding.value);
  if (enc != "raw" && enc != "gzip" && enc != "gz")
    r.fail(encoding, "encoding '" + encoding.value + "' is not supported (raw, gzip)");
  std::size_t byte_skip = 0;
  if (const Field* s = r.find("byte skip")) {
    const auto v = r.numbers(*s, "byte skip");
    if (v.size() != 1 || !(v[0] >= 0.0) || v[0] != std::round(v[0])) r.fail(*s, "byte skip: expected a count >= 0");
    byte_skip = static_cast<std::size_t>(v[0]);
  }

  std::string detached;
  std::string data_file = file;
  std::string_view payload;
  std::uint64_t payload_offset = 0;
  const Field* df = r.find("data file");
  if (!df) df = r.find("datafile");
  if (df) {
    const std::filesystem::path p = path.parent_path() / df->value;
    if (df->value == "LIST" || df->value.find('%') != std::string::npos)
      r.fail(*df, "data file: lists and patterns of files are not supported");
    detached = read_input_file(p);
    data_file = p.string();
    payload = detached;
  } else {
    if (!blank_seen)
      throw InputError(SourceLocation{file, {}, {}, data.size()}, "the header has no blank line before the data");
    payload = data.substr(pos);
    payload_offset = pos;
  }
  std::string inflated;
  if (enc != "raw") {
    inflated = detail::gunzip(payload, data_file, payload_offset);
    payload = inflated;
    payload_offset = 0;  // offsets in the inflated stream from here on
  }
  if (byte_skip > payload.size())
    throw InputError(SourceLocation{data_file, {}, {}, payload_offset + payload.size()},
                     fmt::format("byte skip {} is past the end of the data", byte_skip));
  image.labels = detail::decode_labels(payload.substr(byte_skip), type, big_endian, image.voxel_count(), data_file,
                                       payload_offset + byte_skip);
  return image;
}

void write_nrrd(const std::filesystem::path& path, const LabelImage& image, bool gzip) {
  const Mat3 axes_mm = image.direction * image.spacing.asDiagonal() * 1e3;
  const Vec3 o = image.origin * 1e3;
  std::string out = "NRRD0004\n# label image written by tactus\ntype: int\ndimension: 3\nspace: right-anterior-superior\n";
  out.append(fmt::format("sizes: {} {} {}\n", image.size[0], image.size[1], image.size[2]));
  out.append("space directions:");
  for (int c = 0; c < 3; ++c)
    out.append(fmt::format(" ({:.17g},{:.17g},{:.17g})", axes_mm(0, c), axes_mm(1, c), axes_mm(2, c)));
  out.append(fmt::format("\nspace origin: ({:.17g},{:.17g},{:.17g})\n", o[0], o[1], o[2]));
  out.append("space units: \"mm\" \"mm\" \"mm\"\nendian: little\n");
  out.append(gzip ? "encoding: gzip\n\n" : "encoding: raw\n\n");
  std::string voxels(reinterpret_cast<const char*>(image.labels.data()), image.labels.size() * 4);
  out.append(gzip ? detail::gzip(voxels) : voxels);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw InputError(SourceLocation{path.string(), {}, {}, {}}, "cannot write the file");
  const bool ok = std::fwrite(out.data(), 1, out.size(), f) == out.size();
  if (std::fclose(f) != 0 || !ok) throw InputError(SourceLocation{path.string(), {}, {}, {}}, "cannot write the file");
}

}  // namespace tactus::imaging
