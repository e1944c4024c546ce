#include "mesh/validate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include <fmt/format.h>

namespace tactus::mesh {

bool ValidationReport::ok() const { return count(Severity::error) == 0; }

std::size_t ValidationReport::count(Severity s) const {
  std::size_t n = 0;
  for (const auto& p : problems)
    if (p.severity == s) n += p.count;
  return n;
}

namespace {

// Shape tolerance: an element whose size measure falls below this fraction of its own
// longest edge (or of the mesh's bounding-box diagonal) is treated as flat.
constexpr double kFlat = 1e-12;

/// Collects messages per kind, keeps the first kMaxMessagesPerKind of each and counts the rest.
class Collector {
 public:
  template <class Fn>
  void add(const std::string& kind, Severity severity, Fn&& message) {
    auto it = std::find_if(kinds_.begin(), kinds_.end(), [&](const Kind& k) { return k.name == kind; });
    if (it == kinds_.end()) it = kinds_.insert(kinds_.end(), Kind{kind, severity, {}, 0});
    if (it->messages.size() < kMaxMessagesPerKind)
      it->messages.push_back(message());
    else
      ++it->omitted;
  }

  ValidationReport finish() {
    ValidationReport report;
    for (auto& k : kinds_) {
      for (auto& m : k.messages) report.problems.push_back({k.severity, std::move(m)});
      if (k.omitted > 0)
        report.problems.push_back({k.severity, fmt::format("... and {} more: {}", k.omitted, k.name), k.omitted});
    }
    return report;
  }

 private:
  struct Kind {
    std::string name;
    Severity severity;
    std::vector<std::string> messages;
    std::size_t omitted;
  };
  std::vector<Kind> kinds_;
};

bool finite(const Vec3& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }

void check_vertices(const std::vector<Vec3>& vertices, Collector& out) {
  for (std::size_t v = 0; v < vertices.size(); ++v)
    if (!finite(vertices[v]))
      out.add("non-finite vertex coordinates", Severity::error, [&] {
        return fmt::format("vertex {}: coordinate is not finite ({} {} {})", v, vertices[v].x(), vertices[v].y(),
                           vertices[v].z());
      });
}

double finite_diagonal(const std::vector<Vec3>& vertices) {
  Aabb box;
  for (const auto& p : vertices)
    if (finite(p)) box.add(p);
  return box.size().norm();
}

template <std::size_t N>
std::string list(const std::array<Index, N>& e) {
  std::string s;
  for (std::size_t i = 0; i < N; ++i) s += fmt::format("{}{}", i ? " " : "", e[i]);
  return s;
}

/// Index range and repeated-vertex checks; false when the element must be skipped.
template <std::size_t N>
bool check_indices(const char* name, std::size_t i, const std::array<Index, N>& e, std::size_t nv,
                   Collector& out) {
  for (Index v : e)
    if (v < 0 || static_cast<std::size_t>(v) >= nv) {
      out.add("vertex indices out of range", Severity::error, [&] {
        return fmt::format("{} {} (vertices {}): vertex index {} out of range (mesh has {} vertices)", name, i,
                           list(e), v, nv);
      });
      return false;
    }
  for (std::size_t a = 0; a < N; ++a)
    for (std::size_t b = a + 1; b < N; ++b)
      if (e[a] == e[b]) {
        out.add("elements with a repeated vertex", Severity::error, [&] {
          return fmt::format("{} {} (vertices {}): vertex {} repeated", name, i, list(e), e[a]);
        });
        return false;
      }
  return true;
}

template <std::size_t N>
void check_duplicates(const char* name, const std::vector<std::array<Index, N>>& elements,
                      const std::vector<char>& usable, Collector& out) {
  std::vector<std::pair<std::array<Index, N>, std::size_t>> sorted;
  for (std::size_t i = 0; i < elements.size(); ++i) {
    if (!usable[i]) continue;
    auto key = elements[i];
    std::sort(key.begin(), key.end());
    sorted.emplace_back(key, i);
  }
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 1; i < sorted.size(); ++i)
    if (sorted[i].first == sorted[i - 1].first) {
      std::size_t first = i - 1;
      while (first > 0 && sorted[first - 1].first == sorted[i].first) --first;
      out.add(fmt::format("duplicate {}s", name), Severity::error, [&] {
        return fmt::format("{} {} (vertices {}): duplicate of {} {}", name, sorted[i].second,
                           list(elements[sorted[i].second]), name, sorted[first].second);
      });
    }
}

void check_unused(std::size_t nv, const std::vector<char>& used, Collector& out) {
  for (std::size_t v = 0; v < nv; ++v)
    if (!used[v])
      out.add("unused vertices", Severity::warning,
              [&] { return fmt::format("vertex {}: unused (no element references it)", v); });
}

std::uint64_t edge_key(Index a, Index b) {
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint64_t>(std::max(a, b));
}

void check_edges(const TriMesh& mesh, const std::vector<char>& usable, const SurfaceChecks& checks,
                 Collector& out) {
  struct Use {
    std::uint64_t key;
    Index from, to;
    std::size_t tri;
    bool operator<(const Use& o) const { return key != o.key ? key < o.key : tri < o.tri; }
  };
  std::vector<Use> uses;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!usable[t]) continue;
    const auto& f = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) uses.push_back({edge_key(f[k], f[(k + 1) % 3]), f[k], f[(k + 1) % 3], t});
  }
  std::sort(uses.begin(), uses.end());
  std::size_t boundary = 0;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    const Index lo = std::min(uses[i].from, uses[i].to), hi = std::max(uses[i].from, uses[i].to);
    if (j - i > 2) {
      out.add("non-manifold edges", Severity::error, [&] {
        std::string tris;
        for (std::size_t k = i; k < j; ++k) tris += fmt::format("{}{}", k > i ? " " : "", uses[k].tri);
        return fmt::format("edge ({}, {}): non-manifold, shared by {} triangles ({})", lo, hi, j - i, tris);
      });
    } else if (j - i == 2 && uses[i].from == uses[i + 1].from) {
      out.add("edges with inconsistent orientation", Severity::error, [&] {
        return fmt::format("edge ({}, {}): inconsistent orientation, triangles {} and {} both traverse it {}->{}",
                           lo, hi, uses[i].tri, uses[i + 1].tri, uses[i].from, uses[i].to);
      });
    } else if (j - i == 1) {
      ++boundary;
      if (checks.require_closed)
        out.add("open boundary edges", Severity::error, [&] {
          return fmt::format("edge ({}, {}): open boundary, used only by triangle {}", lo, hi, uses[i].tri);
        });
    }
    i = j;
  }
  if (boundary > 0 && !checks.require_closed)
    out.add("open surface", Severity::warning,
            [&] { return fmt::format("surface is open: {} boundary edges", boundary); });
}

}  // namespace

ValidationReport validate(const TriMesh& mesh, const SurfaceChecks& checks) {
  Collector out;
  const std::size_t nv = mesh.vertices.size();
  check_vertices(mesh.vertices, out);
  const double diagonal = finite_diagonal(mesh.vertices);

  std::vector<char> usable(mesh.triangles.size(), 0);
  std::vector<char> used(nv, 0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& f = mesh.triangles[t];
    if (!check_indices("triangle", t, f, nv, out)) continue;
    for (Index v : f) used[v] = 1;
    usable[t] = 1;
    const Vec3 &a = mesh.vertices[f[0]], &b = mesh.vertices[f[1]], &c = mesh.vertices[f[2]];
    if (!finite(a) || !finite(b) || !finite(c)) continue;
    const double area = 0.5 * (b - a).cross(c - a).norm();
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    if (area <= kFlat * longest * longest || area <= kFlat * diagonal * diagonal)
      out.add("degenerate triangles", Severity::error, [&] {
        return fmt::format("triangle {} (vertices {}): degenerate, area {:.3g} m² (longest edge {:.3g} m)", t,
                           list(f), area, longest);
      });
  }
  check_edges(mesh, usable, checks, out);
  check_duplicates("triangle", mesh.triangles, usable, out);
  check_unused(nv, used, out);
  return out.finish();
}

ValidationReport validate(const TetMesh& mesh) {
  Collector out;
  const std::size_t nv = mesh.vertices.size();
  check_vertices(mesh.vertices, out);
  const double diagonal = finite_diagonal(mesh.vertices);

  std::vector<char> usable(mesh.tets.size(), 0);
  std::vector<char> used(nv, 0);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const Tet& e = mesh.tets[t];
    if (!check_indices("tetrahedron", t, e, nv, out)) continue;
    for (Index v : e) used[v] = 1;
    usable[t] = 1;
    const Vec3 &a = mesh.vertices[e[0]], &b = mesh.vertices[e[1]], &c = mesh.vertices[e[2]],
               &d = mesh.vertices[e[3]];
    if (!finite(a) || !finite(b) || !finite(c) || !finite(d)) continue;
    const double volume = signed_tet_volume(a, b, c, d);
    const double longest =
        std::max({(b - a).norm(), (c - a).norm(), (d - a).norm(), (c - b).norm(), (d - b).norm(), (d - c).norm()});
    const double flat = std::max(kFlat * longest * longest * longest, kFlat * diagonal * diagonal * diagonal);
    if (std::abs(volume) <= flat)
      out.add("zero-volume tetrahedra", Severity::error, [&] {
        return fmt::format("tetrahedron {} (vertices {}): zero volume ({:.3g} m³, longest edge {:.3g} m)", t,
                           list(e), volume, longest);
      });
    else if (volume < 0.0)
      out.add("inverted tetrahedra", Severity::error, [&] {
        return fmt::format("tetrahedron {} (vertices {}): inverted, volume {:.3g} m³", t, list(e), volume);
      });
  }
  check_duplicates("tetrahedron", mesh.tets, usable, out);

  // A face may bound at most two tets.
  std::vector<std::pair<std::array<Index, 3>, std::size_t>> faces;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    if (!usable[t]) continue;
    for (int k = 0; k < 4; ++k) {
      std::array<Index, 3> key{};
      for (int i = 0, n = 0; i < 4; ++i)
        if (i != k) key[n++] = mesh.tets[t][i];
      std::sort(key.begin(), key.end());
      faces.emplace_back(key, t);
    }
  }
  std::sort(faces.begin(), faces.end());
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i;
    while (j < faces.size() && faces[j].first == faces[i].first) ++j;
    if (j - i > 2)
      out.add("non-manifold faces", Severity::error, [&] {
        std::string tets;
        for (std::size_t k = i; k < j; ++k) tets += fmt::format("{}{}", k > i ? " " : "", faces[k].second);
        return fmt::format("face ({}): non-manifold, shared by {} tetrahedra ({})", list(faces[i].first), j - i,
                           tets);
      });
    i = j;
  }

  // Optional labelled faces and regions that came with a file.
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    check_indices("face", f, mesh.faces[f], nv, out);
  if (!mesh.tet_regions.empty() && mesh.tet_regions.size() != mesh.tets.size())
    out.add("region labels", Severity::error, [&] {
      return fmt::format("tet_regions has {} entries for {} tetrahedra", mesh.tet_regions.size(), mesh.tets.size());
    });
  if (!mesh.face_markers.empty() && mesh.face_markers.size() != mesh.faces.size())
    out.add("face markers", Severity::error, [&] {
      return fmt::format("face_markers has {} entries for {} faces", mesh.face_markers.size(), mesh.faces.size());
    });
  check_unused(nv, used, out);
  return out.finish();
}

}  // namespace tactus::mesh
