#pragma once
// Half-edge connectivity over a TriMesh: one-ring walks (curvature voting), vertex
// normals and boundary loops. Construction rejects non-manifold input.
#include <array>
#include <vector>

#include "mesh/tri_mesh.hpp"

namespace tactus::mesh {

class HalfEdgeMesh {
 public:
  struct HalfEdge {
    Index twin = -1;
    Index next = -1;    ///< next half-edge around the same face (or boundary loop)
    Index vertex = -1;  ///< origin vertex
    Index face = -1;    ///< -1 for a boundary half-edge (outside the surface)
  };

  /// Throws InputError for an index out of range, a repeated vertex in a triangle, an edge
  /// shared by more than two triangles, two triangles traversing an edge in the same
  /// direction (inconsistent orientation) or a vertex whose triangles form several fans.
  explicit HalfEdgeMesh(const TriMesh& mesh);

  [[nodiscard]] std::size_t num_vertices() const { return positions_.size(); }
  [[nodiscard]] std::size_t num_faces() const { return num_faces_; }
  [[nodiscard]] std::size_t num_half_edges() const { return half_edges_.size(); }
  [[nodiscard]] std::size_t num_edges() const { return half_edges_.size() / 2; }
  [[nodiscard]] std::size_t num_boundary_half_edges() const { return half_edges_.size() - 3 * num_faces_; }
  [[nodiscard]] bool closed() const { return num_boundary_half_edges() == 0; }
  /// V - E + F (2 for a closed sphere-like surface).
  [[nodiscard]] long euler_characteristic() const;

  [[nodiscard]] const HalfEdge& half_edge(Index h) const { return half_edges_[h]; }
  [[nodiscard]] Index twin(Index h) const { return half_edges_[h].twin; }
  [[nodiscard]] Index next(Index h) const { return half_edges_[h].next; }
  [[nodiscard]] Index origin(Index h) const { return half_edges_[h].vertex; }
  [[nodiscard]] Index target(Index h) const { return half_edges_[next(h)].vertex; }
  [[nodiscard]] Index face(Index h) const { return half_edges_[h].face; }
  [[nodiscard]] bool is_boundary(Index h) const { return half_edges_[h].face < 0; }

  /// One outgoing half-edge of v; the boundary one when v is on the boundary, so a walk
  /// from it covers the whole fan. -1 for an isolated vertex.
  [[nodiscard]] Index outgoing(Index v) const { return outgoing_[v]; }
  [[nodiscard]] bool is_boundary_vertex(Index v) const {
    return outgoing_[v] >= 0 && is_boundary(outgoing_[v]);
  }
  [[nodiscard]] const Vec3& position(Index v) const { return positions_[v]; }

  /// The three half-edges of face f (face f's half-edges are 3f, 3f+1, 3f+2).
  [[nodiscard]] std::array<Index, 3> face_half_edges(Index f) const { return {3 * f, 3 * f + 1, 3 * f + 2}; }
  [[nodiscard]] Triangle face_vertices(Index f) const {
    return {origin(3 * f), origin(3 * f + 1), origin(3 * f + 2)};
  }

  /// Calls fn(h) for each half-edge leaving v, in order around v.
  template <class Fn>
  void for_each_outgoing(Index v, Fn&& fn) const {
    const Index start = outgoing_[v];
    if (start < 0) return;
    Index h = start;
    do {
      fn(h);
      h = next(twin(h));
    } while (h != start);
  }

  /// Neighbours of v in order around it (each once).
  [[nodiscard]] std::vector<Index> one_ring(Index v) const;
  /// Faces around v.
  [[nodiscard]] std::vector<Index> vertex_faces(Index v) const;
  /// Vertices within `rings` edges of v (v excluded), nearest rings first.
  [[nodiscard]] std::vector<Index> k_ring(Index v, int rings) const;
  /// Unit normals, each face's normal weighted by its angle at the vertex.
  [[nodiscard]] std::vector<Vec3> vertex_normals() const;
  /// Each boundary loop as its vertices in order, following the boundary half-edges
  /// (which run against the adjacent triangles' orientation).
  [[nodiscard]] std::vector<std::vector<Index>> boundary_loops() const;

 private:
  std::vector<Vec3> positions_;
  std::vector<HalfEdge> half_edges_;
  std::vector<Index> outgoing_;
  std::size_t num_faces_ = 0;
};

}  // namespace tactus::mesh
