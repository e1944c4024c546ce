#include "mesh/validate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include <fmt/format.h>

#include "mesh/self_intersection.hpp"

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
  void add(const std::string& kind, Severity severity, Fn&& message, std::size_t limit = kMaxMessagesPerKind) {
    auto it = std::find_if(kinds_.begin(), kinds_.end(), [&](const Kind& k) { return k.name == kind; });
    if (it == kinds_.end()) it = kinds_.insert(kinds_.end(), Kind{kind, severity, {}, 0});
    if (it->messages.size() < limit)
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

/// Names vertices and elements in messages: by the file's numbers and lines when known,
/// else by their 0-based positions.
class Names {
 public:
  Names(const char* element, const FileNumbering* numbering) : element_(element), numbering_(numbering) {}

  [[nodiscard]] std::int64_t vertex(Index v) const { return numbering_ ? numbering_->vertex(v) : v; }

  template <std::size_t N>
  [[nodiscard]] std::string vertices(const std::array<Index, N>& e) const {
    std::string s;
    for (std::size_t i = 0; i < N; ++i) s.append(fmt::format("{}{}", i ? " " : "", vertex(e[i])));
    return s;
  }

  /// "triangle 4", or "face 5 (line 12)" as the file numbers it.
  [[nodiscard]] std::string element(std::size_t i) const {
    if (!numbered(i)) return fmt::format("{} {}", element_, i);
    std::string s = fmt::format("{} {}", word(), numbering_->element_number[i]);
    if (line(i) > 0) s.append(fmt::format(" (line {})", line(i)));
    return s;
  }

  /// "triangle 4 (vertices 1 2 3)", or "face 5 (line 12, vertices 2 3 4)".
  template <std::size_t N>
  [[nodiscard]] std::string element(std::size_t i, const std::array<Index, N>& e) const {
    if (!numbered(i)) return fmt::format("{} {} (vertices {})", element_, i, vertices(e));
    if (line(i) == 0) return fmt::format("{} {} (vertices {})", word(), numbering_->element_number[i], vertices(e));
    return fmt::format("{} {} (line {}, vertices {})", word(), numbering_->element_number[i], line(i), vertices(e));
  }

  [[nodiscard]] const char* plural() const { return element_ == std::string("triangle") ? "triangles" : "tetrahedra"; }

 private:
  [[nodiscard]] bool numbered(std::size_t i) const {
    return numbering_ && i < numbering_->element_number.size();
  }
  [[nodiscard]] std::uint32_t line(std::size_t i) const {
    return i < numbering_->element_line.size() ? numbering_->element_line[i] : 0;
  }
  [[nodiscard]] std::string word() const {
    return numbering_->element_word.empty() ? std::string(element_) : numbering_->element_word;
  }

  const char* element_;
  const FileNumbering* numbering_;
};

void check_vertices(const std::vector<Vec3>& vertices, const Names& names, Collector& out) {
  for (std::size_t v = 0; v < vertices.size(); ++v)
    if (!finite(vertices[v]))
      out.add("non-finite vertex coordinates", Severity::error, [&] {
        return fmt::format("vertex {}: coordinate is not finite ({} {} {})", names.vertex(static_cast<Index>(v)),
                           vertices[v].x(), vertices[v].y(), vertices[v].z());
      });
}

double finite_diagonal(const std::vector<Vec3>& vertices) {
  Aabb box;
  for (const auto& p : vertices)
    if (finite(p)) box.add(p);
  return box.size().norm();
}

/// Index range and repeated-vertex checks; false when the element must be skipped.
template <std::size_t N>
bool check_indices(const Names& names, std::size_t i, const std::array<Index, N>& e, std::size_t nv,
                   Collector& out) {
  for (Index v : e)
    if (v < 0 || static_cast<std::size_t>(v) >= nv) {
      out.add("vertex indices out of range", Severity::error, [&] {
        return fmt::format("{}: vertex index {} out of range (mesh has {} vertices)", names.element(i, e),
                           names.vertex(v), nv);
      });
      return false;
    }
  for (std::size_t a = 0; a < N; ++a)
    for (std::size_t b = a + 1; b < N; ++b)
      if (e[a] == e[b]) {
        out.add("elements with a repeated vertex", Severity::error, [&] {
          return fmt::format("{}: vertex {} repeated", names.element(i, e), names.vertex(e[a]));
        });
        return false;
      }
  return true;
}

template <std::size_t N>
void check_duplicates(const Names& names, const std::vector<std::array<Index, N>>& elements,
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
      out.add(fmt::format("duplicate {}", names.plural()), Severity::error, [&] {
        return fmt::format("{}: duplicate of {} (the same vertices)",
                           names.element(sorted[i].second, elements[sorted[i].second]),
                           names.element(sorted[first].second));
      });
    }
}

void check_unused(std::size_t nv, const std::vector<char>& used, const Names& names, Collector& out) {
  for (std::size_t v = 0; v < nv; ++v)
    if (!used[v])
      out.add("unused vertices", Severity::warning, [&] {
        return fmt::format("vertex {}: unused (no element references it)", names.vertex(static_cast<Index>(v)));
      });
}

void check_coincident(const std::vector<Vec3>& vertices, double diagonal, const Names& names, Collector& out) {
  const double tolerance = kCoincidentVertices * diagonal;
  // Pairs, not structured bindings: clang 14 does not let a lambda capture those.
  for (const auto& pair : find_duplicate_vertices(vertices, tolerance))
    out.add("duplicate vertices", Severity::warning, [&, v = pair.first, first = pair.second] {
      return fmt::format("vertex {}: coincides with vertex {} (within {:.3g} m, {:g} of the bounding-box diagonal)",
                         names.vertex(static_cast<Index>(v)), names.vertex(static_cast<Index>(first)), tolerance,
                         kCoincidentVertices);
    });
}

void check_edges(const TriMesh& mesh, const std::vector<char>& usable, const SurfaceChecks& checks,
                 const Names& names, Collector& out) {
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
    const auto edge = [&] { return fmt::format("edge ({}, {})", names.vertex(lo), names.vertex(hi)); };
    if (j - i > 2) {
      out.add("non-manifold edges", Severity::error, [&] {
        std::string tris;
        for (std::size_t k = i; k < j; ++k) tris.append(fmt::format("{}{}", k > i ? ", " : "", names.element(uses[k].tri)));
        return fmt::format("{}: non-manifold, shared by {} triangles ({})", edge(), j - i, tris);
      });
    } else if (j - i == 2 && uses[i].from == uses[i + 1].from) {
      out.add("edges with inconsistent orientation", Severity::error, [&] {
        return fmt::format("{}: inconsistent orientation, {} and {} both traverse it {}->{}", edge(),
                           names.element(uses[i].tri), names.element(uses[i + 1].tri), names.vertex(uses[i].from),
                           names.vertex(uses[i].to));
      });
    } else if (j - i == 1) {
      ++boundary;
      if (checks.require_closed)
        out.add("open boundary edges", Severity::error, [&] {
          return fmt::format("{}: open boundary, used only by {}", edge(), names.element(uses[i].tri));
        });
    }
    i = j;
  }
  if (boundary > 0 && !checks.require_closed)
    out.add("open surface", Severity::warning,
            [&] { return fmt::format("surface is open: {} boundary edges", boundary); });
}

/// `skip`: triangles already reported as unusable, not finite or flat (a flat one has no plane to test against).
void check_self_intersections(const TriMesh& mesh, const std::vector<char>& skip, double diagonal,
                              const Names& names, Collector& out) {
  const auto found = find_self_intersections(mesh, skip, kCoincidentVertices * diagonal, kSelfIntersectionsShown);
  if (found.count == 0) return;
  out.add("self-intersection", Severity::error, [&] {
    return fmt::format("surface intersects itself: {} {} of triangles cross or overlap", found.count,
                       found.count == 1 ? "pair" : "pairs");
  });
  for (const auto& pair : found.first)
    out.add("intersecting triangle pairs", Severity::error, [&, a = pair.first, b = pair.second] {
      return fmt::format("{} and {} intersect", names.element(a, mesh.triangles[a]),
                         names.element(b, mesh.triangles[b]));
    }, kSelfIntersectionsShown);
}

}  // namespace

ValidationReport validate(const TriMesh& mesh, const SurfaceChecks& checks, const FileNumbering* numbering) {
  Collector out;
  const Names names("triangle", numbering);
  const std::size_t nv = mesh.vertices.size();
  check_vertices(mesh.vertices, names, out);
  const double diagonal = finite_diagonal(mesh.vertices);

  std::vector<char> usable(mesh.triangles.size(), 0);
  std::vector<char> skip_intersections(mesh.triangles.size(), 1);
  std::vector<char> used(nv, 0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& f = mesh.triangles[t];
    if (!check_indices(names, t, f, nv, out)) continue;
    for (Index v : f) used[v] = 1;
    usable[t] = 1;
    const Vec3 &a = mesh.vertices[f[0]], &b = mesh.vertices[f[1]], &c = mesh.vertices[f[2]];
    if (!finite(a) || !finite(b) || !finite(c)) continue;
    const double area = 0.5 * (b - a).cross(c - a).norm();
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const bool flat = area <= kFlat * longest * longest || area <= kFlat * diagonal * diagonal;
    skip_intersections[t] = flat;
    if (flat)
      out.add("degenerate triangles", Severity::error, [&] {
        return fmt::format("{}: degenerate, area {:.3g} m² (longest edge {:.3g} m)", names.element(t, f), area,
                           longest);
      });
  }
  check_edges(mesh, usable, checks, names, out);
  check_duplicates(names, mesh.triangles, usable, out);
  check_self_intersections(mesh, skip_intersections, diagonal, names, out);
  check_coincident(mesh.vertices, diagonal, names, out);
  check_unused(nv, used, names, out);
  return out.finish();
}

ValidationReport validate(const TetMesh& mesh, const FileNumbering* numbering) {
  Collector out;
  const Names names("tetrahedron", numbering);
  const std::size_t nv = mesh.vertices.size();
  check_vertices(mesh.vertices, names, out);
  const double diagonal = finite_diagonal(mesh.vertices);

  std::vector<char> usable(mesh.tets.size(), 0);
  std::vector<char> used(nv, 0);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const Tet& e = mesh.tets[t];
    if (!check_indices(names, t, e, nv, out)) continue;
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
        return fmt::format("{}: zero volume ({:.3g} m³, longest edge {:.3g} m)", names.element(t, e), volume,
                           longest);
      });
    else if (volume < 0.0)
      out.add("inverted tetrahedra", Severity::error, [&] {
        return fmt::format("{}: inverted, volume {:.3g} m³", names.element(t, e), volume);
      });
  }
  check_duplicates(names, mesh.tets, usable, out);

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
        for (std::size_t k = i; k < j; ++k) tets.append(fmt::format("{}{}", k > i ? ", " : "", names.element(faces[k].second)));
        return fmt::format("face ({}): non-manifold, shared by {} tetrahedra ({})", names.vertices(faces[i].first),
                           j - i, tets);
      });
    i = j;
  }

  // Optional labelled faces and regions that came with a file.
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    check_indices(Names("face", nullptr), f, mesh.faces[f], nv, out);
  if (!mesh.tet_regions.empty() && mesh.tet_regions.size() != mesh.tets.size())
    out.add("region labels", Severity::error, [&] {
      return fmt::format("tet_regions has {} entries for {} tetrahedra", mesh.tet_regions.size(), mesh.tets.size());
    });
  if (!mesh.face_markers.empty() && mesh.face_markers.size() != mesh.faces.size())
    out.add("face markers", Severity::error, [&] {
      return fmt::format("face_markers has {} entries for {} faces", mesh.face_markers.size(), mesh.faces.size());
    });
  check_coincident(mesh.vertices, diagonal, names, out);
  check_unused(nv, used, names, out);
  return out.finish();
}

}  // namespace tactus::mesh
