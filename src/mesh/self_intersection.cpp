#include "mesh/self_intersection.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>

namespace tactus::mesh {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon() / 2.0;  // unit roundoff
// Shewchuk's first-stage error bounds: a determinant below these (times its permanent)
// may have the wrong sign, so it is taken as zero.
constexpr double kOrient3dBound = (7.0 + 56.0 * kEps) * kEps;
constexpr double kOrient2dBound = (3.0 + 16.0 * kEps) * kEps;

int sign_of(double det, double bound) { return det > bound ? 1 : (det < -bound ? -1 : 0); }

/// Which side of plane abc point d lies on: +1, -1, or 0 within rounding.
int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 ad = a - d, bd = b - d, cd = c - d;
  const double bc = bd.y() * cd.z() - bd.z() * cd.y();
  const double ca = cd.y() * ad.z() - cd.z() * ad.y();
  const double ab = ad.y() * bd.z() - ad.z() * bd.y();
  const double det = ad.x() * bc + bd.x() * ca + cd.x() * ab;
  const double permanent = std::abs(ad.x()) * (std::abs(bd.y() * cd.z()) + std::abs(bd.z() * cd.y())) +
                           std::abs(bd.x()) * (std::abs(cd.y() * ad.z()) + std::abs(cd.z() * ad.y())) +
                           std::abs(cd.x()) * (std::abs(ad.y() * bd.z()) + std::abs(ad.z() * bd.y()));
  return sign_of(det, kOrient3dBound * permanent);
}

using P2 = std::array<double, 2>;

int orient2d(const P2& a, const P2& b, const P2& c) {
  const double left = (a[0] - c[0]) * (b[1] - c[1]);
  const double right = (a[1] - c[1]) * (b[0] - c[0]);
  return sign_of(left - right, kOrient2dBound * (std::abs(left) + std::abs(right)));
}

/// Drops the coordinate along which the plane's normal is largest.
struct Projection {
  int u = 0, v = 1;
  explicit Projection(const Vec3& normal) {
    int drop = 0;
    normal.cwiseAbs().maxCoeff(&drop);
    u = (drop + 1) % 3;
    v = (drop + 2) % 3;
  }
  [[nodiscard]] P2 operator()(const Vec3& p) const { return {p[u], p[v]}; }
};

bool on_segment(const P2& a, const P2& b, const P2& p) {  // p collinear with ab
  return std::min(a[0], b[0]) <= p[0] && p[0] <= std::max(a[0], b[0]) && std::min(a[1], b[1]) <= p[1] &&
         p[1] <= std::max(a[1], b[1]);
}

bool segments_meet_2d(const P2& p, const P2& q, const P2& r, const P2& s) {
  const int d1 = orient2d(r, s, p), d2 = orient2d(r, s, q), d3 = orient2d(p, q, r), d4 = orient2d(p, q, s);
  if (d1 * d2 < 0 && d3 * d4 < 0) return true;
  return (d1 == 0 && on_segment(r, s, p)) || (d2 == 0 && on_segment(r, s, q)) ||
         (d3 == 0 && on_segment(p, q, r)) || (d4 == 0 && on_segment(p, q, s));
}

bool inside_2d(const P2& a, const P2& b, const P2& c, const P2& p) {
  const int o1 = orient2d(a, b, p), o2 = orient2d(b, c, p), o3 = orient2d(c, a, p);
  return (o1 >= 0 && o2 >= 0 && o3 >= 0) || (o1 <= 0 && o2 <= 0 && o3 <= 0);
}

/// Does segment pq meet triangle abc (boundary included)?
bool segment_meets_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const int sp = orient3d(a, b, c, p), sq = orient3d(a, b, c, q);
  if (sp * sq > 0) return false;
  if (sp == 0 && sq == 0) {  // in the triangle's plane
    const Projection pr((b - a).cross(c - a));
    const P2 p2 = pr(p), q2 = pr(q), a2 = pr(a), b2 = pr(b), c2 = pr(c);
    return inside_2d(a2, b2, c2, p2) || inside_2d(a2, b2, c2, q2) || segments_meet_2d(p2, q2, a2, b2) ||
           segments_meet_2d(p2, q2, b2, c2) || segments_meet_2d(p2, q2, c2, a2);
  }
  // The line pq passes through the triangle when it turns the same way round all three edges.
  const int s1 = orient3d(p, q, a, b), s2 = orient3d(p, q, b, c), s3 = orient3d(p, q, c, a);
  return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

/// Two triangles meet iff an edge of one meets the other (a crossing ends on such an
/// edge; a triangle inside a coplanar one has its edges inside it).
bool triangles_meet(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
  for (int k = 0; k < 3; ++k) {
    if (segment_meets_triangle(a[k], a[(k + 1) % 3], b[0], b[1], b[2])) return true;
    if (segment_meets_triangle(b[k], b[(k + 1) % 3], a[0], a[1], a[2])) return true;
  }
  return false;
}

/// Triangles (u, w, a) and (u, w, b) sharing edge uw overlap only when folded flat onto
/// each other: b in a's plane and on a's side of the edge.
bool folded_onto_each_other(const Vec3& u, const Vec3& w, const Vec3& a, const Vec3& b) {
  if (orient3d(u, w, a, b) != 0) return false;
  const Projection pr((w - u).cross(a - u));
  const int sa = orient2d(pr(u), pr(w), pr(a)), sb = orient2d(pr(u), pr(w), pr(b));
  return sa != 0 && sa == sb;
}

/// The pair's verdict given which corners they share (by welded vertex id).
bool overlap_beyond_shared(const TriMesh& m, const Triangle& ta, const Triangle& tb) {
  const auto& V = m.vertices;
  int shared = 0, ia = -1, ib = -1;  // the last shared corner in each
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (ta[i] == tb[j]) {
        ++shared;
        ia = i;
        ib = j;
      }
  if (shared == 0) return triangles_meet({V[ta[0]], V[ta[1]], V[ta[2]]}, {V[tb[0]], V[tb[1]], V[tb[2]]});
  if (shared == 1) {
    // Beyond the common vertex, a crossing ends on the edge opposite it in one of them.
    return segment_meets_triangle(V[ta[(ia + 1) % 3]], V[ta[(ia + 2) % 3]], V[tb[0]], V[tb[1]], V[tb[2]]) ||
           segment_meets_triangle(V[tb[(ib + 1) % 3]], V[tb[(ib + 2) % 3]], V[ta[0]], V[ta[1]], V[ta[2]]);
  }
  if (shared == 2) {
    int oa = 0, ob = 0;  // the corner each does not share
    for (int i = 0; i < 3; ++i) {
      if (std::find(tb.begin(), tb.end(), ta[i]) == tb.end()) oa = i;
      if (std::find(ta.begin(), ta.end(), tb[i]) == ta.end()) ob = i;
    }
    return folded_onto_each_other(V[ta[(oa + 1) % 3]], V[ta[(oa + 2) % 3]], V[ta[oa]], V[tb[ob]]);
  }
  return false;  // the same three vertices: a duplicate triangle, reported as such
}

}  // namespace

SelfIntersections find_self_intersections(const TriMesh& mesh, const std::vector<char>& skip, double weld_tolerance,
                                          std::size_t keep) {
  SelfIntersections result;
  TriMesh welded;
  welded.vertices = mesh.vertices;
  // Corners within the tolerance count as one, so that an unwelded (triangle soup) surface's
  // neighbours share them.
  std::vector<Index> id(mesh.vertices.size());
  std::iota(id.begin(), id.end(), 0);
  for (const auto& [v, first] : find_duplicate_vertices(mesh.vertices, weld_tolerance)) id[v] = id[first];
  std::vector<std::uint32_t> tris;  // the triangles taking part
  Aabb all;
  double extent_sum = 0.0;
  struct Box {
    Vec3 lo, hi;
  };
  std::vector<Box> box(mesh.triangles.size());
  welded.triangles.resize(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (t < skip.size() && skip[t]) continue;
    const auto& f = mesh.triangles[t];
    welded.triangles[t] = {id[f[0]], id[f[1]], id[f[2]]};
    box[t] = {mesh.vertices[f[0]].cwiseMin(mesh.vertices[f[1]]).cwiseMin(mesh.vertices[f[2]]),
              mesh.vertices[f[0]].cwiseMax(mesh.vertices[f[1]]).cwiseMax(mesh.vertices[f[2]])};
    all.add(box[t].lo);
    all.add(box[t].hi);
    extent_sum += (box[t].hi - box[t].lo).maxCoeff();
    tris.push_back(static_cast<std::uint32_t>(t));
  }
  if (tris.size() < 2) return result;

  // Cells about the size of a triangle; doubled while large triangles would fill too many.
  const Vec3 span = all.size();
  double h = std::max({extent_sum / static_cast<double>(tris.size()), span.maxCoeff() / double(1 << 20),
                       std::numeric_limits<double>::min()});
  std::vector<std::array<std::int32_t, 6>> cells(mesh.triangles.size());
  const auto cell = [&](double x, int axis) {
    return static_cast<std::int32_t>(std::min((x - all.min[axis]) / h, double(1 << 20)));
  };
  std::uint64_t entries = 0;
  for (;;) {
    entries = 0;
    for (const auto t : tris) {
      auto& c = cells[t];
      std::uint64_t n = 1;
      for (int a = 0; a < 3; ++a) {
        c[a] = cell(box[t].lo[a], a);
        c[a + 3] = cell(box[t].hi[a], a);
        n *= static_cast<std::uint64_t>(c[a + 3] - c[a] + 1);
      }
      entries += n;
    }
    if (entries <= 8 * tris.size() + 1024) break;
    h *= 2.0;
  }
  const auto key = [](std::int32_t x, std::int32_t y, std::int32_t z) {
    return (static_cast<std::uint64_t>(x) << 42) | (static_cast<std::uint64_t>(y) << 21) |
           static_cast<std::uint64_t>(z);
  };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> grid;
  grid.reserve(entries);
  for (const auto t : tris) {
    const auto& c = cells[t];
    for (std::int32_t x = c[0]; x <= c[3]; ++x)
      for (std::int32_t y = c[1]; y <= c[4]; ++y)
        for (std::int32_t z = c[2]; z <= c[5]; ++z) grid.emplace_back(key(x, y, z), t);
  }
  std::sort(grid.begin(), grid.end());

  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t i = 0; i < grid.size();) {
    std::size_t j = i;
    while (j < grid.size() && grid[j].first == grid[i].first) ++j;
    for (std::size_t p = i; p < j; ++p)
      for (std::size_t q = p + 1; q < j; ++q) {
        const std::uint32_t a = grid[p].second, b = grid[q].second;
        if ((box[a].hi.array() < box[b].lo.array()).any() || (box[b].hi.array() < box[a].lo.array()).any())
          continue;
        // Test each pair once: in the lowest cell both occupy.
        const auto &ca = cells[a], &cb = cells[b];
        if (key(std::max(ca[0], cb[0]), std::max(ca[1], cb[1]), std::max(ca[2], cb[2])) != grid[i].first) continue;
        if (overlap_beyond_shared(welded, welded.triangles[a], welded.triangles[b]))
          pairs.emplace_back(std::min(a, b), std::max(a, b));
      }
    i = j;
  }
  result.count = pairs.size();
  const std::size_t shown = std::min(keep, pairs.size());
  std::partial_sort(pairs.begin(), pairs.begin() + static_cast<std::ptrdiff_t>(shown), pairs.end());
  result.first.assign(pairs.begin(), pairs.begin() + static_cast<std::ptrdiff_t>(shown));
  return result;
}

std::vector<std::pair<std::size_t, std::size_t>> find_duplicate_vertices(const std::vector<Vec3>& vertices,
                                                                         double tolerance) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  Aabb all;
  for (const auto& p : vertices)
    if (p.allFinite()) all.add(p);
  if (all.empty()) return out;
  // Cells four tolerances wide: a vertex looks into a neighbouring cell only when it lies
  // within the tolerance of that side.
  const double cell = 4.0 * std::max(tolerance, all.size().maxCoeff() * 1e-15 + std::numeric_limits<double>::min());
  using Key = std::array<std::int64_t, 3>;
  std::vector<std::pair<Key, std::size_t>> sorted;
  sorted.reserve(vertices.size());
  const auto key_of = [&](const Vec3& p) {
    Key k{};
    for (int a = 0; a < 3; ++a) k[a] = static_cast<std::int64_t>(std::floor((p[a] - all.min[a]) / cell));
    return k;
  };
  for (std::size_t v = 0; v < vertices.size(); ++v)
    if (vertices[v].allFinite()) sorted.emplace_back(key_of(vertices[v]), v);
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    const Vec3& p = vertices[v];
    if (!p.allFinite()) continue;
    const Key k = key_of(p);
    std::array<std::array<int, 3>, 3> offsets{};  // per axis: the offsets to look at, then 2 = unused
    std::array<int, 3> counts{};
    for (int a = 0; a < 3; ++a) {
      const double inside = (p[a] - all.min[a]) - static_cast<double>(k[a]) * cell;
      offsets[a][counts[a]++] = 0;
      if (inside <= tolerance) offsets[a][counts[a]++] = -1;
      if (inside >= cell - tolerance) offsets[a][counts[a]++] = 1;
    }
    std::size_t lowest = v;
    for (int i = 0; i < counts[0]; ++i)
      for (int j = 0; j < counts[1]; ++j)
        for (int l = 0; l < counts[2]; ++l) {
          const Key nk{k[0] + offsets[0][i], k[1] + offsets[1][j], k[2] + offsets[2][l]};
          auto it = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(nk, std::size_t{0}));
          for (; it != sorted.end() && it->first == nk && it->second < lowest; ++it)
            if ((vertices[it->second] - p).norm() <= tolerance) lowest = it->second;
        }
    if (lowest != v) out.emplace_back(v, lowest);
  }
  return out;
}

}  // namespace tactus::mesh
