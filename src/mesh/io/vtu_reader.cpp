// Reading VTK XML unstructured grids (.vtu) as ParaView, VTK and meshio write them. Data
// arrays may be inline (format "ascii", or "binary": base64) or in the AppendedData block
// (encoding "raw" or "base64"), zlib-compressed or not (vtkZLibDataCompressor), with UInt32
// or UInt64 headers, little or big endian. Tetrahedra (cell type 10) and triangles (5) are
// read, other cells counted in `skipped`; the integer cell data named "region" (what
// Tactus writes) becomes the tetrahedron regions, other point and cell data are skipped.
//
// Expat parses the XML but only records where each array's content lies; the contents are
// decoded from the file's own bytes afterwards, so that every error can name the line of a
// text value or the byte offset of binary data. Raw appended data is not XML, so expat is
// given the file without it.
#include <expat.h>
#include <zlib.h>

#include <bit>
#include <charconv>
#include <climits>
#include <cmath>
#include <deque>
#include <exception>
#include <map>
#include <memory>
#include <optional>
#include <type_traits>

#include "mesh/io/io_common.hpp"

namespace tactus::mesh::io {
namespace {

/// Where one DataArray's values are: inline between its tags, or at `offset` in the
/// appended data.
struct ArrayRef {
  std::string name, type, format;
  std::int64_t components = 1;
  std::optional<std::uint64_t> offset;
  std::size_t tag = 0;  ///< byte offset of "<DataArray" in the file (errors point here)
  std::size_t content_begin = 0, content_end = 0;
  bool content_ended = false;  ///< a child element or the end tag has closed the content
};

struct Piece {
  std::size_t tag = 0;
  std::int64_t points = 0, cells = 0;
  std::optional<ArrayRef> coords, connectivity, offsets, types, regions;
};

/// The number types VTK XML names, by size and kind.
struct ScalarType {
  std::size_t size = 0;
  bool is_float = false, is_signed = false;
};

std::optional<ScalarType> scalar_type(std::string_view name) {
  if (name == "Float32") return ScalarType{4, true, true};
  if (name == "Float64") return ScalarType{8, true, true};
  if (name == "Int8") return ScalarType{1, false, true};
  if (name == "UInt8") return ScalarType{1, false, false};
  if (name == "Int16") return ScalarType{2, false, true};
  if (name == "UInt16") return ScalarType{2, false, false};
  if (name == "Int32") return ScalarType{4, false, true};
  if (name == "UInt32") return ScalarType{4, false, false};
  if (name == "Int64") return ScalarType{8, false, true};
  if (name == "UInt64") return ScalarType{8, false, false};
  return std::nullopt;
}

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

class VtuReader {
 public:
  VtuReader(std::string_view data, const std::string& file) : data_(data), file_(file) {}

  MeshFile read() {
    parse_xml();
    if (!saw_root_) fail_line(0, "not a VTK XML file: no <VTKFile> element");
    if (pieces_.empty()) fail_line(0, "no <Piece> in the <UnstructuredGrid>");
    return build_mesh();
  }

 private:
  // ---- errors ----------------------------------------------------------------------

  [[noreturn]] void fail_line(std::size_t offset, const std::string& reason) const {
    offset = std::min(offset, data_.size());
    const auto line = 1 + static_cast<std::uint64_t>(std::count(data_.begin(), data_.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
    throw InputError(SourceLocation{file_, line, {}, {}}, reason);
  }
  [[noreturn]] void fail_byte(std::size_t offset, const std::string& reason) const {
    throw InputError(SourceLocation{file_, {}, {}, offset}, reason);
  }
  static std::string array_name(const ArrayRef& a) { return "DataArray '" + quote(a.name) + "'"; }

  // ---- XML ---------------------------------------------------------------------------

  /// The AppendedData block's bytes lie between its '_' and "</AppendedData>"; expat sees
  /// the file with them cut out.
  void parse_xml() {
    std::string_view before = data_, after;
    if (const std::size_t tag = data_.find("<AppendedData"); tag != std::string_view::npos) {
      const std::size_t close = data_.find('>', tag);
      if (close == std::string_view::npos) fail_byte(tag, "truncated file: the <AppendedData> tag does not end");
      std::size_t mark = close + 1;
      while (mark < data_.size() && is_space(data_[mark])) ++mark;
      if (mark >= data_.size() || data_[mark] != '_')
        fail_byte(mark, "appended data must start with '_' after the <AppendedData> tag");
      appended_begin_ = mark + 1;
      const std::size_t end = data_.rfind("</AppendedData>");
      if (end == std::string_view::npos || end < appended_begin_)
        fail_byte(appended_begin_, "truncated file: no '</AppendedData>' after the appended data");
      appended_end_ = end;
      has_appended_ = true;
      before = data_.substr(0, appended_begin_);
      after = data_.substr(end);
    }
    const std::unique_ptr<XML_ParserStruct, decltype(&XML_ParserFree)> parser(XML_ParserCreate(nullptr), XML_ParserFree);
    if (!parser) throw std::bad_alloc();
    parser_ = parser.get();
    XML_SetUserData(parser_, this);
    XML_SetElementHandler(parser_, &VtuReader::on_start, &VtuReader::on_end);
    XML_SetStartDoctypeDeclHandler(parser_, &VtuReader::on_doctype);
    feed(before, after.empty());
    if (!after.empty()) feed(after, true);
    parser_ = nullptr;
  }

  void feed(std::string_view part, bool final) {
    // XML_Parse takes an int length: large files go in pieces.
    constexpr std::size_t chunk = std::size_t{1} << 30;
    do {
      const std::size_t n = std::min(part.size(), chunk);
      const bool last = final && n == part.size();
      if (XML_Parse(parser_, part.data(), static_cast<int>(n), last ? XML_TRUE : XML_FALSE) != XML_STATUS_OK) {
        if (pending_) std::rethrow_exception(pending_);
        fail_line(file_offset(), std::string("malformed XML: ") + XML_ErrorString(XML_GetErrorCode(parser_)));
      }
      part.remove_prefix(n);
    } while (!part.empty());
  }

  /// The file offset of expat's current event (the appended bytes it never saw added back).
  [[nodiscard]] std::size_t file_offset() const {
    const auto at = static_cast<std::size_t>(std::max<XML_Index>(XML_GetCurrentByteIndex(parser_), 0));
    return has_appended_ && at >= appended_begin_ ? at + (appended_end_ - appended_begin_) : at;
  }

  // Expat is C: nothing may be thrown through it. A handler's error is kept, the parser
  // stopped, and the error thrown again once XML_Parse has returned.
  template <class F>
  static void guarded(void* self, F&& f) {
    auto* r = static_cast<VtuReader*>(self);
    if (r->pending_) return;
    try {
      f(*r);
    } catch (...) {
      r->pending_ = std::current_exception();
      XML_StopParser(r->parser_, XML_FALSE);
    }
  }
  static void XMLCALL on_start(void* self, const XML_Char* name, const XML_Char** attrs) {
    guarded(self, [&](VtuReader& r) { r.start_element(name, attrs); });
  }
  static void XMLCALL on_end(void* self, const XML_Char* name) {
    guarded(self, [&](VtuReader& r) { r.end_element(name); });
  }
  static void XMLCALL on_doctype(void* self, const XML_Char*, const XML_Char*, const XML_Char*, int) {
    // No DTD means no entity declarations to expand.
    guarded(self, [](VtuReader& r) { r.fail_line(r.file_offset(), "a DOCTYPE declaration is not allowed in a VTK XML file"); });
  }

  static std::optional<std::string_view> attribute(const XML_Char** attrs, std::string_view key) {
    for (; attrs[0]; attrs += 2)
      if (key == attrs[0]) return std::string_view(attrs[1]);
    return std::nullopt;
  }

  std::int64_t count_attribute(const XML_Char** attrs, std::string_view key, std::size_t at, bool required) const {
    const auto text = attribute(attrs, key);
    if (!text) {
      if (required) fail_line(at, "missing attribute " + std::string(key));
      return 0;
    }
    std::int64_t v = -1;
    const auto r = std::from_chars(text->data(), text->data() + text->size(), v);
    if (r.ec != std::errc() || r.ptr != text->data() + text->size() || v < 0 || v > INT32_MAX)
      fail_line(at, std::string(key) + " must be a count, got '" + quote(*text) + "'");
    return v;
  }

  void start_element(std::string_view name, const XML_Char** attrs) {
    const std::size_t at = file_offset();
    if (open_array_ && !open_array_->content_ended) {
      open_array_->content_end = at;  // a child element (InformationKey) ends the values
      open_array_->content_ended = true;
    }
    // A copy: the stack may reallocate below.
    const std::string parent = stack_.empty() ? std::string() : stack_.back();
    stack_.emplace_back(name);
    if (stack_.size() == 1) {
      if (name != "VTKFile") fail_line(at, "not a VTK XML file: the root element is <" + quote(name) + ">");
      read_file_attributes(attrs, at);
    } else if (name == "Piece" && parent == "UnstructuredGrid") {
      Piece& p = pieces_.emplace_back();
      p.tag = at;
      p.points = count_attribute(attrs, "NumberOfPoints", at, true);
      p.cells = count_attribute(attrs, "NumberOfCells", at, true);
    } else if (name == "DataArray" && !pieces_.empty() && stack_.size() >= 2) {
      open_array_ = slot_for(parent, attribute(attrs, "Name").value_or(""));
      if (open_array_) read_array_attributes(*open_array_, attrs, at);
    } else if (name == "AppendedData" && stack_.size() == 2) {
      const auto encoding = attribute(attrs, "encoding").value_or("");
      if (encoding != "raw" && encoding != "base64")
        fail_line(at, "AppendedData encoding must be 'raw' or 'base64', got '" + quote(encoding) + "'");
      appended_base64_ = encoding == "base64";
    }
  }

  void end_element(std::string_view name) {
    if (name == "DataArray" && open_array_) {
      if (!open_array_->content_ended) open_array_->content_end = std::max(file_offset(), open_array_->content_begin);
      open_array_ = nullptr;
    }
    if (!stack_.empty()) stack_.pop_back();
  }

  void read_file_attributes(const XML_Char** attrs, std::size_t at) {
    saw_root_ = true;
    const auto type = attribute(attrs, "type").value_or("");
    if (type != "UnstructuredGrid")
      fail_line(at, "VTK XML type '" + quote(type) + "' is not read; .vtu files hold an UnstructuredGrid");
    const auto order = attribute(attrs, "byte_order").value_or("LittleEndian");
    if (order == "BigEndian") order_ = std::endian::big;
    else if (order != "LittleEndian") fail_line(at, "byte_order must be LittleEndian or BigEndian, got '" + quote(order) + "'");
    const auto header = attribute(attrs, "header_type").value_or("UInt32");
    if (header == "UInt64") header_size_ = 8;
    else if (header != "UInt32") fail_line(at, "header_type must be UInt32 or UInt64, got '" + quote(header) + "'");
    const auto compressor = attribute(attrs, "compressor").value_or("");
    if (compressor == "vtkZLibDataCompressor") zlib_ = true;
    else if (!compressor.empty())
      fail_line(at, "compressor '" + quote(compressor) + "' is not supported (vtkZLibDataCompressor is)");
  }

  /// The arrays read, by where they are; every other array is left alone.
  ArrayRef* slot_for(std::string_view parent, std::string_view name) {
    Piece& p = pieces_.back();
    std::optional<ArrayRef>* slot = nullptr;
    if (parent == "Points" && !p.coords) slot = &p.coords;
    else if (parent == "Cells" && name == "connectivity") slot = &p.connectivity;
    else if (parent == "Cells" && name == "offsets") slot = &p.offsets;
    else if (parent == "Cells" && name == "types") slot = &p.types;
    else if (parent == "CellData" && name == "region") slot = &p.regions;
    if (!slot) return nullptr;
    if (slot->has_value()) fail_line(file_offset(), "a second <DataArray Name=\"" + quote(name) + "\"> in one piece");
    slot->emplace();
    (*slot)->name = name.empty() ? parent : name;  // VTK leaves the points array unnamed
    return &**slot;
  }

  void read_array_attributes(ArrayRef& a, const XML_Char** attrs, std::size_t at) {
    a.tag = at;
    a.content_begin = at + static_cast<std::size_t>(std::max(XML_GetCurrentByteCount(parser_), 0));
    a.content_end = a.content_begin;
    a.type = attribute(attrs, "type").value_or("");
    if (!scalar_type(a.type)) fail_line(at, array_name(a) + ": unknown type '" + quote(a.type) + "'");
    a.format = attribute(attrs, "format").value_or("");
    if (a.format != "ascii" && a.format != "binary" && a.format != "appended")
      fail_line(at, array_name(a) + ": format must be ascii, binary or appended, got '" + quote(a.format) + "'");
    if (attribute(attrs, "NumberOfComponents")) a.components = count_attribute(attrs, "NumberOfComponents", at, true);
    if (a.format == "appended") {
      const auto text = attribute(attrs, "offset");
      std::uint64_t v = 0;
      if (!text) fail_line(at, array_name(a) + ": an appended array needs an offset");
      const auto r = std::from_chars(text->data(), text->data() + text->size(), v);
      if (r.ec != std::errc() || r.ptr != text->data() + text->size())
        fail_line(at, array_name(a) + ": offset must be a number, got '" + quote(*text) + "'");
      a.offset = v;
    }
  }

  // ---- array contents -------------------------------------------------------------------

  /// Binary array bytes from the file: raw, or base64 text decoded as it is read. Both
  /// stop at `end`; base64 may be one stream or several (VTK encodes a compressed array's
  /// header apart from its data), so padding may end any 4-character group.
  class Payload {
   public:
    Payload(const VtuReader& r, std::size_t begin, std::size_t end, bool base64)
        : r_(r), pos_(begin), end_(end), base64_(base64) {}

    /// The next `n` bytes; `what` names them in the error if they are not there.
    std::string take(std::uint64_t n, const std::string& what) {
      // Checked before anything is allocated: 4 base64 characters hold at most 3 bytes.
      const std::uint64_t left = base64_ ? pending_.size() + (end_ - pos_) / 4 * 3 : end_ - pos_;
      if (n > left)
        r_.fail_byte(pos_, "truncated data: " + what + " needs " + std::to_string(n) + " bytes, at most " +
                               std::to_string(left) + " left");
      const auto size = static_cast<std::size_t>(n);
      if (!base64_) {
        std::string out(r_.data_.substr(pos_, size));
        pos_ += size;
        return out;
      }
      while (pending_.size() < size) decode_group(what);
      std::string out = pending_.substr(0, size);
      pending_.erase(0, size);
      return out;
    }
    [[nodiscard]] std::size_t pos() const { return pos_; }

   private:
    void decode_group(const std::string& what) {
      int values[4];
      int have = 0;
      std::size_t first = pos_;
      while (have < 4) {
        while (pos_ < end_ && is_space(r_.data_[pos_])) ++pos_;
        if (pos_ >= end_) r_.fail_byte(pos_, "truncated base64 data while reading " + what);
        if (have == 0) first = pos_;
        const char c = r_.data_[pos_];
        values[have] = c == '=' ? -2 : base64_value(c);
        if (values[have] == -1)
          r_.fail_byte(pos_, "invalid base64 character '" + quote(std::string_view(&c, 1)) + "' in " + what);
        ++pos_;
        ++have;
      }
      // '=' may only pad the end of a group: "xx==" or "xxx=".
      const int bytes = values[3] != -2 ? 3 : values[2] != -2 ? 2 : 1;
      if (values[0] < 0 || values[1] < 0 || (bytes == 1 && values[2] != -2))
        r_.fail_byte(first, "invalid base64 padding in " + what);
      const std::uint32_t v = static_cast<std::uint32_t>(values[0]) << 18 | static_cast<std::uint32_t>(values[1]) << 12 |
                              static_cast<std::uint32_t>(std::max(values[2], 0)) << 6 |
                              static_cast<std::uint32_t>(std::max(values[3], 0));
      const char out[3] = {static_cast<char>(v >> 16), static_cast<char>(v >> 8), static_cast<char>(v)};
      pending_.append(out, static_cast<std::size_t>(bytes));
    }

    const VtuReader& r_;
    std::size_t pos_, end_;
    bool base64_;
    std::string pending_;  ///< decoded bytes not yet taken
  };

  std::uint64_t header_word(Payload& in, const std::string& what) const {
    const std::string bytes = in.take(header_size_, what);
    return header_size_ == 8 ? load_bytes<std::uint64_t>(bytes.data(), order_)
                             : load_bytes<std::uint32_t>(bytes.data(), order_);
  }

  /// A binary array's data: the header read, the blocks decompressed.
  std::string binary_bytes(const ArrayRef& a) const {
    std::size_t begin = a.content_begin, end = a.content_end;
    bool base64 = true;
    if (a.format == "appended") {
      if (!has_appended_) fail_line(a.tag, array_name(a) + " is appended but the file has no <AppendedData>");
      if (*a.offset > appended_end_ - appended_begin_)
        fail_line(a.tag, array_name(a) + ": offset " + std::to_string(*a.offset) + " lies past the end of the " +
                             std::to_string(appended_end_ - appended_begin_) + " bytes of appended data");
      begin = appended_begin_ + static_cast<std::size_t>(*a.offset);
      end = appended_end_;
      base64 = appended_base64_;
    }
    Payload in(*this, begin, end, base64);
    const std::string what = array_name(a);
    if (!zlib_) return in.take(header_word(in, what + " header"), what);

    // vtkZLibDataCompressor: block count, block size, size of the last block (0: a full
    // one), the compressed size of each block, then the blocks.
    const std::uint64_t blocks = header_word(in, what + " block count");
    const std::uint64_t block_size = header_word(in, what + " block size");
    const std::uint64_t last_size = header_word(in, what + " last block size");
    if (blocks > 0 && (block_size == 0 || last_size > block_size))
      fail_byte(in.pos(), what + ": compression header has block size " + std::to_string(block_size) +
                              " and last block size " + std::to_string(last_size));
    std::vector<std::uint64_t> compressed;
    reserve_bounded(compressed, blocks, end - in.pos(), header_size_);
    for (std::uint64_t b = 0; b < blocks; ++b) compressed.push_back(header_word(in, what + " compressed block sizes"));
    std::string out;
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const std::uint64_t size = b + 1 == blocks && last_size != 0 ? last_size : block_size;
      const std::size_t at = in.pos();
      const std::string packed = in.take(compressed[b], what + " compressed block " + std::to_string(b));
      // Deflate expands at most about 1032:1; a larger claim is a corrupt header, not a
      // reason to allocate.
      if (size > packed.size() * 1032 + 64)
        fail_byte(at, what + ": block " + std::to_string(b) + " claims " + std::to_string(size) + " bytes from " +
                          std::to_string(packed.size()) + " compressed, more than zlib can expand");
      const std::size_t old = out.size();
      out.resize(old + static_cast<std::size_t>(size));
      auto got = static_cast<uLongf>(size);
      const int rc = uncompress(reinterpret_cast<Bytef*>(out.data() + old), &got,
                                reinterpret_cast<const Bytef*>(packed.data()), static_cast<uLong>(packed.size()));
      if (rc != Z_OK)
        fail_byte(at, what + ": zlib error in block " + std::to_string(b) + ": " + zError(rc));
      if (got != size)
        fail_byte(at, what + ": block " + std::to_string(b) + " holds " + std::to_string(got) + " bytes, its header says " +
                          std::to_string(size));
    }
    return out;
  }

  /// The values of an array as T (double or int64), `expected` of them when given.
  template <class T>
  std::vector<T> values(const ArrayRef& a, std::optional<std::uint64_t> expected) const {
    const ScalarType st = *scalar_type(a.type);
    if constexpr (std::is_integral_v<T>)
      if (st.is_float) fail_line(a.tag, array_name(a) + " has type " + a.type + "; an integer type is needed");
    std::vector<T> out;
    if (a.format == "ascii") {
      reserve_bounded(out, expected.value_or(0), a.content_end - a.content_begin, 2);
      std::size_t i = a.content_begin;
      while (true) {
        while (i < a.content_end && is_space(data_[i])) ++i;
        if (i >= a.content_end) break;
        const std::size_t start = i;
        while (i < a.content_end && !is_space(data_[i])) ++i;
        const std::string_view token = data_.substr(start, i - start);
        if (expected && out.size() == *expected)
          fail_line(start, array_name(a) + " holds more than the " + std::to_string(*expected) + " values expected");
        out.push_back(ascii_value<T>(a, st, token, start));
      }
    } else {
      const std::string bytes = binary_bytes(a);
      if (bytes.size() % st.size != 0)
        fail_line(a.tag, array_name(a) + " holds " + std::to_string(bytes.size()) + " bytes, not a whole number of " +
                             a.type + " values");
      out.reserve(bytes.size() / st.size);
      for (std::size_t p = 0; p < bytes.size(); p += st.size) out.push_back(binary_value<T>(a, st, bytes.data() + p));
    }
    if (expected && out.size() != *expected)
      fail_line(a.tag, array_name(a) + " holds " + std::to_string(out.size()) + " values, expected " +
                           std::to_string(*expected));
    return out;
  }

  template <class T>
  T ascii_value(const ArrayRef& a, const ScalarType& st, std::string_view token, std::size_t at) const {
    if constexpr (std::is_floating_point_v<T>) {
      double v = 0.0;
      const auto r = std::from_chars(token.data(), token.data() + token.size(), v);
      if (r.ec != std::errc() || r.ptr != token.data() + token.size() || !std::isfinite(v))
        fail_line(at, array_name(a) + ": expected a finite number, got '" + quote(token) + "'");
      return v;
    } else {
      std::int64_t v = 0;
      const auto r = std::from_chars(token.data(), token.data() + token.size(), v);
      if (r.ec != std::errc() || r.ptr != token.data() + token.size() || (!st.is_signed && v < 0))
        fail_line(at, array_name(a) + ": expected " + (st.is_signed ? "an integer" : "a non-negative integer") +
                          ", got '" + quote(token) + "'");
      return v;
    }
  }

  template <class T>
  T binary_value(const ArrayRef& a, const ScalarType& st, const char* p) const {
    if (st.is_float) {
      const double v = st.size == 4 ? load_bytes<float>(p, order_) : load_bytes<double>(p, order_);
      if (!std::isfinite(v)) fail_line(a.tag, array_name(a) + " holds a value that is NaN or infinite");
      return static_cast<T>(v);
    }
    if (st.size == 8 && !st.is_signed) {
      const auto v = load_bytes<std::uint64_t>(p, order_);
      if (v > static_cast<std::uint64_t>(INT64_MAX)) fail_line(a.tag, array_name(a) + " holds " + std::to_string(v) + ", too large");
      return static_cast<T>(v);
    }
    switch (st.size * 2 + (st.is_signed ? 1 : 0)) {
      case 2: return static_cast<T>(load_bytes<std::uint8_t>(p, order_));
      case 3: return static_cast<T>(load_bytes<std::int8_t>(p, order_));
      case 4: return static_cast<T>(load_bytes<std::uint16_t>(p, order_));
      case 5: return static_cast<T>(load_bytes<std::int16_t>(p, order_));
      case 8: return static_cast<T>(load_bytes<std::uint32_t>(p, order_));
      case 9: return static_cast<T>(load_bytes<std::int32_t>(p, order_));
      default: return static_cast<T>(load_bytes<std::int64_t>(p, order_));
    }
  }

  // ---- the mesh ----------------------------------------------------------------------------

  const ArrayRef& required(const std::optional<ArrayRef>& a, const Piece& p, const char* what) const {
    if (!a) fail_line(p.tag, std::string("the piece has no ") + what);
    return *a;
  }

  MeshFile build_mesh() {
    std::vector<Vec3> points;
    TetMesh volume;
    TriMesh surface;
    std::map<std::string, std::size_t> skipped;
    bool any_regions = false;
    std::size_t tets_without_regions = 0;
    for (const Piece& p : pieces_) {
      const auto base = static_cast<Index>(points.size());
      if (p.points > 0) {
        const ArrayRef& c = required(p.coords, p, "<Points> array");
        if (c.components != 3) fail_line(c.tag, "points need NumberOfComponents=\"3\", got " + std::to_string(c.components));
        const auto xyz = values<double>(c, static_cast<std::uint64_t>(p.points) * 3);
        for (std::size_t i = 0; i < xyz.size(); i += 3) points.emplace_back(xyz[i], xyz[i + 1], xyz[i + 2]);
      }
      if (p.cells == 0) continue;
      const ArrayRef& conn_ref = required(p.connectivity, p, "cell connectivity array");
      const auto types = values<std::int64_t>(required(p.types, p, "cell types array"), static_cast<std::uint64_t>(p.cells));
      const auto offsets = values<std::int64_t>(required(p.offsets, p, "cell offsets array"), static_cast<std::uint64_t>(p.cells));
      const auto conn = values<std::int64_t>(conn_ref, std::nullopt);
      std::vector<std::int64_t> regions;
      if (p.regions && p.regions->components == 1) regions = values<std::int64_t>(*p.regions, static_cast<std::uint64_t>(p.cells));
      auto point = [&](std::int64_t v, std::size_t cell) {
        if (v < 0 || v >= p.points)
          fail_line(conn_ref.tag, "cell " + std::to_string(cell) + " refers to point " + std::to_string(v) + " of a piece with " +
                                      std::to_string(p.points) + " points");
        return base + static_cast<Index>(v);
      };
      std::int64_t begin = 0;
      for (std::size_t c = 0; c < types.size(); ++c) {
        const std::int64_t end = offsets[c];
        if (end < begin || end > static_cast<std::int64_t>(conn.size()))
          fail_line(p.offsets->tag, "cell " + std::to_string(c) + "'s offsets " + std::to_string(begin) + ".." +
                                        std::to_string(end) + " lie outside the connectivity (" +
                                        std::to_string(conn.size()) + " values)");
        const auto n = static_cast<std::size_t>(end - begin);
        const auto* v = conn.data() + begin;
        begin = end;
        if (types[c] == 10 && n == 4) {
          volume.tets.push_back({point(v[0], c), point(v[1], c), point(v[2], c), point(v[3], c)});
          if (regions.empty()) {
            ++tets_without_regions;
          } else {
            if (regions[c] < INT32_MIN || regions[c] > INT32_MAX)
              fail_line(p.regions->tag, "region label " + std::to_string(regions[c]) + " out of range");
            volume.tet_regions.push_back(static_cast<int>(regions[c]));
            any_regions = true;
          }
        } else if (types[c] == 5 && n == 3) {
          surface.triangles.push_back({point(v[0], c), point(v[1], c), point(v[2], c)});
        } else if (types[c] == 10 || types[c] == 5) {
          fail_line(conn_ref.tag, "cell " + std::to_string(c) + " of type " + std::to_string(types[c]) + " has " +
                                      std::to_string(n) + " points");
        } else {
          const char* name = vtk_cell_name(types[c]);
          ++skipped[name ? std::string(name) : "cells of type " + std::to_string(types[c])];
        }
      }
    }
    // Regions from some pieces only cannot be lined up with the tets: none are kept.
    if (!any_regions || tets_without_regions > 0) volume.tet_regions.clear();

    MeshFile out;
    out.format = MeshFormat::vtu;
    for (const auto& [name, count] : skipped) {
      if (!out.skipped.empty()) out.skipped.append(", ");
      out.skipped.append(std::to_string(count)).append(" ").append(name);
    }
    if (volume.tets.empty() && surface.triangles.empty())
      fail_line(pieces_.front().tag, "no tetrahedra or triangles to read" +
                                         (out.skipped.empty() ? std::string() : " (the file holds " + out.skipped + ")"));
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

  std::string_view data_;
  std::string file_;
  XML_Parser parser_ = nullptr;
  std::exception_ptr pending_;  ///< an error raised inside an expat handler
  std::vector<std::string> stack_;  ///< open elements
  bool saw_root_ = false;
  std::endian order_ = std::endian::little;
  std::size_t header_size_ = 4;
  bool zlib_ = false;
  bool has_appended_ = false, appended_base64_ = false;
  std::size_t appended_begin_ = 0, appended_end_ = 0;
  std::deque<Piece> pieces_;  ///< a deque: open_array_ points into it while pieces are added
  ArrayRef* open_array_ = nullptr;
};

}  // namespace

MeshFile parse_vtu(std::string_view data, const std::string& file) { return VtuReader(data, file).read(); }

}  // namespace tactus::mesh::io
