// Object File Format: "OFF" (also COFF, NOFF, CNOFF, whose extra vertex columns are
// skipped), then "nv nf ne" (possibly on the OFF line itself), nv vertex lines and nf
// face lines "k i1 ... ik [colour]". Polygons are fan-triangulated; '#' starts a comment.
#include "core/text.hpp"
#include "mesh/io/io_common.hpp"

namespace tactus::mesh::io {

namespace {

std::vector<std::string_view> content_tokens(LineReader& in, std::string_view& line) {
  while (in.next(line)) {
    const auto hash = line.find('#');
    auto tok = text::split(hash == std::string_view::npos ? line : line.substr(0, hash));
    if (!tok.empty()) return tok;
  }
  return {};
}

}  // namespace

MeshFile parse_off(std::string_view data, const std::string& file) {
  LineReader in(data, file);
  std::string_view line;
  auto tok = content_tokens(in, line);
  if (tok.empty()) in.fail("empty file: expected 'OFF'");
  const auto head = tok[0];
  if (head != "OFF" && head != "COFF" && head != "NOFF" && head != "CNOFF" && head != "NCOFF")
    in.fail_at(head, "expected 'OFF' header, got '" + quote(head) + "'");
  tok.erase(tok.begin());
  if (!tok.empty() && tok[0] == "BINARY") in.fail_at(tok[0], "binary OFF is not supported; save it as ASCII");
  if (tok.empty()) {
    tok = content_tokens(in, line);
    if (tok.empty()) in.fail("unexpected end of file: expected 'vertices faces edges' counts");
  }
  if (tok.size() < 2 || tok.size() > 3) in.fail("expected 'vertices faces edges' counts");
  const std::int64_t nv = in.count(tok[0], "vertex count");
  const std::int64_t nf = in.count(tok[1], "face count");
  if (tok.size() == 3) (void)in.count(tok[2], "edge count");

  TriMesh mesh;
  reserve_bounded(mesh.vertices, static_cast<std::uint64_t>(nv), in.remaining(), 6);
  for (std::int64_t i = 0; i < nv; ++i) {
    tok = content_tokens(in, line);
    if (tok.empty())
      in.fail("truncated file: end of file while reading " + std::to_string(nv) + " vertices: got " +
              std::to_string(i));
    if (tok.size() < 3) in.fail("vertex " + std::to_string(i) + " needs 3 coordinates, got " + std::to_string(tok.size()));
    for (std::size_t k = 3; k < tok.size(); ++k) (void)in.to_double(tok[k]);
    mesh.vertices.emplace_back(in.coordinate(tok[0]), in.coordinate(tok[1]), in.coordinate(tok[2]));
  }
  reserve_bounded(mesh.triangles, static_cast<std::uint64_t>(nf), in.remaining(), 8);
  FileNumbering numbering("face", 0);
  for (std::int64_t f = 0; f < nf; ++f) {
    tok = content_tokens(in, line);
    if (tok.empty())
      in.fail("truncated file: end of file while reading " + std::to_string(nf) + " faces: got " +
              std::to_string(f));
    const std::int64_t k = in.count(tok[0], "face vertex count");
    if (k < 3) in.fail_at(tok[0], "face " + std::to_string(f) + " has " + std::to_string(k) + " vertices; needs at least 3");
    if (static_cast<std::int64_t>(tok.size()) - 1 < k)
      in.fail("face " + std::to_string(f) + " lists " + std::to_string(tok.size() - 1) + " indices, expected " +
              std::to_string(k));
    // Anything after the k indices is a colour.
    auto vertex = [&](std::int64_t j) {
      const auto t = tok[static_cast<std::size_t>(j + 1)];
      const std::int64_t v = in.to_int(t, "a vertex index");
      if (v < 0 || v >= nv)
        in.fail_at(t, "face " + std::to_string(f) + " vertex index " + std::to_string(v) + " out of range [0, " +
                          std::to_string(nv) + ")");
      return static_cast<Index>(v);
    };
    const Index first = vertex(0);
    Index prev = vertex(1);
    for (std::int64_t j = 2; j < k; ++j) {
      const Index cur = vertex(j);
      mesh.triangles.push_back({first, prev, cur});
      numbering.add_element(f, in.line());
      prev = cur;
    }
  }
  MeshFile out;
  out.format = MeshFormat::off;
  out.surface = std::move(mesh);
  out.surface_numbering = std::move(numbering);
  return out;
}

std::string format_off(const TriMesh& mesh) {
  std::string out = "OFF\n";
  put_int(out, static_cast<std::int64_t>(mesh.vertices.size()));
  out += ' ';
  put_int(out, static_cast<std::int64_t>(mesh.triangles.size()));
  out += " 0\n";
  for (const auto& v : mesh.vertices) {
    for (int k = 0; k < 3; ++k) {
      if (k) out += ' ';
      put_double(out, v[k]);
    }
    out += '\n';
  }
  for (const auto& t : mesh.triangles) {
    out += '3';
    for (const Index i : t) {
      out += ' ';
      put_int(out, i);
    }
    out += '\n';
  }
  return out;
}

}  // namespace tactus::mesh::io
