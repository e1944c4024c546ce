// Gmsh MSH: reading 1.0 ($NOD/$ELM), 2.x and 4.0/4.1 ASCII, and binary 2.2 and 4.1 (either
// byte order, told by the marker after $MeshFormat); writing 2.2 and 4.1 ASCII. Nodes are
// kept in file order; element node tags are mapped through the node tags (which need not
// be contiguous). Triangles (type 2) and tetrahedra (type 4) are read with their physical
// tag (1.0: the reg-phys column; 2.x: the first element tag; 4.x: the first physical tag of
// the element's entity in $Entities) as region or face marker, or, in a file without
// physical groups, their elementary (entity) tag where it varies; other element types and
// unknown sections are skipped. Gmsh's reference tetrahedron is positively oriented, so tets are kept as
// written; orient_whole_file() still corrects a file that is inverted throughout.
#include <algorithm>
#include <bit>
#include <iterator>
#include <map>
#include <set>
#include <unordered_map>

#include "core/text.hpp"
#include "mesh/io/io_common.hpp"

namespace tactus::mesh::io {

namespace {

/// Gmsh's element types a reader meets, by what they are (msh's element type table).
std::string element_name(std::int64_t type) {
  switch (type) {
    case 1: return "lines (type 1)";
    case 3: return "quadrangles (type 3)";
    case 5: return "hexahedra (type 5)";
    case 6: return "prisms (type 6)";
    case 7: return "pyramids (type 7)";
    case 8: return "second-order lines (type 8)";
    case 9: return "second-order triangles (type 9)";
    case 11: return "second-order tetrahedra (type 11)";
    case 15: return "points (type 15)";
    default: return "elements of type " + std::to_string(type);
  }
}

/// How many nodes an element of Gmsh type `type` has (msh's element type table), or 0 for
/// a type not listed. Binary files need it to step over elements of types not read.
int element_nodes(std::int64_t type) {
  static constexpr int nodes[] = {0, 2, 3, 4, 4, 8, 6, 5, 3, 6, 9, 10, 27, 18, 14, 1, 8, 20, 15, 13,
                                  9, 10, 12, 15, 15, 21, 4, 5, 6, 20, 35, 56};
  if (type >= 0 && type < static_cast<std::int64_t>(std::size(nodes))) return nodes[type];
  if (type == 92) return 64;
  if (type == 93) return 125;
  return 0;
}

struct Element {
  std::array<Index, 4> nodes{};
  int physical = 0;
  int elementary = 0;  ///< the geometric entity: the region where a file has no physical groups
  std::int64_t number = 0;  ///< the file's element tag
  std::uint32_t line = 0;   ///< 0 in binary files
};

class MshReader {
 public:
  MshReader(std::string_view data, const std::string& file) : data_(data), in_(data, file) {}

  MeshFile read() {
    std::string_view line;
    while (in_.next_content(line, 0)) {
      const auto tok = text::split(line);
      const auto name = tok[0];
      if (name.size() < 2 || name[0] != '$')
        in_.fail_at(name, "expected a section such as '$MeshFormat', got '" + quote(name) + "'");
      // MSH 1.0 has no $MeshFormat: its first section is $NOD (or $NOE).
      if ((name == "$NOD" || name == "$NOE") && (version_ == 0 || version_ == 1)) {
        version_ = 1;
        read_nodes1(name);
        continue;
      }
      if (name != "$MeshFormat" && version_ == 0)
        in_.fail_at(name, "'" + quote(name) + "' before '$MeshFormat'");
      if (name == "$MeshFormat") read_format();
      else if (name == "$ELM" && version_ == 1) read_elements1();
      else if (name == "$Entities" && version_ == 4) binary_ ? read_entities4_binary() : read_entities();
      else if (name == "$Nodes" && version_ == 2) binary_ ? read_nodes2_binary() : read_nodes2();
      else if (name == "$Nodes" && version_ == 4) binary_ ? read_nodes41_binary() : minor40_ ? read_nodes40() : read_nodes41();
      else if (name == "$Elements" && version_ == 2) binary_ ? read_elements2_binary() : read_elements2();
      else if (name == "$Elements" && version_ == 4)
        binary_ ? read_elements41_binary() : minor40_ ? read_elements40() : read_elements41();
      else skip_section(name);
    }
    if (version_ == 0) in_.fail("no '$MeshFormat' section: not a Gmsh MSH file");
    if (!have_nodes_) in_.fail(version_ == 1 ? "no '$NOD' section" : "no '$Nodes' section");
    return result();
  }

 private:
  std::vector<std::string_view> content(const std::string& context) {
    std::string_view line;
    if (!in_.next_content(line, 0)) in_.fail("truncated file: end of file while reading " + context);
    return text::split(line);
  }

  void expect_line(const std::string& want, const std::string& context) {
    const auto tok = content(context + " (missing '" + want + "')");
    if (tok[0] != want) in_.fail_at(tok[0], "expected '" + want + "', got '" + quote(tok[0]) + "'");
  }
  void end_section(std::string_view name) {
    expect_line("$End" + std::string(name.substr(1)), std::string(name));
  }

  void skip_section(std::string_view name) {
    // Only the name is kept: the view into the line dies with the next read.
    const std::string want = "$End" + std::string(name.substr(1));
    const std::string section(name);
    std::string_view line;
    while (in_.next(line))
      if (text::trim(line) == want) return;
    in_.fail("truncated file: end of file inside section '" + quote(section) + "' (missing '" + quote(want) + "')");
  }

  void read_format() {
    const auto tok = content("$MeshFormat");
    if (tok.size() != 3) in_.fail("expected 'version file-type data-size' in $MeshFormat");
    if (tok[0] == "4.1") version_ = 4;
    else if (tok[0] == "4" || tok[0] == "4.0") version_ = 4, minor40_ = true;
    else if (tok[0] == "2.2" || tok[0] == "2.1" || tok[0] == "2.0" || tok[0] == "2") version_ = 2;
    else in_.fail_at(tok[0], "unsupported MSH version '" + quote(tok[0]) + "' (supported: 1.0, 2.x, 4.0, 4.1)");
    const std::int64_t type = in_.to_int(tok[1], "a file type");
    if (type != 0 && type != 1) in_.fail_at(tok[1], "unknown MSH file type " + std::to_string(type));
    binary_ = type == 1;
    if (binary_ && minor40_) in_.fail_at(tok[1], "binary MSH 4.0 is not supported; save as 4.1 or as ASCII");
    // The data size is sizeof(double) in 2.x and sizeof(size_t) in 4.x, which a 32-bit
    // Gmsh writes as 4.
    data_size_ = static_cast<int>(text::to_int(tok[2]).value_or(0));
    if (data_size_ != 8 && !(binary_ && version_ == 4 && data_size_ == 4))
      in_.fail_at(tok[2], "unsupported data size '" + quote(tok[2]) + "'");
    if (binary_) {
      in_.report_byte_offsets();
      // An int 1 follows the line: it tells the byte order the file was written in.
      ByteCursor bytes(data_, in_.file(), in_.offset());
      const auto one = bytes.read<std::uint32_t>("the endianness marker after the $MeshFormat line");
      if (one == 1) order_ = std::endian::little;
      else if (one == 0x01000000u) order_ = std::endian::big;
      else bytes.fail_at(in_.offset(), "endianness marker must be the integer 1, got " + std::to_string(one));
      in_.seek(bytes.pos());
    }
    end_section("$MeshFormat");
  }

  // ---- shared by all versions ----

  /// An elementary (entity) tag as a region label; tags beyond int's range are refused.
  int tag_of(std::string_view tok, const char* what) const {
    const std::int64_t v = in_.to_int(tok, what);
    if (v < INT32_MIN || v > INT32_MAX) in_.fail_at(tok, std::string(what) + " " + std::to_string(v) + " out of range");
    return static_cast<int>(v);
  }
  static int clamp_tag(std::int64_t tag) { return static_cast<int>(std::clamp<std::int64_t>(tag, INT32_MIN, INT32_MAX)); }

  int physical_of(std::string_view tok) const {
    const std::int64_t v = in_.to_int(tok, "a physical tag");
    if (v < INT32_MIN || v > INT32_MAX) in_.fail_at(tok, "physical tag " + std::to_string(v) + " out of range");
    return static_cast<int>(v);
  }

  /// Adds a node; false if its tag is taken.
  bool new_node(std::int64_t tag, const Vec3& p) {
    if (!node_index_.try_emplace(tag, static_cast<Index>(nodes_.size())).second) return false;
    nodes_.push_back(p);
    node_tags_.push_back(tag);
    return true;
  }

  void add_node(std::string_view tag_text, std::string_view x, std::string_view y, std::string_view z) {
    const std::int64_t tag = in_.to_int(tag_text, "a node tag");
    if (!new_node(tag, Vec3(in_.coordinate(x), in_.coordinate(y), in_.coordinate(z))))
      in_.fail_at(tag_text, "node tag " + std::to_string(tag) + " defined twice");
  }

  void begin_nodes() {
    if (have_nodes_) in_.fail("second '$Nodes' section");
    have_nodes_ = true;
  }

  const Index* find_node(std::int64_t tag) const {
    const auto it = node_index_.find(tag);
    return it == node_index_.end() ? nullptr : &it->second;
  }

  Index node(std::string_view tok, const std::string& element) const {
    const std::int64_t tag = in_.to_int(tok, "a node tag");
    const Index* i = find_node(tag);
    if (!i) in_.fail_at(tok, element + " refers to node tag " + std::to_string(tag) + ", which is not defined");
    return *i;
  }

  void add_element(std::int64_t type, const std::vector<std::string_view>& tok, std::size_t first, int physical,
                   int elementary, std::string_view id) {
    const std::size_t n = type == 2 ? 3 : 4;
    const std::string what = std::string(type == 2 ? "triangle " : "tetrahedron ") + std::string(id);
    if (tok.size() != first + n)
      in_.fail(what + ": expected " + std::to_string(n) + " nodes, got " + std::to_string(tok.size() > first ? tok.size() - first : 0));
    Element e;
    e.physical = physical;
    e.elementary = elementary;
    e.number = in_.to_int(id, "an element number");
    e.line = static_cast<std::uint32_t>(std::min<std::uint64_t>(in_.line(), UINT32_MAX));
    for (std::size_t k = 0; k < n; ++k) e.nodes[k] = node(tok[first + k], what);
    (type == 2 ? tris_ : tets_).push_back(e);
  }

  void begin_elements() {
    if (!have_nodes_) in_.fail("'$Elements' before '$Nodes'");
    if (have_elements_) in_.fail("second '$Elements' section");
    have_elements_ = true;
  }

  int entity_physical(std::int64_t dim, std::int64_t entity) const {
    const auto it = entity_physical_.find({static_cast<int>(std::clamp<std::int64_t>(dim, -1, 4)), entity});
    return it == entity_physical_.end() ? 0 : it->second;
  }

  // ---- MSH 1.0 ----

  void read_nodes1(std::string_view name) {
    const std::string end = name == "$NOD" ? "$ENDNOD" : "$ENDNOE";
    begin_nodes();
    const auto head = content(std::string(name));
    const std::int64_t n = in_.count(head[0], "node count");
    reserve_bounded(nodes_, static_cast<std::uint64_t>(n), in_.remaining(), 8);
    for (std::int64_t i = 0; i < n; ++i) {
      const auto tok = content(std::to_string(n) + " nodes: got " + std::to_string(i));
      if (tok.size() != 4) in_.fail("expected 'tag x y z' for node " + std::to_string(i) + ", got " + std::to_string(tok.size()) + " values");
      add_node(tok[0], tok[1], tok[2], tok[3]);
    }
    expect_line(end, std::string(name));
  }

  void read_elements1() {
    begin_elements();
    const auto head = content("$ELM");
    const std::int64_t n = in_.count(head[0], "element count");
    for (std::int64_t i = 0; i < n; ++i) {
      const auto tok = content(std::to_string(n) + " elements: got " + std::to_string(i));
      if (tok.size() < 5) in_.fail("expected 'number type physical elementary node-count nodes...'");
      (void)in_.to_int(tok[0], "an element number");
      const std::int64_t type = in_.to_int(tok[1], "an element type");
      const int phys = physical_of(tok[2]);
      const int elementary = tag_of(tok[3], "an elementary tag");
      const std::int64_t count = in_.count(tok[4], "node count");
      if (static_cast<std::int64_t>(tok.size()) != 5 + count)
        in_.fail("element " + std::string(tok[0]) + " lists " + std::to_string(tok.size() - 5) + " nodes, its count says " +
                 std::to_string(count));
      if (type == 2 || type == 4) add_element(type, tok, 5, phys, elementary, tok[0]);
      else ++skipped_[type];
    }
    expect_line("$ENDELM", "$ELM");
  }

  // ---- MSH 2.x ----

  void read_nodes2() {
    begin_nodes();
    const auto head = content("$Nodes");
    const std::int64_t n = in_.count(head[0], "node count");
    reserve_bounded(nodes_, static_cast<std::uint64_t>(n), in_.remaining(), 8);
    for (std::int64_t i = 0; i < n; ++i) {
      const auto tok = content(std::to_string(n) + " nodes: got " + std::to_string(i));
      if (tok.size() != 4) in_.fail("expected 'tag x y z' for node " + std::to_string(i) + ", got " + std::to_string(tok.size()) + " values");
      add_node(tok[0], tok[1], tok[2], tok[3]);
    }
    end_section("$Nodes");
  }

  void read_elements2() {
    begin_elements();
    const auto head = content("$Elements");
    const std::int64_t n = in_.count(head[0], "element count");
    for (std::int64_t i = 0; i < n; ++i) {
      const auto tok = content(std::to_string(n) + " elements: got " + std::to_string(i));
      if (tok.size() < 3) in_.fail("expected 'number type number-of-tags tags... nodes...'");
      (void)in_.to_int(tok[0], "an element number");
      const std::int64_t type = in_.to_int(tok[1], "an element type");
      const std::int64_t ntags = in_.count(tok[2], "tag count");
      if (static_cast<std::int64_t>(tok.size()) < 3 + ntags) in_.fail("element has fewer tags than its count");
      if (type != 2 && type != 4) {
        ++skipped_[type];
        continue;
      }
      const int phys = ntags > 0 ? physical_of(tok[3]) : 0;
      const int elementary = ntags > 1 ? tag_of(tok[4], "an elementary tag") : 0;
      add_element(type, tok, 3 + static_cast<std::size_t>(ntags), phys, elementary, tok[0]);
    }
    end_section("$Elements");
  }

  // ---- MSH 4.x ASCII ----

  void read_entities() {
    const auto head = content("$Entities");
    if (head.size() != 4) in_.fail("expected 'numPoints numCurves numSurfaces numVolumes'");
    std::int64_t counts[4];
    for (int d = 0; d < 4; ++d) counts[d] = in_.count(head[static_cast<std::size_t>(d)], "entity count");
    for (int dim = 0; dim < 4; ++dim) {
      for (std::int64_t i = 0; i < counts[dim]; ++i) {
        const auto tok = content("$Entities: " + std::to_string(counts[dim]) + " entities of dimension " +
                                 std::to_string(dim) + ": got " + std::to_string(i));
        // 4.1 points have X Y Z; 4.0 points and every other entity a bounding box.
        const std::size_t phys_at = dim == 0 && !minor40_ ? 4 : 7;
        if (tok.size() <= phys_at) in_.fail("entity line too short");
        const std::int64_t tag = in_.to_int(tok[0], "an entity tag");
        const std::int64_t n_phys = in_.count(tok[phys_at], "physical tag count");
        if (static_cast<std::int64_t>(tok.size()) < static_cast<std::int64_t>(phys_at) + 1 + n_phys)
          in_.fail("entity line lists fewer physical tags than its count " + std::to_string(n_phys));
        int phys = 0;
        if (n_phys > 0) phys = physical_of(tok[phys_at + 1]);
        for (std::int64_t k = 1; k < n_phys; ++k) (void)in_.to_int(tok[phys_at + 1 + static_cast<std::size_t>(k)]);
        entity_physical_[{dim, tag}] = phys;
      }
    }
    end_section("$Entities");
  }

  /// A 4.x node block's header line (4.1: "entityDim entityTag parametric numNodes"; 4.0
  /// swaps the first two): its node count, checked against the `declared` total, and the
  /// parametric coordinates each of its nodes carries after x y z.
  std::pair<std::int64_t, std::size_t> node_block(std::int64_t blocks, std::int64_t b, std::int64_t declared,
                                                  bool v40) {
    const auto bh = content(std::to_string(blocks) + " node blocks: got " + std::to_string(b));
    if (bh.size() != 4)
      in_.fail(v40 ? "expected 'entityTag entityDim parametric numNodes'"
                   : "expected 'entityDim entityTag parametric numNodesInBlock'");
    const std::string_view dim_token = bh[v40 ? 1 : 0];
    const std::int64_t dim = in_.to_int(dim_token, "an entity dimension");
    if (dim < 0 || dim > 3) in_.fail_at(dim_token, "entity dimension must be 0..3, got " + std::to_string(dim));
    const std::int64_t parametric = in_.to_int(bh[2], "0 or 1");
    if (parametric != 0 && parametric != 1) in_.fail_at(bh[2], "parametric flag must be 0 or 1");
    const std::int64_t m = in_.count(bh[3], "block node count");
    if (static_cast<std::int64_t>(nodes_.size()) + m > declared)
      in_.fail_at(bh[3], "node blocks hold more nodes than the " + std::to_string(declared) + " declared");
    return {m, parametric ? static_cast<std::size_t>(dim) : 0};
  }

  void read_nodes41() {
    begin_nodes();
    const auto head = content("$Nodes");
    if (head.size() != 4) in_.fail("expected 'numEntityBlocks numNodes minNodeTag maxNodeTag'");
    const std::int64_t blocks = in_.count(head[0], "block count");
    const std::int64_t n = in_.count(head[1], "node count");
    reserve_bounded(nodes_, static_cast<std::uint64_t>(n), in_.remaining(), 8);
    std::vector<std::int64_t> tags;
    for (std::int64_t b = 0; b < blocks; ++b) {
      const auto [m, parametric_values] = node_block(blocks, b, n, false);
      const std::size_t values = 3 + parametric_values;
      // Tags come first, then coordinates.
      tags.clear();
      for (std::int64_t i = 0; i < m; ++i) {
        const auto tok = content(std::to_string(m) + " node tags: got " + std::to_string(i));
        if (tok.size() != 1) in_.fail("expected one node tag per line");
        tags.push_back(in_.to_int(tok[0], "a node tag"));
      }
      for (std::int64_t i = 0; i < m; ++i) {
        const auto tok = content(std::to_string(m) + " node coordinates: got " + std::to_string(i));
        if (tok.size() != values)
          in_.fail("expected " + std::to_string(values) + " coordinates, got " + std::to_string(tok.size()));
        const std::int64_t tag = tags[static_cast<std::size_t>(i)];
        if (!new_node(tag, Vec3(in_.coordinate(tok[0]), in_.coordinate(tok[1]), in_.coordinate(tok[2]))))
          in_.fail("node tag " + std::to_string(tag) + " defined twice");
      }
    }
    if (static_cast<std::int64_t>(nodes_.size()) != n)
      in_.fail("$Nodes declares " + std::to_string(n) + " nodes but its blocks hold " + std::to_string(nodes_.size()));
    end_section("$Nodes");
  }

  /// 4.0: "numEntityBlocks numNodes", blocks headed "entityTag entityDim parametric
  /// numNodes", each node on one line as "tag x y z [u v w]".
  void read_nodes40() {
    begin_nodes();
    const auto head = content("$Nodes");
    if (head.size() != 2) in_.fail("expected 'numEntityBlocks numNodes' (MSH 4.0)");
    const std::int64_t blocks = in_.count(head[0], "block count");
    const std::int64_t n = in_.count(head[1], "node count");
    reserve_bounded(nodes_, static_cast<std::uint64_t>(n), in_.remaining(), 8);
    for (std::int64_t b = 0; b < blocks; ++b) {
      const auto [m, parametric_values] = node_block(blocks, b, n, true);
      const std::size_t values = 4 + parametric_values;
      for (std::int64_t i = 0; i < m; ++i) {
        const auto tok = content(std::to_string(m) + " nodes of a block: got " + std::to_string(i));
        if (tok.size() != values)
          in_.fail("expected " + std::to_string(values) + " values (tag and coordinates), got " + std::to_string(tok.size()));
        add_node(tok[0], tok[1], tok[2], tok[3]);
      }
    }
    if (static_cast<std::int64_t>(nodes_.size()) != n)
      in_.fail("$Nodes declares " + std::to_string(n) + " nodes but its blocks hold " + std::to_string(nodes_.size()));
    end_section("$Nodes");
  }

  void read_elements4(bool v40) {
    begin_elements();
    const auto head = content("$Elements");
    if (head.size() != (v40 ? 2u : 4u))
      in_.fail(v40 ? "expected 'numEntityBlocks numElements' (MSH 4.0)"
                   : "expected 'numEntityBlocks numElements minElementTag maxElementTag'");
    const std::int64_t blocks = in_.count(head[0], "block count");
    const std::int64_t n = in_.count(head[1], "element count");
    std::int64_t seen = 0;
    for (std::int64_t b = 0; b < blocks; ++b) {
      const auto bh = content(std::to_string(blocks) + " element blocks: got " + std::to_string(b));
      if (bh.size() != 4)
        in_.fail(v40 ? "expected 'entityTag entityDim elementType numElements'"
                     : "expected 'entityDim entityTag elementType numElementsInBlock'");
      // 4.0 names the entity before its dimension, 4.1 after.
      const std::int64_t dim = in_.to_int(bh[v40 ? 1 : 0], "an entity dimension");
      const std::int64_t entity = in_.to_int(bh[v40 ? 0 : 1], "an entity tag");
      const std::int64_t type = in_.to_int(bh[2], "an element type");
      const std::int64_t m = in_.count(bh[3], "block element count");
      if (seen + m > n) in_.fail_at(bh[3], "element blocks hold more elements than the " + std::to_string(n) + " declared");
      seen += m;
      const int phys = entity_physical(dim, entity);
      for (std::int64_t i = 0; i < m; ++i) {
        const auto tok = content(std::to_string(m) + " elements of a block: got " + std::to_string(i));
        if (type == 2 || type == 4) add_element(type, tok, 1, phys, clamp_tag(entity), tok[0]);
        else ++skipped_[type];
      }
    }
    if (seen != n) in_.fail("$Elements declares " + std::to_string(n) + " elements but its blocks hold " + std::to_string(seen));
    end_section("$Elements");
  }
  void read_elements41() { read_elements4(false); }
  void read_elements40() { read_elements4(true); }

  // ---- binary (2.2 and 4.1): the section headers and ends are text, the data between
  // them binary in the byte order of the marker; errors name byte offsets ----

  ByteCursor binary_cursor() const { return ByteCursor(data_, in_.file(), in_.offset(), order_); }

  /// A count written as an int (2.2) or a size_t of data_size_ bytes (4.1), at most
  /// 2^31 - 1 like the text counts.
  std::int64_t binary_count(ByteCursor& bytes, const char* what, bool size_t_field = true) const {
    const std::size_t at = bytes.pos();
    std::uint64_t v = 0;
    if (size_t_field && data_size_ == 8) v = bytes.read<std::uint64_t>(what);
    else v = bytes.read<std::uint32_t>(what);
    if (v > static_cast<std::uint64_t>(INT32_MAX)) bytes.fail_at(at, std::string(what) + " too large: " + std::to_string(v));
    return static_cast<std::int64_t>(v);
  }

  Vec3 binary_point(ByteCursor& bytes) const {
    const std::size_t at = bytes.pos();
    Vec3 p;
    for (int k = 0; k < 3; ++k) p[k] = bytes.read<double>("a node coordinate");
    if (!p.allFinite()) bytes.fail_at(at, "node coordinate is NaN or infinite");
    return p;
  }

  Index binary_node(ByteCursor& bytes, std::int64_t tag, std::size_t at, std::int64_t type, std::int64_t id) const {
    const Index* i = find_node(tag);
    if (!i)
      bytes.fail_at(at, std::string(type == 2 ? "triangle " : "tetrahedron ") + std::to_string(id) + " refers to node tag " +
                            std::to_string(tag) + ", which is not defined");
    return *i;
  }

  void read_nodes2_binary() {
    begin_nodes();
    const auto head = content("$Nodes");
    const std::int64_t n = in_.count(head[0], "node count");
    ByteCursor bytes = binary_cursor();
    reserve_bounded(nodes_, static_cast<std::uint64_t>(n), bytes.remaining(), 28);
    for (std::int64_t i = 0; i < n; ++i) {
      const std::size_t at = bytes.pos();
      const std::int64_t tag = bytes.read<std::int32_t>("a node tag");
      if (!new_node(tag, binary_point(bytes))) bytes.fail_at(at, "node tag " + std::to_string(tag) + " defined twice");
    }
    in_.seek(bytes.pos());
    end_section("$Nodes");
  }

  void read_elements2_binary() {
    begin_elements();
    const auto head = content("$Elements");
    const std::int64_t n = in_.count(head[0], "element count");
    ByteCursor bytes = binary_cursor();
    // Blocks of one type: "type count tags", then per element "number tags... nodes...".
    for (std::int64_t seen = 0; seen < n;) {
      const std::size_t block_at = bytes.pos();
      const std::int64_t type = bytes.read<std::int32_t>("an element type");
      const std::int64_t m = binary_count(bytes, "block element count", false);
      const std::int64_t ntags = binary_count(bytes, "tag count", false);
      if (m == 0 || seen + m > n)
        bytes.fail_at(block_at, "element block of " + std::to_string(m) + " elements; " + std::to_string(n - seen) +
                                    " of the " + std::to_string(n) + " declared are left");
      const int nodes = element_nodes(type);
      if (nodes == 0) bytes.fail_at(block_at, "element type " + std::to_string(type) + " is unknown: its node count is needed to read on");
      seen += m;
      for (std::int64_t i = 0; i < m; ++i) {
        const std::int64_t id = bytes.read<std::int32_t>("an element number");
        int phys = 0, elementary = 0;
        for (std::int64_t t = 0; t < ntags; ++t) {
          const std::int32_t tag = bytes.read<std::int32_t>("an element tag");
          if (t == 0) phys = tag;
          if (t == 1) elementary = tag;
        }
        if (type != 2 && type != 4) {
          bytes.skip(static_cast<std::size_t>(nodes) * 4, "element nodes");
          ++skipped_[type];
          continue;
        }
        Element e;
        e.physical = phys;
        e.elementary = elementary;
        e.number = id;
        for (int k = 0; k < nodes; ++k) {
          const std::size_t at = bytes.pos();
          e.nodes[static_cast<std::size_t>(k)] = binary_node(bytes, bytes.read<std::int32_t>("a node tag"), at, type, id);
        }
        (type == 2 ? tris_ : tets_).push_back(e);
      }
    }
    in_.seek(bytes.pos());
    end_section("$Elements");
  }

  void read_entities4_binary() {
    ByteCursor bytes = binary_cursor();
    std::int64_t counts[4];
    for (auto& c : counts) c = binary_count(bytes, "entity count");
    for (int dim = 0; dim < 4; ++dim) {
      for (std::int64_t i = 0; i < counts[dim]; ++i) {
        const std::int64_t tag = bytes.read<std::int32_t>("an entity tag");
        bytes.skip(dim == 0 ? 24 : 48, "an entity's coordinates");  // a point, or a bounding box
        const std::int64_t n_phys = binary_count(bytes, "physical tag count");
        int phys = 0;
        for (std::int64_t k = 0; k < n_phys; ++k) {
          const std::int32_t p = bytes.read<std::int32_t>("a physical tag");
          if (k == 0) phys = p;
        }
        if (dim > 0) {
          const std::int64_t n_bound = binary_count(bytes, "bounding entity count");
          bytes.skip(static_cast<std::size_t>(n_bound) * 4, "bounding entity tags");
        }
        entity_physical_[{dim, tag}] = phys;
      }
    }
    in_.seek(bytes.pos());
    end_section("$Entities");
  }

  void read_nodes41_binary() {
    begin_nodes();
    ByteCursor bytes = binary_cursor();
    const std::int64_t blocks = binary_count(bytes, "block count");
    const std::int64_t n = binary_count(bytes, "node count");
    bytes.skip(2 * static_cast<std::size_t>(data_size_), "the smallest and largest node tags");
    reserve_bounded(nodes_, static_cast<std::uint64_t>(n), bytes.remaining(), 24);
    std::vector<std::int64_t> tags;
    for (std::int64_t b = 0; b < blocks; ++b) {
      const std::size_t block_at = bytes.pos();
      const std::int64_t dim = bytes.read<std::int32_t>("an entity dimension");
      (void)bytes.read<std::int32_t>("an entity tag");
      const std::int64_t parametric = bytes.read<std::int32_t>("the parametric flag");
      const std::int64_t m = binary_count(bytes, "block node count");
      if (dim < 0 || dim > 3) bytes.fail_at(block_at, "entity dimension must be 0..3, got " + std::to_string(dim));
      if (parametric != 0 && parametric != 1) bytes.fail_at(block_at + 8, "parametric flag must be 0 or 1");
      if (static_cast<std::int64_t>(nodes_.size()) + m > n)
        bytes.fail_at(block_at, "node blocks hold more nodes than the " + std::to_string(n) + " declared");
      tags.clear();
      reserve_bounded(tags, static_cast<std::uint64_t>(m), bytes.remaining(), static_cast<std::size_t>(data_size_));
      for (std::int64_t i = 0; i < m; ++i)
        tags.push_back(data_size_ == 8 ? static_cast<std::int64_t>(bytes.read<std::uint64_t>("a node tag"))
                                       : bytes.read<std::uint32_t>("a node tag"));
      for (std::int64_t i = 0; i < m; ++i) {
        const std::size_t at = bytes.pos();
        const std::int64_t tag = tags[static_cast<std::size_t>(i)];
        if (!new_node(tag, binary_point(bytes))) bytes.fail_at(at, "node tag " + std::to_string(tag) + " defined twice");
        if (parametric) bytes.skip(static_cast<std::size_t>(dim) * 8, "parametric coordinates");
      }
    }
    if (static_cast<std::int64_t>(nodes_.size()) != n)
      bytes.fail("$Nodes declares " + std::to_string(n) + " nodes but its blocks hold " + std::to_string(nodes_.size()));
    in_.seek(bytes.pos());
    end_section("$Nodes");
  }

  void read_elements41_binary() {
    begin_elements();
    ByteCursor bytes = binary_cursor();
    const std::int64_t blocks = binary_count(bytes, "block count");
    const std::int64_t n = binary_count(bytes, "element count");
    bytes.skip(2 * static_cast<std::size_t>(data_size_), "the smallest and largest element tags");
    const auto tag_value = [&](const char* what) {
      return data_size_ == 8 ? static_cast<std::int64_t>(bytes.read<std::uint64_t>(what)) : bytes.read<std::uint32_t>(what);
    };
    std::int64_t seen = 0;
    for (std::int64_t b = 0; b < blocks; ++b) {
      const std::size_t block_at = bytes.pos();
      const std::int64_t dim = bytes.read<std::int32_t>("an entity dimension");
      const std::int64_t entity = bytes.read<std::int32_t>("an entity tag");
      const std::int64_t type = bytes.read<std::int32_t>("an element type");
      const std::int64_t m = binary_count(bytes, "block element count");
      if (seen + m > n) bytes.fail_at(block_at, "element blocks hold more elements than the " + std::to_string(n) + " declared");
      const int nodes = element_nodes(type);
      if (nodes == 0 && m > 0)
        bytes.fail_at(block_at, "element type " + std::to_string(type) + " is unknown: its node count is needed to read on");
      seen += m;
      const int phys = entity_physical(dim, entity);
      for (std::int64_t i = 0; i < m; ++i) {
        const std::int64_t id = tag_value("an element tag");
        if (type != 2 && type != 4) {
          bytes.skip(static_cast<std::size_t>(nodes) * static_cast<std::size_t>(data_size_), "element nodes");
          ++skipped_[type];
          continue;
        }
        Element e;
        e.physical = phys;
        e.elementary = clamp_tag(entity);
        e.number = id;
        for (int k = 0; k < nodes; ++k) {
          const std::size_t at = bytes.pos();
          e.nodes[static_cast<std::size_t>(k)] = binary_node(bytes, tag_value("a node tag"), at, type, id);
        }
        (type == 2 ? tris_ : tets_).push_back(e);
      }
    }
    if (seen != n) bytes.fail("$Elements declares " + std::to_string(n) + " elements but its blocks hold " + std::to_string(seen));
    in_.seek(bytes.pos());
    end_section("$Elements");
  }

  /// A Gmsh element tag names one element: a tag used twice among the triangles and
  /// tetrahedra is refused, at the later of the two lines (ASCII files).
  void check_unique_element_tags() const {
    std::vector<std::pair<std::int64_t, std::uint32_t>> tags;  // tag, line (0: binary)
    for (const auto* list : {&tris_, &tets_})
      for (const auto& e : *list) tags.emplace_back(e.number, e.line);
    std::sort(tags.begin(), tags.end());
    for (std::size_t i = 1; i < tags.size(); ++i) {
      if (tags[i].first != tags[i - 1].first) continue;
      SourceLocation where{in_.file(), {}, {}, {}};
      std::string lines;
      if (tags[i].second > 0) {
        where.line = std::max(tags[i].second, tags[i - 1].second);
        lines.append(" (lines ").append(std::to_string(std::min(tags[i].second, tags[i - 1].second)));
        lines.append(" and ").append(std::to_string(*where.line)).append(")");
      }
      throw InputError(where, "element tag " + std::to_string(tags[i].first) + " names two elements" + lines);
    }
  }

  MeshFile result() {
    MeshFile out;
    out.format = MeshFormat::msh;
    for (const auto& [type, count] : skipped_)
      out.skipped += (out.skipped.empty() ? "" : ", ") + std::to_string(count) + " " + element_name(type);
    if (tris_.empty() && tets_.empty())
      in_.fail("no triangles (type 2) or tetrahedra (type 4) to read" +
               (out.skipped.empty() ? std::string() : " (the file holds " + out.skipped + ")"));
    check_unique_element_tags();
    std::vector<Triangle> tris;
    std::vector<int> markers;
    bool any_marker = false;
    FileNumbering tri_numbering("element", 0, node_tags_);
    // Regions and markers are the physical tags. A file with no physical group at all labels
    // its elements by their geometric entities instead (Gmsh writes physical tag 0 then),
    // where those tell elements apart: one entity throughout (a single volume, or what
    // Tactus writes) labels nothing.
    auto has_physical = [](const std::vector<Element>& v) {
      return std::any_of(v.begin(), v.end(), [](const Element& e) { return e.physical != 0; });
    };
    auto several_entities = [](const std::vector<Element>& v) {
      return std::any_of(v.begin(), v.end(), [&](const Element& e) { return e.elementary != v.front().elementary; });
    };
    const bool physical_groups = has_physical(tris_) || has_physical(tets_);
    const bool tri_entities = !physical_groups && several_entities(tris_);
    const bool tet_entities = !physical_groups && several_entities(tets_);
    auto label = [&](const Element& e, bool entities) { return entities ? e.elementary : e.physical; };
    for (const auto& e : tris_) {
      tris.push_back({e.nodes[0], e.nodes[1], e.nodes[2]});
      tri_numbering.add_element(e.number, e.line);
      markers.push_back(label(e, tri_entities));
      any_marker = any_marker || markers.back() != 0;
    }
    if (!any_marker) markers.clear();  // no labelled surfaces: no labels
    if (!tets_.empty()) {
      TetMesh vol;
      vol.vertices = nodes_;
      bool any_region = false;
      out.volume_numbering = FileNumbering("element", 0, node_tags_);
      for (const auto& e : tets_) {
        vol.tets.push_back(e.nodes);
        out.volume_numbering.add_element(e.number, e.line);
        vol.tet_regions.push_back(label(e, tet_entities));
        any_region = any_region || vol.tet_regions.back() != 0;
      }
      if (!any_region) vol.tet_regions.clear();
      vol.faces = tris;
      vol.face_markers = markers;
      out.flipped_tets = orient_whole_file(vol);
      out.volume = std::move(vol);
    }
    if (!tris.empty() || tets_.empty()) {
      TriMesh surf;
      surf.vertices = std::move(nodes_);
      surf.triangles = std::move(tris);
      out.surface = std::move(surf);
      out.surface_numbering = std::move(tri_numbering);
    }
    return out;
  }

  std::string_view data_;
  LineReader in_;
  int version_ = 0;     ///< 1, 2 or 4
  bool minor40_ = false;  ///< 4.0, whose layout differs from 4.1
  bool binary_ = false;
  int data_size_ = 8;
  std::endian order_ = std::endian::little;
  bool have_nodes_ = false;
  bool have_elements_ = false;
  std::vector<Vec3> nodes_;
  std::vector<std::int64_t> node_tags_;  ///< per node, its tag
  std::unordered_map<std::int64_t, Index> node_index_;
  std::map<std::pair<int, std::int64_t>, int> entity_physical_;
  std::vector<Element> tris_, tets_;
  std::map<std::int64_t, std::size_t> skipped_;  ///< elements of other types, by type
};

void put_vec(std::string& out, const Vec3& v) {
  for (int k = 0; k < 3; ++k) {
    out += ' ';
    put_double(out, v[k]);
  }
}

void put_nodes(std::string& out, const std::vector<Index>& nodes) {
  for (const Index i : nodes) {
    out += ' ';
    put_int(out, std::int64_t{i} + 1);
  }
}

}  // namespace

MeshFile parse_msh(std::string_view data, const std::string& file) { return MshReader(data, file).read(); }

std::string format_msh(const TriMesh* surface, const TetMesh* volume, int version) {
  if (version != 22 && version != 41)
    throw InputError("unsupported MSH version " + std::to_string(version) + " for writing (use 22 or 41)");
  const std::vector<Vec3>& vertices = surface ? surface->vertices : volume->vertices;
  const std::vector<Triangle>& tris = surface ? surface->triangles : volume->faces;
  static const std::vector<Tet> no_tets;
  static const std::vector<int> none;
  const std::vector<Tet>& tets = volume ? volume->tets : no_tets;
  const std::vector<int>& markers = volume ? volume->face_markers : none;
  const std::vector<int>& regions = volume ? volume->tet_regions : none;
  auto marker = [&](std::size_t i) { return markers.empty() ? 0 : markers[i]; };
  auto region = [&](std::size_t i) { return regions.empty() ? 0 : regions[i]; };

  std::string out = version == 22 ? "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n" : "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  if (version == 22) {
    out += "$Nodes\n";
    put_int(out, static_cast<std::int64_t>(vertices.size()));
    out += '\n';
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      put_int(out, static_cast<std::int64_t>(i) + 1);
      put_vec(out, vertices[i]);
      out += '\n';
    }
    out += "$EndNodes\n$Elements\n";
    put_int(out, static_cast<std::int64_t>(tris.size() + tets.size()));
    out += '\n';
    std::int64_t id = 1;
    // Two tags: physical, then elementary (an entity, which must not be 0).
    auto element = [&](int type, int phys, std::vector<Index> nodes) {
      put_int(out, id++);
      out += type == 2 ? " 2 2 " : " 4 2 ";
      put_int(out, phys);
      out += ' ';
      put_int(out, phys != 0 ? phys : 1);
      put_nodes(out, nodes);
      out += '\n';
    };
    for (std::size_t i = 0; i < tris.size(); ++i) element(2, marker(i), {tris[i].begin(), tris[i].end()});
    for (std::size_t i = 0; i < tets.size(); ++i) element(4, region(i), {tets[i].begin(), tets[i].end()});
    out += "$EndElements\n";
    return out;
  }

  // 4.1: one entity per distinct label; all nodes live in the first entity of the
  // highest dimension present.
  std::set<int> surf_labels, vol_labels;
  for (std::size_t i = 0; i < tris.size(); ++i) surf_labels.insert(marker(i));
  for (std::size_t i = 0; i < tets.size(); ++i) vol_labels.insert(region(i));
  if (surf_labels.empty() && vol_labels.empty()) surf_labels.insert(0);
  std::map<int, int> surf_entity, vol_entity;
  for (const int l : surf_labels) surf_entity.emplace(l, static_cast<int>(surf_entity.size()) + 1);
  for (const int l : vol_labels) vol_entity.emplace(l, static_cast<int>(vol_entity.size()) + 1);
  Aabb box;
  for (const auto& v : vertices) box.add(v);
  const Vec3 lo = box.empty() ? Vec3::Zero() : box.min, hi = box.empty() ? Vec3::Zero() : box.max;
  out += "$Entities\n0 0 ";
  put_int(out, static_cast<std::int64_t>(surf_entity.size()));
  out += ' ';
  put_int(out, static_cast<std::int64_t>(vol_entity.size()));
  out += '\n';
  for (const auto* entities : {&surf_entity, &vol_entity}) {
    for (const auto& [label, tag] : *entities) {
      put_int(out, tag);
      put_vec(out, lo);
      put_vec(out, hi);
      out += label != 0 ? " 1 " + std::to_string(label) + " 0\n" : " 0 0\n";
    }
  }
  out += "$EndEntities\n$Nodes\n";
  const auto n = static_cast<std::int64_t>(vertices.size());
  const int node_dim = vol_entity.empty() ? 2 : 3;
  if (n == 0) {
    out += "0 0 0 0\n";
  } else {
    out += "1 " + std::to_string(n) + " 1 " + std::to_string(n) + '\n';
    out += std::to_string(node_dim) + " 1 0 " + std::to_string(n) + '\n';
    for (std::int64_t i = 1; i <= n; ++i) {
      put_int(out, i);
      out += '\n';
    }
    for (const auto& v : vertices) {
      put_vec(out, v);
      out += '\n';
    }
  }
  out += "$EndNodes\n$Elements\n";
  // One block per run of equal labels keeps the elements in their original order.
  struct Block {
    int dim, entity;
    std::size_t begin, end;
  };
  std::vector<Block> blocks;
  for (std::size_t i = 0; i < tris.size(); ++i) {
    if (i == 0 || marker(i) != marker(i - 1)) blocks.push_back({2, surf_entity.at(marker(i)), i, i});
    blocks.back().end = i + 1;
  }
  for (std::size_t i = 0; i < tets.size(); ++i) {
    if (i == 0 || region(i) != region(i - 1)) blocks.push_back({3, vol_entity.at(region(i)), i, i});
    blocks.back().end = i + 1;
  }
  const std::size_t total = tris.size() + tets.size();
  out += std::to_string(blocks.size()) + ' ' + std::to_string(total) + ' ' +
         (total ? "1 " + std::to_string(total) : std::string("0 0")) + '\n';
  std::int64_t id = 1;
  for (const auto& b : blocks) {
    out += std::to_string(b.dim) + ' ' + std::to_string(b.entity) + (b.dim == 2 ? " 2 " : " 4 ") +
           std::to_string(b.end - b.begin) + '\n';
    for (std::size_t i = b.begin; i < b.end; ++i) {
      put_int(out, id++);
      if (b.dim == 2) put_nodes(out, {tris[i].begin(), tris[i].end()});
      else put_nodes(out, {tets[i].begin(), tets[i].end()});
      out += '\n';
    }
  }
  out += "$EndElements\n";
  return out;
}

}  // namespace tactus::mesh::io
