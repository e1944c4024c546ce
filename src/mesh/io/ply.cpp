// PLY, ASCII and binary little endian. The header declares elements and their
// properties; "vertex" must have x, y, z (any numeric type; other properties are read and
// skipped), "face" a list named vertex_indices (or vertex_index) of any integer types.
// Other elements are skipped property by property. Polygons are fan-triangulated.
// binary_big_endian is rejected.
#include <cmath>
#include <limits>

#include "core/text.hpp"
#include "mesh/io/io_common.hpp"

namespace tactus::mesh::io {

namespace {

enum class Type { i8, u8, i16, u16, i32, u32, f32, f64 };

struct TypeInfo {
  const char* name;
  Type type;
};
constexpr TypeInfo type_names[] = {
    {"char", Type::i8},    {"int8", Type::i8},     {"uchar", Type::u8},   {"uint8", Type::u8},
    {"short", Type::i16},  {"int16", Type::i16},   {"ushort", Type::u16}, {"uint16", Type::u16},
    {"int", Type::i32},    {"int32", Type::i32},   {"uint", Type::u32},   {"uint32", Type::u32},
    {"float", Type::f32},  {"float32", Type::f32}, {"double", Type::f64}, {"float64", Type::f64}};

std::size_t size_of(Type t) {
  switch (t) {
    case Type::i8:
    case Type::u8: return 1;
    case Type::i16:
    case Type::u16: return 2;
    case Type::i32:
    case Type::u32:
    case Type::f32: return 4;
    case Type::f64: return 8;
  }
  return 1;
}
bool is_integer(Type t) { return t != Type::f32 && t != Type::f64; }

struct Property {
  std::string name;
  Type type{};
  bool list = false;
  Type count_type{};
};

struct Element {
  std::string name;
  std::int64_t count = 0;
  std::vector<Property> props;
  std::uint64_t header_line = 0;
};

// A source of PLY scalars: whitespace-separated text, or little-endian bytes.
class AsciiSource {
 public:
  explicit AsciiSource(LineReader& in) : in_(in) {}
  std::string_view token(const std::string& context) {
    while (next_ >= tokens_.size()) {
      std::string_view line;
      if (!in_.next(line)) in_.fail("truncated file: end of file while reading " + context);
      tokens_ = text::split(line);
      next_ = 0;
    }
    return tokens_[next_++];
  }
  double real(Type t, const std::string& context) {
    const auto tok = token(context);
    if (is_integer(t)) return static_cast<double>(integer_of(tok, t));
    return in_.to_double(tok);
  }
  std::int64_t integer(Type t, const std::string& context) {
    const auto tok = token(context);
    if (!is_integer(t)) in_.fail_at(tok, context + ": property is not of an integer type");
    return integer_of(tok, t);
  }
  double coordinate(Type t, const std::string& context) {
    const auto tok = token(context);
    if (is_integer(t)) return static_cast<double>(integer_of(tok, t));
    return in_.coordinate(tok);
  }
  [[noreturn]] void fail(const std::string& reason) const { in_.fail(reason); }
  [[nodiscard]] std::size_t remaining() const { return in_.remaining(); }

 private:
  std::int64_t integer_of(std::string_view tok, Type t) const {
    const std::int64_t v = in_.to_int(tok);
    std::int64_t lo = 0, hi = 0;
    switch (t) {
      case Type::i8: lo = INT8_MIN, hi = INT8_MAX; break;
      case Type::u8: lo = 0, hi = UINT8_MAX; break;
      case Type::i16: lo = INT16_MIN, hi = INT16_MAX; break;
      case Type::u16: lo = 0, hi = UINT16_MAX; break;
      case Type::i32: lo = INT32_MIN, hi = INT32_MAX; break;
      default: lo = 0, hi = UINT32_MAX; break;
    }
    if (v < lo || v > hi) in_.fail_at(tok, "value " + std::to_string(v) + " does not fit the declared type");
    return v;
  }
  LineReader& in_;
  std::vector<std::string_view> tokens_;
  std::size_t next_ = 0;
};

class BinarySource {
 public:
  explicit BinarySource(ByteCursor& in) : in_(in) {}
  double real(Type t, const std::string& context) {
    switch (t) {
      case Type::f32: return in_.read<float>(context);
      case Type::f64: return in_.read<double>(context);
      default: return static_cast<double>(integer(t, context));
    }
  }
  std::int64_t integer(Type t, const std::string& context) {
    switch (t) {
      case Type::i8: return in_.read<std::int8_t>(context);
      case Type::u8: return in_.read<std::uint8_t>(context);
      case Type::i16: return in_.read<std::int16_t>(context);
      case Type::u16: return in_.read<std::uint16_t>(context);
      case Type::i32: return in_.read<std::int32_t>(context);
      case Type::u32: return in_.read<std::uint32_t>(context);
      default: in_.fail(context + ": property is not of an integer type");
    }
  }
  double coordinate(Type t, const std::string& context) {
    const std::size_t at = in_.pos();
    const double v = real(t, context);
    if (!std::isfinite(v)) in_.fail_at(at, context + ": coordinate is NaN or infinite");
    return v;
  }
  [[noreturn]] void fail(const std::string& reason) const { in_.fail(reason); }
  [[nodiscard]] std::size_t remaining() const { return in_.remaining(); }

 private:
  ByteCursor& in_;
};

std::size_t min_bytes(const Element& e, bool binary) {
  if (!binary) return 2 * e.props.size();
  std::size_t n = 0;
  for (const auto& p : e.props) n += p.list ? size_of(p.count_type) : size_of(p.type);
  return n;
}

template <class Source>
void read_body(Source& src, const std::vector<Element>& elements, bool binary, TriMesh& mesh) {
  std::vector<std::int64_t> polygon;
  for (const auto& e : elements) {
    if (e.props.empty()) continue;  // nothing to read, however large the count
    const bool is_vertex = e.name == "vertex";
    const bool is_face = e.name == "face";
    if (is_vertex) reserve_bounded(mesh.vertices, static_cast<std::uint64_t>(e.count), src.remaining(), min_bytes(e, binary));
    if (is_face) reserve_bounded(mesh.triangles, static_cast<std::uint64_t>(e.count), src.remaining(), min_bytes(e, binary));
    for (std::int64_t i = 0; i < e.count; ++i) {
      const std::string context = e.name + " " + std::to_string(i) + " of " + std::to_string(e.count);
      Vec3 p = Vec3::Zero();
      for (const auto& prop : e.props) {
        if (prop.list) {
          const std::int64_t k = src.integer(prop.count_type, context);
          if (k < 0) src.fail(context + ": negative list length " + std::to_string(k));
          const bool indices = is_face && (prop.name == "vertex_indices" || prop.name == "vertex_index");
          if (indices && k < 3) src.fail(context + " has " + std::to_string(k) + " vertices; needs at least 3");
          polygon.clear();
          for (std::int64_t j = 0; j < k; ++j) {
            if (!indices) {
              (void)src.real(prop.type, context);
              continue;
            }
            const std::int64_t v = src.integer(prop.type, context);
            if (v < 0 || v >= static_cast<std::int64_t>(mesh.vertices.size()))
              src.fail(context + ": vertex index " + std::to_string(v) + " out of range [0, " +
                       std::to_string(mesh.vertices.size()) + ")");
            polygon.push_back(v);
          }
          for (std::size_t j = 1; j + 1 < polygon.size(); ++j)
            mesh.triangles.push_back({static_cast<Index>(polygon[0]), static_cast<Index>(polygon[j]),
                                      static_cast<Index>(polygon[j + 1])});
        } else if (is_vertex && (prop.name == "x" || prop.name == "y" || prop.name == "z")) {
          p[prop.name[0] - 'x'] = src.coordinate(prop.type, context);
        } else {
          (void)src.real(prop.type, context);
        }
      }
      if (is_vertex) mesh.vertices.push_back(p);
    }
  }
}

}  // namespace

MeshFile parse_ply(std::string_view data, const std::string& file) {
  LineReader in(data, file);
  std::string_view line;
  if (!in.next(line) || text::trim(line) != "ply") in.fail("not a PLY file: first line must be 'ply'");
  bool binary = false;
  bool have_format = false;
  std::vector<Element> elements;
  for (;;) {
    if (!in.next(line)) in.fail("truncated file: end of file before 'end_header'");
    const auto tok = text::split(line);
    if (tok.empty()) continue;
    const auto key = tok[0];
    if (key == "comment" || key == "obj_info") continue;
    if (key == "end_header") break;
    if (key == "format") {
      if (tok.size() != 3) in.fail("expected 'format <ascii|binary_little_endian> 1.0'");
      if (tok[1] == "ascii") binary = false;
      else if (tok[1] == "binary_little_endian") binary = true;
      else if (tok[1] == "binary_big_endian")
        in.fail_at(tok[1], "binary_big_endian PLY is not supported; save as ASCII or binary_little_endian");
      else in.fail_at(tok[1], "unknown PLY format '" + quote(tok[1]) + "'");
      if (tok[2] != "1.0") in.fail_at(tok[2], "unsupported PLY version '" + quote(tok[2]) + "'");
      have_format = true;
    } else if (key == "element") {
      if (tok.size() != 3) in.fail("expected 'element <name> <count>'");
      Element e;
      e.name = std::string(tok[1]);
      e.count = in.count(tok[2], "element count");
      e.header_line = in.line();
      for (const auto& other : elements)
        if (other.name == e.name) in.fail_at(tok[1], "element '" + quote(tok[1]) + "' declared twice");
      elements.push_back(std::move(e));
    } else if (key == "property") {
      if (elements.empty()) in.fail("property before any element");
      auto type_of = [&](std::string_view name) {
        for (const auto& t : type_names)
          if (name == t.name) return t.type;
        in.fail_at(name, "unknown property type '" + quote(name) + "'");
      };
      Property p;
      if (tok.size() >= 2 && tok[1] == "list") {
        if (tok.size() != 5) in.fail("expected 'property list <count type> <item type> <name>'");
        p.list = true;
        p.count_type = type_of(tok[2]);
        p.type = type_of(tok[3]);
        if (!is_integer(p.count_type)) in.fail_at(tok[2], "list count type must be an integer type");
        p.name = std::string(tok[4]);
      } else {
        if (tok.size() != 3) in.fail("expected 'property <type> <name>'");
        p.type = type_of(tok[1]);
        p.name = std::string(tok[2]);
      }
      elements.back().props.push_back(std::move(p));
    } else {
      in.fail_at(key, "unknown keyword '" + quote(key) + "' in PLY header");
    }
  }
  if (!have_format) in.fail("PLY header has no 'format' line");
  // The header must declare what a mesh needs before any data is read.
  const Element* vertex = nullptr;
  const Element* face = nullptr;
  for (const auto& e : elements) {
    if (e.name == "vertex") vertex = &e;
    if (e.name == "face") face = &e;
  }
  if (!vertex) in.fail("PLY header declares no 'vertex' element");
  for (const char* axis : {"x", "y", "z"}) {
    bool found = false;
    for (const auto& p : vertex->props) found = found || (!p.list && p.name == axis);
    if (!found)
      throw InputError(SourceLocation{file, vertex->header_line, {}, {}},
                       std::string("vertex element has no property '") + axis + "'");
  }
  if (face) {
    bool found = false;
    for (const auto& p : face->props) {
      if (p.list && (p.name == "vertex_indices" || p.name == "vertex_index")) {
        if (!is_integer(p.type))
          throw InputError(SourceLocation{file, face->header_line, {}, {}}, "face vertex indices must be integers");
        found = true;
      }
    }
    if (!found)
      throw InputError(SourceLocation{file, face->header_line, {}, {}},
                       "face element has no list property 'vertex_indices'");
    if (vertex > face)
      throw InputError(SourceLocation{file, face->header_line, {}, {}},
                       "face element is declared before the vertex element");
  }
  TriMesh mesh;
  if (binary) {
    ByteCursor cursor(data, file, in.offset());
    BinarySource src(cursor);
    read_body(src, elements, true, mesh);
  } else {
    AsciiSource src(in);
    read_body(src, elements, false, mesh);
  }
  MeshFile out;
  out.format = MeshFormat::ply;
  out.surface = std::move(mesh);
  return out;
}

std::string format_ply(const TriMesh& mesh, bool binary) {
  std::string out = "ply\nformat ";
  out += binary ? "binary_little_endian" : "ascii";
  out += " 1.0\ncomment Tactus\nelement vertex ";
  put_int(out, static_cast<std::int64_t>(mesh.vertices.size()));
  out += "\nproperty double x\nproperty double y\nproperty double z\nelement face ";
  put_int(out, static_cast<std::int64_t>(mesh.triangles.size()));
  out += "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) {
      if (binary) {
        put_le(out, v[k]);
      } else {
        if (k) out += ' ';
        put_double(out, v[k]);
      }
    }
    if (!binary) out += '\n';
  }
  for (const auto& t : mesh.triangles) {
    if (binary) {
      put_le(out, std::uint8_t{3});
      for (const Index i : t) put_le(out, std::int32_t{i});
    } else {
      out += '3';
      for (const Index i : t) {
        out += ' ';
        put_int(out, i);
      }
      out += '\n';
    }
  }
  return out;
}

}  // namespace tactus::mesh::io
