// TetGen .node / .ele / .face. Items are numbered from 0 or 1 (whichever the first
// point uses) and consecutively; '#' starts a comment. .ele may hold 4- or 10-node tets
// (the first four are the corners) and attributes, the first of which is the region;
// .face may carry a boundary marker and, with -nn, two adjacent tets (ignored).
// TetGen's own output is positively oriented in TetMesh's sense, but files from older
// versions and other tools use the mirrored order, so orient_whole_file() flips a file
// whose tets are all negative and leaves mixed files to validate().
#include <cmath>

#include "core/text.hpp"
#include "mesh/io/io_common.hpp"

namespace tactus::mesh::io {

namespace {

std::vector<std::string_view> content_tokens(LineReader& in) {
  std::string_view line;
  while (in.next(line)) {
    const auto hash = line.find('#');
    auto tok = text::split(hash == std::string_view::npos ? line : line.substr(0, hash));
    if (!tok.empty()) return tok;
  }
  return {};
}

std::vector<std::string_view> need_tokens(LineReader& in, const std::string& context, std::int64_t n, std::int64_t got) {
  auto tok = content_tokens(in);
  if (tok.empty())
    in.fail("truncated file: end of file while reading " + std::to_string(n) + " " + context + ": got " +
            std::to_string(got));
  return tok;
}

struct Nodes {
  std::vector<Vec3> points;
  std::int64_t base = 0;
};

Nodes read_node(std::string_view data, const std::string& file) {
  LineReader in(data, file);
  auto head = content_tokens(in);
  if (head.empty()) in.fail("empty .node file");
  if (head.size() > 4) in.fail("expected '<#points> <dimension> <#attributes> <#boundary markers>'");
  const std::int64_t n = in.count(head[0], "point count");
  const std::int64_t dim = head.size() > 1 ? in.to_int(head[1], "a dimension") : 3;
  if (dim != 3) in.fail_at(head[1], "only 3-dimensional .node files are supported, got dimension " + std::to_string(dim));
  const std::int64_t attrs = head.size() > 2 ? in.count(head[2], "attribute count") : 0;
  const std::int64_t markers = head.size() > 3 ? in.count(head[3], "boundary marker count") : 0;
  if (markers > 1) in.fail_at(head[3], "boundary marker count must be 0 or 1");
  const std::size_t width = 4 + static_cast<std::size_t>(attrs + markers);
  Nodes nodes;
  reserve_bounded(nodes.points, static_cast<std::uint64_t>(n), in.remaining(), 8);
  for (std::int64_t i = 0; i < n; ++i) {
    const auto tok = need_tokens(in, "points", n, i);
    if (tok.size() != width)
      in.fail("point line needs " + std::to_string(width) + " values (index, x, y, z, " + std::to_string(attrs) +
              " attributes, " + std::to_string(markers) + " markers), got " + std::to_string(tok.size()));
    const std::int64_t id = in.to_int(tok[0], "a point index");
    if (i == 0) {
      if (id != 0 && id != 1) in.fail_at(tok[0], "first point must be numbered 0 or 1, got " + std::to_string(id));
      nodes.base = id;
    } else if (id != nodes.base + i) {
      in.fail_at(tok[0], "expected point number " + std::to_string(nodes.base + i) + ", got " + std::to_string(id));
    }
    for (std::size_t k = 4; k < tok.size(); ++k) (void)in.to_double(tok[k]);
    nodes.points.emplace_back(in.coordinate(tok[1]), in.coordinate(tok[2]), in.coordinate(tok[3]));
  }
  return nodes;
}

Index vertex(const LineReader& in, std::string_view tok, const Nodes& nodes, const std::string& what) {
  const std::int64_t id = in.to_int(tok, "a point index");
  const std::int64_t i = id - nodes.base;
  if (i < 0 || i >= static_cast<std::int64_t>(nodes.points.size()))
    in.fail_at(tok, what + " refers to point " + std::to_string(id) + ", out of range [" + std::to_string(nodes.base) +
                        ", " + std::to_string(nodes.base + static_cast<std::int64_t>(nodes.points.size())) + ")");
  return static_cast<Index>(i);
}

int integer_label(const LineReader& in, std::string_view tok, const char* what) {
  const double v = in.to_double(tok, what);
  if (!(v == std::floor(v) && v >= INT32_MIN && v <= INT32_MAX))
    in.fail_at(tok, std::string(what) + " must be an integer, got '" + quote(tok) + "'");
  return static_cast<int>(v);
}

void read_ele(std::string_view data, const std::string& file, const Nodes& nodes, TetMesh& mesh,
              FileNumbering& numbering) {
  LineReader in(data, file);
  auto head = content_tokens(in);
  if (head.empty()) in.fail("empty .ele file");
  if (head.size() > 3) in.fail("expected '<#tetrahedra> <nodes per tetrahedron> <#attributes>'");
  const std::int64_t n = in.count(head[0], "tetrahedron count");
  const std::int64_t per = head.size() > 1 ? in.to_int(head[1], "nodes per tetrahedron") : 4;
  if (per != 4 && per != 10) in.fail_at(head[1], "nodes per tetrahedron must be 4 or 10, got " + std::to_string(per));
  const std::int64_t attrs = head.size() > 2 ? in.count(head[2], "attribute count") : 0;
  const std::size_t width = 1 + static_cast<std::size_t>(per + attrs);
  reserve_bounded(mesh.tets, static_cast<std::uint64_t>(n), in.remaining(), 10);
  for (std::int64_t t = 0; t < n; ++t) {
    const auto tok = need_tokens(in, "tetrahedra", n, t);
    if (tok.size() != width)
      in.fail("tetrahedron line needs " + std::to_string(width) + " values, got " + std::to_string(tok.size()));
    const std::string what = "tetrahedron " + std::string(tok[0]);
    numbering.add_element(in.to_int(tok[0], "a tetrahedron index"), in.line());
    Tet tet{};
    for (std::size_t k = 0; k < 4; ++k) tet[k] = vertex(in, tok[1 + k], nodes, what);
    for (std::size_t k = 5; k < 1 + static_cast<std::size_t>(per); ++k) (void)vertex(in, tok[k], nodes, what);
    mesh.tets.push_back(tet);
    if (attrs > 0) mesh.tet_regions.push_back(integer_label(in, tok[1 + static_cast<std::size_t>(per)], "region attribute"));
    for (std::size_t k = 2 + static_cast<std::size_t>(per); k < tok.size(); ++k) (void)in.to_double(tok[k]);
  }
}

void read_face(std::string_view data, const std::string& file, const Nodes& nodes, std::vector<Triangle>& faces,
               std::vector<int>& markers, FileNumbering& numbering) {
  LineReader in(data, file);
  auto head = content_tokens(in);
  if (head.empty()) in.fail("empty .face file");
  if (head.size() > 2) in.fail("expected '<#faces> <#boundary markers>'");
  const std::int64_t n = in.count(head[0], "face count");
  const std::int64_t has_markers = head.size() > 1 ? in.count(head[1], "boundary marker count") : 0;
  if (has_markers > 1) in.fail_at(head[1], "boundary marker count must be 0 or 1");
  const std::size_t width = 4 + static_cast<std::size_t>(has_markers);
  reserve_bounded(faces, static_cast<std::uint64_t>(n), in.remaining(), 8);
  for (std::int64_t f = 0; f < n; ++f) {
    const auto tok = need_tokens(in, "faces", n, f);
    // Two more columns (adjacent tets, from tetgen -nn) may follow.
    if (tok.size() != width && tok.size() != width + 2)
      in.fail("face line needs " + std::to_string(width) + " values, got " + std::to_string(tok.size()));
    const std::string what = "face " + std::string(tok[0]);
    numbering.add_element(in.to_int(tok[0], "a face index"), in.line());
    Triangle tri{};
    for (std::size_t k = 0; k < 3; ++k) tri[k] = vertex(in, tok[1 + k], nodes, what);
    faces.push_back(tri);
    if (has_markers) markers.push_back(integer_label(in, tok[4], "boundary marker"));
    for (std::size_t k = width; k < tok.size(); ++k) (void)in.to_int(tok[k], "an adjacent tetrahedron");
  }
}

void put_label_line(std::string& out, std::int64_t id, const std::vector<Index>& nodes, const int* label) {
  put_int(out, id);
  for (const Index i : nodes) {
    out += ' ';
    put_int(out, std::int64_t{i} + 1);
  }
  if (label) {
    out += ' ';
    put_int(out, *label);
  }
  out += '\n';
}

}  // namespace

MeshFile parse_tetgen(std::string_view node, const std::string& node_file, const std::string_view* ele,
                      const std::string& ele_file, const std::string_view* face, const std::string& face_file) {
  Nodes nodes = read_node(node, node_file);
  MeshFile out;
  out.format = MeshFormat::tetgen;
  std::vector<Triangle> faces;
  std::vector<int> markers;
  FileNumbering face_numbering("face", nodes.base);
  if (face) read_face(*face, face_file, nodes, faces, markers, face_numbering);
  if (ele) {
    TetMesh mesh;
    out.volume_numbering.vertex_base = nodes.base;
    read_ele(*ele, ele_file, nodes, mesh, out.volume_numbering);
    mesh.vertices = std::move(nodes.points);
    mesh.faces = std::move(faces);
    mesh.face_markers = std::move(markers);
    out.flipped_tets = orient_whole_file(mesh);
    out.volume = std::move(mesh);
  } else {
    TriMesh mesh;
    mesh.vertices = std::move(nodes.points);
    mesh.triangles = std::move(faces);
    out.surface = std::move(mesh);
    out.surface_numbering = std::move(face_numbering);
  }
  return out;
}

std::string format_tetgen_node(const std::vector<Vec3>& vertices) {
  std::string out;
  put_int(out, static_cast<std::int64_t>(vertices.size()));
  out += " 3 0 0\n";
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    put_int(out, static_cast<std::int64_t>(i) + 1);
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      put_double(out, vertices[i][k]);
    }
    out += '\n';
  }
  return out;
}

std::string format_tetgen_face(const std::vector<Triangle>& faces, const std::vector<int>& markers) {
  std::string out;
  put_int(out, static_cast<std::int64_t>(faces.size()));
  out += markers.empty() ? " 0\n" : " 1\n";
  for (std::size_t i = 0; i < faces.size(); ++i)
    put_label_line(out, static_cast<std::int64_t>(i) + 1, {faces[i].begin(), faces[i].end()},
                   markers.empty() ? nullptr : &markers[i]);
  return out;
}

TetGenText format_tetgen(const TetMesh& mesh) {
  TetGenText text;
  text.node = format_tetgen_node(mesh.vertices);
  put_int(text.ele, static_cast<std::int64_t>(mesh.tets.size()));
  text.ele += mesh.tet_regions.empty() ? " 4 0\n" : " 4 1\n";
  for (std::size_t i = 0; i < mesh.tets.size(); ++i)
    put_label_line(text.ele, static_cast<std::int64_t>(i) + 1, {mesh.tets[i].begin(), mesh.tets[i].end()},
                   mesh.tet_regions.empty() ? nullptr : &mesh.tet_regions[i]);
  if (!mesh.faces.empty()) text.face = format_tetgen_face(mesh.faces, mesh.face_markers);
  return text;
}

}  // namespace tactus::mesh::io
