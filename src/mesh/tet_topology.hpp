#pragma once
// Adjacency of a tetrahedral mesh (edges, faces, neighbours across faces, vertex→tets)
// and extraction of its boundary surface.
#include <array>
#include <vector>

#include "mesh/tet_mesh.hpp"

namespace tactus::mesh {

/// Local faces of a tet: face i is opposite vertex i, listed counter-clockwise seen from
/// outside a positively oriented tet.
inline constexpr std::array<std::array<int, 3>, 4> kTetFaces{{{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};
/// Local edges of a tet (pairs of local vertices).
inline constexpr std::array<std::array<int, 2>, 6> kTetEdges{{{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};

struct TetTopology {
  /// Throws InputError for an index out of range, a repeated vertex inside a tet, or a
  /// face shared by more than two tets.
  explicit TetTopology(const TetMesh& mesh);

  std::vector<std::array<Index, 2>> edges;     ///< unique edges, smaller vertex first
  std::vector<std::array<Index, 6>> tet_edges;  ///< per tet, in kTetEdges order
  /// Unique faces, oriented as seen from outside face_tets[f][0].
  std::vector<Triangle> faces;
  std::vector<std::array<Index, 2>> face_tets;  ///< [1] is -1 on the boundary
  std::vector<std::array<Index, 4>> tet_faces;  ///< per tet, in kTetFaces order
  /// Neighbour across each local face (opposite vertex i), -1 on the boundary.
  std::vector<std::array<Index, 4>> tet_neighbors;
  /// Tets around each vertex, as offsets into vertex_tet_list (CSR).
  std::vector<Index> vertex_tet_offsets;
  std::vector<Index> vertex_tet_list;

  [[nodiscard]] std::size_t num_vertices() const { return vertex_tet_offsets.size() - 1; }
  /// Tets using vertex v.
  [[nodiscard]] std::vector<Index> vertex_tets(Index v) const {
    return {vertex_tet_list.begin() + vertex_tet_offsets[v], vertex_tet_list.begin() + vertex_tet_offsets[v + 1]};
  }
  [[nodiscard]] bool is_boundary_face(Index f) const { return face_tets[f][1] < 0; }
  [[nodiscard]] std::vector<Index> boundary_faces() const;
};

/// The boundary of a tet mesh as a triangle surface with its own compact vertex numbering.
struct BoundarySurface {
  TriMesh surface;                       ///< outward oriented when the tets are positive
  std::vector<Index> surface_to_volume;  ///< surface vertex → tet-mesh vertex
  std::vector<Index> volume_to_surface;  ///< tet-mesh vertex → surface vertex, -1 if interior
  std::vector<Index> face_tet;           ///< surface triangle → the tet it bounds
};

BoundarySurface extract_boundary(const TetMesh& mesh);
BoundarySurface extract_boundary(const TetMesh& mesh, const TetTopology& topology);

/// Region tag of "outside the mesh" for extract_region_surface's `facing`.
inline constexpr int kOutsideRegion = 0;

/// The faces where tets tagged with one of `inside` meet tets tagged with one of `facing`
/// (kOutsideRegion: the mesh's boundary), oriented out of the `inside` tets, with their own
/// compact vertex numbering: a segmented tissue's outer skin, a fascia between two
/// tissues, a vessel's wall. Needs tet_regions; a tag in both sets is an error of the caller.
BoundarySurface extract_region_surface(const TetMesh& mesh, const TetTopology& topology, const std::vector<int>& inside,
                                       const std::vector<int>& facing);

}  // namespace tactus::mesh
