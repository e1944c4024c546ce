#include "mesh/tet_topology.hpp"

#include <algorithm>
#include <tuple>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::mesh {

TetTopology::TetTopology(const TetMesh& mesh) {
  const auto nv = static_cast<Index>(mesh.vertices.size());
  const auto nt = static_cast<Index>(mesh.tets.size());
  for (Index t = 0; t < nt; ++t) {
    const Tet& e = mesh.tets[t];
    for (int k = 0; k < 4; ++k)
      if (e[k] < 0 || e[k] >= nv)
        throw InputError(fmt::format("tetrahedron {} (vertices {} {} {} {}): vertex index {} out of range "
                                     "(mesh has {} vertices)",
                                     t, e[0], e[1], e[2], e[3], e[k], nv));
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        if (e[a] == e[b])
          throw InputError(fmt::format("tetrahedron {} (vertices {} {} {} {}): repeated vertex {}", t, e[0],
                                       e[1], e[2], e[3], e[a]));
  }

  // Edges: sort (lo, hi, tet, local edge) and number the unique pairs.
  {
    std::vector<std::tuple<Index, Index, Index, int>> all;
    all.reserve(6 * mesh.tets.size());
    for (Index t = 0; t < nt; ++t)
      for (int k = 0; k < 6; ++k) {
        const Index a = mesh.tets[t][kTetEdges[k][0]], b = mesh.tets[t][kTetEdges[k][1]];
        all.emplace_back(std::min(a, b), std::max(a, b), t, k);
      }
    std::sort(all.begin(), all.end());
    tet_edges.resize(mesh.tets.size());
    for (std::size_t i = 0; i < all.size(); ++i) {
      const auto& [a, b, t, k] = all[i];
      if (i == 0 || std::get<0>(all[i - 1]) != a || std::get<1>(all[i - 1]) != b) edges.push_back({a, b});
      tet_edges[t][k] = static_cast<Index>(edges.size() - 1);
    }
  }

  // Faces: key by sorted vertices; the first tet seen owns the orientation.
  {
    struct Entry {
      std::array<Index, 3> key;
      Index tet;
      int local;
    };
    std::vector<Entry> all;
    all.reserve(4 * mesh.tets.size());
    for (Index t = 0; t < nt; ++t)
      for (int k = 0; k < 4; ++k) {
        std::array<Index, 3> key{mesh.tets[t][kTetFaces[k][0]], mesh.tets[t][kTetFaces[k][1]],
                                 mesh.tets[t][kTetFaces[k][2]]};
        std::sort(key.begin(), key.end());
        all.push_back({key, t, k});
      }
    std::sort(all.begin(), all.end(), [](const Entry& x, const Entry& y) {
      return std::tie(x.key, x.tet, x.local) < std::tie(y.key, y.tet, y.local);
    });
    tet_faces.resize(mesh.tets.size());
    tet_neighbors.assign(mesh.tets.size(), {-1, -1, -1, -1});
    for (std::size_t i = 0; i < all.size();) {
      std::size_t j = i;
      while (j < all.size() && all[j].key == all[i].key) ++j;
      if (j - i > 2)
        throw InputError(fmt::format("face ({} {} {}): non-manifold, shared by {} tetrahedra (first {} and {})",
                                     all[i].key[0], all[i].key[1], all[i].key[2], j - i, all[i].tet,
                                     all[i + 1].tet));
      const auto f = static_cast<Index>(faces.size());
      const Tet& e = mesh.tets[all[i].tet];
      const auto& lf = kTetFaces[all[i].local];
      faces.push_back({e[lf[0]], e[lf[1]], e[lf[2]]});
      face_tets.push_back({all[i].tet, j - i == 2 ? all[i + 1].tet : -1});
      tet_faces[all[i].tet][all[i].local] = f;
      if (j - i == 2) {
        tet_faces[all[i + 1].tet][all[i + 1].local] = f;
        tet_neighbors[all[i].tet][all[i].local] = all[i + 1].tet;
        tet_neighbors[all[i + 1].tet][all[i + 1].local] = all[i].tet;
      }
      i = j;
    }
  }

  // Vertex → tets, compressed rows.
  vertex_tet_offsets.assign(mesh.vertices.size() + 1, 0);
  for (const Tet& e : mesh.tets)
    for (Index v : e) ++vertex_tet_offsets[v + 1];
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) vertex_tet_offsets[v + 1] += vertex_tet_offsets[v];
  vertex_tet_list.resize(4 * mesh.tets.size());
  std::vector<Index> fill(vertex_tet_offsets.begin(), vertex_tet_offsets.end() - 1);
  for (Index t = 0; t < nt; ++t)
    for (Index v : mesh.tets[t]) vertex_tet_list[fill[v]++] = t;
}

std::vector<Index> TetTopology::boundary_faces() const {
  std::vector<Index> result;
  for (Index f = 0; f < static_cast<Index>(faces.size()); ++f)
    if (is_boundary_face(f)) result.push_back(f);
  return result;
}

BoundarySurface extract_boundary(const TetMesh& mesh) { return extract_boundary(mesh, TetTopology(mesh)); }

namespace {

/// Appends the tet-mesh face `tri` (tet-mesh vertex numbers) bounding tet `tet`, numbering
/// its vertices in the surface's order of first use.
void append_face(BoundarySurface& out, const TetMesh& mesh, Triangle tri, Index tet) {
  for (Index& v : tri) {
    if (out.volume_to_surface[v] < 0) {
      out.volume_to_surface[v] = static_cast<Index>(out.surface_to_volume.size());
      out.surface_to_volume.push_back(v);
      out.surface.vertices.push_back(mesh.vertices[v]);
    }
    v = out.volume_to_surface[v];
  }
  out.surface.triangles.push_back(tri);
  out.face_tet.push_back(tet);
}

}  // namespace

BoundarySurface extract_boundary(const TetMesh& mesh, const TetTopology& topology) {
  BoundarySurface out;
  out.volume_to_surface.assign(mesh.vertices.size(), -1);
  for (Index f : topology.boundary_faces()) append_face(out, mesh, topology.faces[f], topology.face_tets[f][0]);
  return out;
}

BoundarySurface extract_region_surface(const TetMesh& mesh, const TetTopology& topology, const std::vector<int>& inside,
                                       const std::vector<int>& facing) {
  if (mesh.tet_regions.size() != mesh.tets.size())
    throw InputError("the mesh tags no regions; a region's surface needs tagged tetrahedra");
  auto in = [](const std::vector<int>& set, int tag) { return std::find(set.begin(), set.end(), tag) != set.end(); };
  auto region = [&](Index t) { return t < 0 ? kOutsideRegion : mesh.tet_regions[static_cast<std::size_t>(t)]; };
  BoundarySurface out;
  out.volume_to_surface.assign(mesh.vertices.size(), -1);
  for (std::size_t f = 0; f < topology.faces.size(); ++f) {
    const auto [first, second] = topology.face_tets[f];
    Triangle tri = topology.faces[f];  // seen from outside `first`
    if (in(inside, region(first)) && in(facing, region(second))) {
      append_face(out, mesh, tri, first);
    } else if (second >= 0 && in(inside, region(second)) && in(facing, region(first))) {
      std::swap(tri[1], tri[2]);
      append_face(out, mesh, tri, second);
    }
  }
  return out;
}

}  // namespace tactus::mesh
