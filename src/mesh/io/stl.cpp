// STL, ASCII and binary. Binary is recognised by its size (84 + 50 n bytes, n from the
// header), not by the word "solid", which many binary files start with too. Triangles
// in STL carry their own corners; corners with exactly equal coordinates are merged so
// that triangles share vertex indices (-0 and +0 count as equal).
#include <bit>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include "core/text.hpp"
#include "mesh/io/io_common.hpp"

namespace tactus::mesh::io {

namespace {

struct KeyHash {
  std::size_t operator()(const std::array<std::uint64_t, 3>& k) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (const auto x : k) h = (h ^ x) * 0x100000001b3ULL + (h >> 29);
    return static_cast<std::size_t>(h);
  }
};

class VertexMerger {
 public:
  explicit VertexMerger(TriMesh& mesh) : mesh_(mesh) {}
  Index add(const Vec3& p) {
    std::array<std::uint64_t, 3> key{};
    for (int k = 0; k < 3; ++k) key[k] = std::bit_cast<std::uint64_t>(p[k] + 0.0);  // -0 -> +0
    const auto [it, inserted] = index_.try_emplace(key, static_cast<Index>(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.push_back(p);
    return it->second;
  }

 private:
  TriMesh& mesh_;
  std::unordered_map<std::array<std::uint64_t, 3>, Index, KeyHash> index_;
};

constexpr std::size_t header_size = 84;
constexpr std::size_t record_size = 50;

MeshFile parse_binary(std::string_view data, const std::string& file, std::uint32_t count) {
  ByteCursor in(data, file, header_size);
  TriMesh mesh;
  VertexMerger merge(mesh);
  mesh.triangles.reserve(count);  // the size check has already matched the count
  for (std::uint32_t t = 0; t < count; ++t) {
    const std::string what = "triangle " + std::to_string(t);
    in.skip(12, what);  // normal: recomputed from the corners when needed
    Triangle tri{};
    for (int c = 0; c < 3; ++c) {
      Vec3 p;
      for (int k = 0; k < 3; ++k) {
        const std::size_t at = in.pos();
        const float f = in.read<float>(what);
        if (!std::isfinite(f)) in.fail_at(at, what + ": coordinate is NaN or infinite");
        p[k] = f;
      }
      tri[c] = merge.add(p);
    }
    in.skip(2, what);  // attribute byte count
    mesh.triangles.push_back(tri);
  }
  MeshFile out;
  out.format = MeshFormat::stl;
  out.surface = std::move(mesh);
  return out;
}

MeshFile parse_ascii(std::string_view data, const std::string& file) {
  LineReader in(data, file);
  TriMesh mesh;
  VertexMerger merge(mesh);
  enum class State { start, solid, facet, loop, end_loop };
  bool seen_solid = false;
  State state = State::start;
  std::vector<Index> loop;
  std::string_view line;
  auto expect = [&](std::string_view got, std::string_view want) {
    if (got != want) in.fail_at(got, "expected '" + std::string(want) + "', got '" + quote(got) + "'");
  };
  while (in.next(line)) {
    const auto tok = text::split(line);
    if (tok.empty()) continue;
    const auto word = tok[0];
    switch (state) {
      case State::start:
        expect(word, "solid");
        seen_solid = true;
        state = State::solid;
        break;
      case State::solid:
        if (word == "endsolid") {
          state = State::start;
        } else {
          expect(word, "facet");
          if (tok.size() != 5 || tok[1] != "normal") in.fail("expected 'facet normal nx ny nz'");
          for (int k = 2; k < 5; ++k) (void)in.to_double(tok[k], "a normal component");
          state = State::facet;
        }
        break;
      case State::facet:
        expect(word, "outer");
        if (tok.size() != 2 || tok[1] != "loop") in.fail("expected 'outer loop'");
        loop.clear();
        state = State::loop;
        break;
      case State::loop:
        if (word == "endloop") {
          if (loop.size() < 3) in.fail("facet has " + std::to_string(loop.size()) + " vertices; needs 3");
          for (std::size_t i = 1; i + 1 < loop.size(); ++i) mesh.triangles.push_back({loop[0], loop[i], loop[i + 1]});
          state = State::end_loop;
        } else {
          expect(word, "vertex");
          if (tok.size() != 4) in.fail("expected 'vertex x y z'");
          loop.push_back(merge.add(Vec3(in.coordinate(tok[1]), in.coordinate(tok[2]), in.coordinate(tok[3]))));
        }
        break;
      case State::end_loop:
        expect(word, "endfacet");
        state = State::solid;
        break;
    }
  }
  if (!seen_solid) in.fail("empty file: no 'solid' found");
  if (state != State::start && state != State::solid) in.fail("unexpected end of file inside a facet");
  if (state == State::solid) in.fail("unexpected end of file: missing 'endsolid'");
  MeshFile out;
  out.format = MeshFormat::stl;
  out.surface = std::move(mesh);
  return out;
}

bool looks_like_text(std::string_view data) {
  for (const char ch : data) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == 0 || (c < 0x20 && c != '\n' && c != '\r' && c != '\t' && c != '\f' && c != '\v') || c >= 0x7f)
      return false;
  }
  return true;
}

}  // namespace

MeshFile parse_stl(std::string_view data, const std::string& file) {
  if (data.size() >= header_size) {
    std::uint32_t count = 0;
    std::memcpy(&count, data.data() + 80, 4);
    if constexpr (std::endian::native == std::endian::big)
      count = (count >> 24) | ((count >> 8) & 0xff00U) | ((count << 8) & 0xff0000U) | (count << 24);
    if (data.size() == header_size + record_size * std::uint64_t{count}) return parse_binary(data, file, count);
    if (!(text::trim(data).starts_with("solid") && looks_like_text(data))) {
      ByteCursor at(data, file);
      at.fail_at(std::min<std::uint64_t>(data.size(), header_size + record_size * std::uint64_t{count}),
                 "binary STL header declares " + std::to_string(count) + " triangles (" +
                     std::to_string(header_size + record_size * std::uint64_t{count}) +
                     " bytes) but the file has " + std::to_string(data.size()) + " bytes (truncated or not an STL)");
    }
  } else if (!looks_like_text(data)) {
    ByteCursor(data, file).fail_at(data.size(), "file too short for binary STL (" + std::to_string(data.size()) +
                                                    " bytes, need at least 84) and not ASCII STL");
  }
  return parse_ascii(data, file);
}

std::string format_stl(const TriMesh& mesh, bool binary) {
  std::string out;
  if (binary) {
    std::string header = "Tactus binary STL";
    header.resize(80, ' ');
    out = header;
    put_le(out, static_cast<std::uint32_t>(mesh.triangles.size()));
    out.reserve(header_size + record_size * mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const Vec3 n = mesh.face_normal(t);
      for (int k = 0; k < 3; ++k) put_le(out, static_cast<float>(n[k]));
      for (const Index i : mesh.triangles[t])
        for (int k = 0; k < 3; ++k) put_le(out, static_cast<float>(mesh.vertices[i][k]));
      put_le(out, std::uint16_t{0});
    }
    return out;
  }
  out = "solid tactus\n";
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3 n = mesh.face_normal(t);
    out += "  facet normal";
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      put_double(out, n[k]);
    }
    out += "\n    outer loop\n";
    for (const Index i : mesh.triangles[t]) {
      out += "      vertex";
      for (int k = 0; k < 3; ++k) {
        out += ' ';
        put_double(out, mesh.vertices[i][k]);
      }
      out += '\n';
    }
    out += "    endloop\n  endfacet\n";
  }
  out += "endsolid tactus\n";
  return out;
}

}  // namespace tactus::mesh::io
