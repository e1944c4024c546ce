// Wavefront OBJ: "v x y z [w | r g b]" and "f a b c ..." with the a, a/t, a//n and
// a/t/n forms; negative indices count back from the last vertex read. Polygons are
// fan-triangulated; every other statement (vt, vn, g, o, s, usemtl, l, ...) is ignored.
#include <cctype>

#include "core/text.hpp"
#include "mesh/io/io_common.hpp"

namespace tactus::mesh::io {

namespace {

bool is_keyword(std::string_view s) {
  if (s.empty() || !std::isalpha(static_cast<unsigned char>(s.front()))) return false;
  for (const char c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  return true;
}

}  // namespace

MeshFile parse_obj(std::string_view data, const std::string& file) {
  LineReader in(data, file);
  TriMesh mesh;
  FileNumbering numbering("face", 1);
  std::int64_t faces = 0;
  std::vector<Index> polygon;
  std::string_view line;
  while (in.next(line)) {
    const auto hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    const auto tok = text::split(line);
    if (tok.empty()) continue;
    if (tok[0] == "v") {
      if (tok.size() < 4) in.fail("vertex needs 3 coordinates, got " + std::to_string(tok.size() - 1));
      if (tok.size() > 8) in.fail_at(tok[8], "too many values for a vertex");
      // Colours or a weight may follow; they are checked as numbers but not kept.
      for (std::size_t i = 4; i < tok.size(); ++i) (void)in.to_double(tok[i]);
      if (mesh.vertices.size() >= static_cast<std::size_t>(INT32_MAX)) in.fail("too many vertices");
      mesh.vertices.emplace_back(in.coordinate(tok[1]), in.coordinate(tok[2]), in.coordinate(tok[3]));
    } else if (tok[0] == "f") {
      if (tok.size() < 4) in.fail("face needs at least 3 vertices, got " + std::to_string(tok.size() - 1));
      polygon.clear();
      for (std::size_t i = 1; i < tok.size(); ++i) {
        const auto slash = tok[i].find('/');
        const auto index_text = tok[i].substr(0, slash);
        const std::int64_t raw = in.to_int(index_text, "a vertex index");
        const auto n = static_cast<std::int64_t>(mesh.vertices.size());
        const std::int64_t index = raw > 0 ? raw - 1 : n + raw;
        if (raw == 0 || index < 0 || index >= n)
          in.fail_at(tok[i], "face vertex index " + std::to_string(raw) + " out of range (" + std::to_string(n) +
                                 " vertices defined so far)");
        polygon.push_back(static_cast<Index>(index));
      }
      ++faces;
      for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
        mesh.triangles.push_back({polygon[0], polygon[i], polygon[i + 1]});
        numbering.add_element(faces, in.line());
      }
    } else if (!is_keyword(tok[0])) {
      in.fail_at(tok[0], "unknown keyword '" + quote(tok[0]) + "'");
    }
  }
  if (mesh.triangles.empty())
    in.fail("no faces to read (" + std::to_string(mesh.vertices.size()) + " vertices, no 'f' statement)");
  MeshFile out;
  out.format = MeshFormat::obj;
  out.surface = std::move(mesh);
  out.surface_numbering = std::move(numbering);
  return out;
}

std::string format_obj(const TriMesh& mesh) {
  std::string out = "# Tactus OBJ\n";
  for (const auto& v : mesh.vertices) {
    out += 'v';
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      put_double(out, v[k]);
    }
    out += '\n';
  }
  for (const auto& t : mesh.triangles) {
    out += 'f';
    for (const Index i : t) {
      out += ' ';
      put_int(out, std::int64_t{i} + 1);
    }
    out += '\n';
  }
  return out;
}

}  // namespace tactus::mesh::io
