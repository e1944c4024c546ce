#include "mesh/implicit_surface.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

namespace tactus::mesh {

double Ellipsoid::distance(const Vec3& p) const {
  // k0·(k0 - 1)/k1 is a good distance estimate near the surface and never zero off it.
  const Vec3 q = p - center;
  const double k0 = q.cwiseQuotient(radii).norm();
  const double k1 = q.cwiseQuotient(radii.cwiseProduct(radii)).norm();
  if (k1 == 0.0) return -radii.minCoeff();
  return k0 * (k0 - 1.0) / k1;
}

double smooth_union_field(const std::vector<Ellipsoid>& parts, double k, const Vec3& p) {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& e : parts) {
    const double di = e.distance(p);
    if (!std::isfinite(d)) {
      d = di;
      continue;
    }
    const double h = std::max(k - std::abs(d - di), 0.0) / k;
    d = std::min(d, di) - h * h * k * 0.25;
  }
  return d;
}

TriMesh marching_tetrahedra(const std::function<double(const Vec3&)>& field, const Aabb& box, double cell) {
  // Two cells of padding keep the surface off the grid border.
  const Vec3 origin = box.min - Vec3::Constant(2.0 * cell);
  std::array<int, 3> n{};  // lattice points per axis
  for (int a = 0; a < 3; ++a) n[a] = static_cast<int>(std::ceil(box.size()[a] / cell)) + 5;
  const auto point_id = [&](int i, int j, int k) { return (static_cast<std::int64_t>(k) * n[1] + j) * n[0] + i; };
  const auto position = [&](int i, int j, int k) { return Vec3(origin + cell * Vec3(i, j, k)); };

  std::vector<double> value(static_cast<std::size_t>(n[0]) * n[1] * n[2]);
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        double f = field(position(i, j, k));
        // No lattice point exactly on the surface: the level set is then a manifold.
        if (std::abs(f) < 1e-9 * cell) f = 1e-9 * cell;
        value[point_id(i, j, k)] = f;
      }

  TriMesh out;
  std::unordered_map<std::uint64_t, Index> edge_vertex;
  struct Corner {
    std::int64_t id;
    Vec3 p;
    double f;
  };
  // One vertex per crossed lattice edge, shared by every tet around it. Keeping it away
  // from the edge ends avoids slivers of triangles.
  const auto crossing = [&](const Corner& a, const Corner& b) {
    const std::int64_t lo = std::min(a.id, b.id), hi = std::max(a.id, b.id);
    const std::uint64_t key = (static_cast<std::uint64_t>(lo) << 32) | static_cast<std::uint64_t>(hi);
    auto [it, inserted] = edge_vertex.try_emplace(key, static_cast<Index>(out.vertices.size()));
    if (inserted) {
      const double t = std::clamp(a.f / (a.f - b.f), 0.1, 0.9);
      out.vertices.push_back(a.p + t * (b.p - a.p));
    }
    return it->second;
  };
  // Orients each triangle so its normal points along `outward`.
  const auto emit = [&](Index a, Index b, Index c, const Vec3& outward) {
    const Vec3 normal = (out.vertices[b] - out.vertices[a]).cross(out.vertices[c] - out.vertices[a]);
    if (normal.dot(outward) >= 0.0)
      out.triangles.push_back({a, b, c});
    else
      out.triangles.push_back({a, c, b});
  };

  std::array<int, 3> perm{0, 1, 2};
  std::vector<std::array<int, 3>> orders;
  do orders.push_back(perm);
  while (std::next_permutation(perm.begin(), perm.end()));

  for (int k = 0; k + 1 < n[2]; ++k)
    for (int j = 0; j + 1 < n[1]; ++j)
      for (int i = 0; i + 1 < n[0]; ++i) {
        const std::array<std::int64_t, 8> ids{point_id(i, j, k),         point_id(i + 1, j, k),
                                              point_id(i, j + 1, k),     point_id(i + 1, j + 1, k),
                                              point_id(i, j, k + 1),     point_id(i + 1, j, k + 1),
                                              point_id(i, j + 1, k + 1), point_id(i + 1, j + 1, k + 1)};
        bool any_in = false, any_out = false;
        for (auto id : ids) (value[id] < 0.0 ? any_in : any_out) = true;
        if (!any_in || !any_out) continue;
        for (const auto& order : orders) {
          // Kuhn tet: walk from corner 000 to 111 one axis at a time.
          std::array<Corner, 4> c;
          std::array<int, 3> g{i, j, k};
          for (int s = 0; s < 4; ++s) {
            if (s > 0) ++g[order[s - 1]];
            const std::int64_t id = point_id(g[0], g[1], g[2]);
            c[s] = {id, position(g[0], g[1], g[2]), value[id]};
          }
          std::array<int, 4> in{}, outside{};
          int n_in = 0, n_out = 0;
          for (int s = 0; s < 4; ++s) (c[s].f < 0.0 ? in[n_in++] : outside[n_out++]) = s;
          if (n_in == 0 || n_out == 0) continue;
          if (n_in == 1 || n_out == 1) {
            // One corner cut off: the triangle separates it from the other three.
            const bool lone_in = n_in == 1;
            const Corner& apex = c[lone_in ? in[0] : outside[0]];
            const auto& others = lone_in ? outside : in;
            const Index a = crossing(apex, c[others[0]]), b = crossing(apex, c[others[1]]),
                        d = crossing(apex, c[others[2]]);
            const Vec3 centroid = (out.vertices[a] + out.vertices[b] + out.vertices[d]) / 3.0;
            emit(a, b, d, lone_in ? Vec3(centroid - apex.p) : Vec3(apex.p - centroid));
          } else {
            // Two in, two out: a quad around the tet, split in two.
            const Corner &p = c[in[0]], &q = c[in[1]], &r = c[outside[0]], &s = c[outside[1]];
            const Index pr = crossing(p, r), ps = crossing(p, s), qs = crossing(q, s), qr = crossing(q, r);
            const Vec3 outward = 0.5 * (r.p + s.p - p.p - q.p);
            emit(pr, ps, qs, outward);
            emit(pr, qs, qr, outward);
          }
        }
      }
  return out;
}

void taubin_smooth(TriMesh& mesh, int iterations, double lambda, double mu) {
  std::vector<std::vector<Index>> neighbours(mesh.vertices.size());
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      neighbours[t[k]].push_back(t[(k + 1) % 3]);
      neighbours[t[k]].push_back(t[(k + 2) % 3]);
    }
  for (auto& nb : neighbours) {
    std::sort(nb.begin(), nb.end());
    nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
  }
  std::vector<Vec3> moved(mesh.vertices.size());
  const auto step = [&](double factor) {
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
      if (neighbours[v].empty()) {
        moved[v] = mesh.vertices[v];
        continue;
      }
      Vec3 mean = Vec3::Zero();
      for (Index w : neighbours[v]) mean += mesh.vertices[w];
      mean /= static_cast<double>(neighbours[v].size());
      moved[v] = mesh.vertices[v] + factor * (mean - mesh.vertices[v]);
    }
    mesh.vertices.swap(moved);
  };
  for (int it = 0; it < iterations; ++it) {
    step(lambda);
    step(mu);
  }
}

}  // namespace tactus::mesh
