#include "mesh/half_edge.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::mesh {

HalfEdgeMesh::HalfEdgeMesh(const TriMesh& mesh)
    : positions_(mesh.vertices), num_faces_(mesh.triangles.size()) {
  const auto nv = static_cast<Index>(mesh.vertices.size());
  const auto nf = static_cast<Index>(mesh.triangles.size());
  half_edges_.resize(3 * num_faces_);
  for (Index f = 0; f < nf; ++f) {
    const auto& t = mesh.triangles[f];
    for (int k = 0; k < 3; ++k) {
      if (t[k] < 0 || t[k] >= nv)
        throw InputError(fmt::format("triangle {} (vertices {} {} {}): vertex index {} out of range "
                                     "(mesh has {} vertices)",
                                     f, t[0], t[1], t[2], t[k], nv));
    }
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      throw InputError(fmt::format("triangle {} (vertices {} {} {}): repeated vertex", f, t[0], t[1], t[2]));
    for (int k = 0; k < 3; ++k)
      half_edges_[3 * f + k] = {-1, 3 * f + (k + 1) % 3, t[k], f};
  }

  // Group half-edges by undirected edge: sorting keeps errors deterministic.
  std::vector<std::pair<std::uint64_t, Index>> keyed(half_edges_.size());
  for (Index h = 0; h < static_cast<Index>(half_edges_.size()); ++h)
    keyed[h] = {edge_key(origin(h), origin(half_edges_[h].next)), h};
  std::sort(keyed.begin(), keyed.end());

  std::vector<Index> boundary;  // interior half-edges with no twin
  for (std::size_t i = 0; i < keyed.size();) {
    std::size_t j = i;
    while (j < keyed.size() && keyed[j].first == keyed[i].first) ++j;
    const Index h0 = keyed[i].second;
    const Index a = origin(h0), b = target(h0);
    if (j - i > 2) {
      std::string faces;
      for (std::size_t k = i; k < j; ++k) faces += fmt::format("{}{}", k > i ? ", " : "", face(keyed[k].second));
      throw InputError(fmt::format("non-manifold edge ({}, {}): shared by {} triangles ({})",
                                   std::min(a, b), std::max(a, b), j - i, faces));
    }
    if (j - i == 2) {
      const Index h1 = keyed[i + 1].second;
      if (origin(h1) == a)
        throw InputError(fmt::format("inconsistent orientation at edge ({}, {}): triangles {} and {} "
                                     "both traverse it {}->{}",
                                     std::min(a, b), std::max(a, b), std::min(face(h0), face(h1)),
                                     std::max(face(h0), face(h1)), a, b));
      half_edges_[h0].twin = h1;
      half_edges_[h1].twin = h0;
    } else {
      boundary.push_back(h0);
    }
    i = j;
  }

  // Boundary half-edges run opposite to their interior twins and link into loops.
  std::vector<Index> boundary_out(nv, -1);
  for (Index h : boundary) {
    const auto b = static_cast<Index>(half_edges_.size());
    half_edges_.push_back({h, -1, target(h), -1});
    half_edges_[h].twin = b;
    if (boundary_out[target(h)] >= 0)
      throw InputError(fmt::format("non-manifold vertex {}: its triangles meet only at the vertex "
                                   "(several boundary fans)",
                                   target(h)));
    boundary_out[target(h)] = b;
  }
  for (Index b = static_cast<Index>(3 * num_faces_); b < static_cast<Index>(half_edges_.size()); ++b)
    half_edges_[b].next = boundary_out[origin(twin(b))];

  outgoing_.assign(nv, -1);
  for (Index h = 0; h < static_cast<Index>(3 * num_faces_); ++h)
    if (outgoing_[origin(h)] < 0) outgoing_[origin(h)] = h;
  for (Index v = 0; v < nv; ++v)
    if (boundary_out[v] >= 0) outgoing_[v] = boundary_out[v];

  // A vertex whose triangles form several closed fans cannot be walked around.
  std::vector<Index> degree(nv, 0);
  for (Index h = 0; h < static_cast<Index>(half_edges_.size()); ++h) ++degree[origin(h)];
  for (Index v = 0; v < nv; ++v) {
    Index walked = 0;
    for_each_outgoing(v, [&](Index) { ++walked; });
    if (walked != degree[v])
      throw InputError(fmt::format("non-manifold vertex {}: its triangles form more than one fan", v));
  }
}

long HalfEdgeMesh::euler_characteristic() const {
  return static_cast<long>(num_vertices()) - static_cast<long>(num_edges()) +
         static_cast<long>(num_faces());
}

std::vector<Index> HalfEdgeMesh::one_ring(Index v) const {
  std::vector<Index> ring;
  for_each_outgoing(v, [&](Index h) { ring.push_back(target(h)); });
  return ring;
}

std::vector<Index> HalfEdgeMesh::vertex_faces(Index v) const {
  std::vector<Index> faces;
  for_each_outgoing(v, [&](Index h) {
    if (!is_boundary(h)) faces.push_back(face(h));
  });
  return faces;
}

std::vector<Index> HalfEdgeMesh::k_ring(Index v, int rings) const {
  std::vector<Index> result;
  std::vector<Index> frontier{v};
  std::vector<char> seen(num_vertices(), 0);
  seen[v] = 1;
  for (int r = 0; r < rings && !frontier.empty(); ++r) {
    std::vector<Index> next_frontier;
    for (Index u : frontier)
      for_each_outgoing(u, [&](Index h) {
        const Index w = target(h);
        if (!seen[w]) {
          seen[w] = 1;
          next_frontier.push_back(w);
        }
      });
    result.insert(result.end(), next_frontier.begin(), next_frontier.end());
    frontier = std::move(next_frontier);
  }
  return result;
}

std::vector<Vec3> HalfEdgeMesh::vertex_normals() const {
  std::vector<Vec3> normals(num_vertices(), Vec3::Zero());
  for (Index f = 0; f < static_cast<Index>(num_faces_); ++f) {
    const Triangle t = face_vertices(f);
    const Vec3 n = (positions_[t[1]] - positions_[t[0]]).cross(positions_[t[2]] - positions_[t[0]]);
    const double len = n.norm();
    if (len == 0.0) continue;
    for (int k = 0; k < 3; ++k) {
      const Vec3 e1 = positions_[t[(k + 1) % 3]] - positions_[t[k]];
      const Vec3 e2 = positions_[t[(k + 2) % 3]] - positions_[t[k]];
      const double angle = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      normals[t[k]] += angle * n / len;
    }
  }
  for (auto& n : normals) {
    const double len = n.norm();
    if (len > 0.0) n /= len;
  }
  return normals;
}

std::vector<std::vector<Index>> HalfEdgeMesh::boundary_loops() const {
  std::vector<std::vector<Index>> loops;
  std::vector<char> visited(half_edges_.size(), 0);
  for (auto b = static_cast<Index>(3 * num_faces_); b < static_cast<Index>(half_edges_.size()); ++b) {
    if (visited[b]) continue;
    std::vector<Index> loop;
    for (Index h = b; !visited[h]; h = next(h)) {
      visited[h] = 1;
      loop.push_back(origin(h));
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

}  // namespace tactus::mesh
