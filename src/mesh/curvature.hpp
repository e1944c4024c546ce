#pragma once
// Curvature at the vertices of a deforming triangle surface by normal voting and
// curvature voting over the q-ring neighbourhood of a vertex (seed 000 §3.2 eq. 5–8,
// after Taubin 1995 and Page et al. 2001/2002). Topology is fixed at construction;
// positions come with every call because the surface deforms every step, and a call
// allocates nothing, so the haptic and interaction loops can query contact vertices.
// Queries are const and share no scratch space: several threads may use one estimator.
//
// Sign convention: with an outward-oriented surface, convex is positive (a sphere of
// radius r seen from outside: k1 = k2 = kmean = +1/r; a cylinder: k1 = 1/r, k2 = 0,
// kmean = 1/(2r)), a plane is zero and concave (inward-facing) regions are negative.
// docs/contact-mechanics.md gives the derivation and the weights.
#include <cstddef>
#include <span>
#include <vector>

#include "core/math.hpp"
#include "mesh/half_edge.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::mesh {

struct VertexCurvature {
  Vec3 normal = Vec3::Zero();      ///< unit voted normal (outward for an outward mesh)
  double k1 = 0.0;                 ///< larger principal curvature, 1/m
  double k2 = 0.0;                 ///< smaller principal curvature, 1/m
  double kmean = 0.0;              ///< (k1 + k2) / 2, 1/m
  Vec3 direction1 = Vec3::Zero();  ///< unit tangent direction of k1
  Vec3 direction2 = Vec3::Zero();  ///< unit tangent direction of k2 (normal × direction1)
  /// False when the neighbourhood gives no answer (isolated vertex, zero area, non-finite
  /// positions); everything else is then zero, so a caller may treat the point as flat.
  bool valid = false;
};

/// How the voted normal curvatures become the curvature tensor.
enum class CurvatureFit {
  /// Weighted least squares for the tensor whose Euler normal curvatures best match the
  /// votes: exact for any spread of directions (default).
  least_squares,
  /// Taubin's matrix (eq. 6) and the fixed map k1 = 3m1 − m2, k2 = 3m2 − m1 (eq. 5):
  /// exact when the directions sample the tangent circle evenly.
  taubin,
};

class CurvatureEstimator {
 public:
  /// Two rings: one ring gives only 5–7 votes from the nearest vertices, too few to
  /// separate three tensor components from triangulation noise; two rings give 12–19 and
  /// still stay within a finger-sized patch at haptic mesh densities.
  static constexpr int kDefaultRings = 2;
  /// More rings smooth away the curvature a finger feels and grow the tables quadratically.
  static constexpr int kMaxRings = 6;

  /// Precomputes every vertex's q-ring (`rings`) neighbourhood and its faces. Throws
  /// InputError when rings is outside [1, kMaxRings].
  explicit CurvatureEstimator(const HalfEdgeMesh& mesh, int rings = kDefaultRings,
                              CurvatureFit fit = CurvatureFit::least_squares);

  [[nodiscard]] int rings() const { return rings_; }
  [[nodiscard]] CurvatureFit fit() const { return fit_; }
  [[nodiscard]] std::size_t num_vertices() const { return vertex_count_; }
  [[nodiscard]] std::size_t num_faces() const { return triangles_.size(); }
  /// Vertices within `rings` edges of v, v excluded (Adj(p) of seed 000 §3.2).
  [[nodiscard]] std::span<const Index> neighbourhood(Index v) const;
  /// Faces whose three vertices lie in v's neighbourhood or are v.
  [[nodiscard]] std::span<const Index> neighbourhood_faces(Index v) const;

  /// Curvature at `vertex` for the current `positions` (one per vertex of the mesh the
  /// estimator was built on). Allocates nothing. Throws InputError when positions has the
  /// wrong size or vertex is out of range.
  [[nodiscard]] VertexCurvature estimate(std::span<const Vec3> positions, Index vertex) const;

  /// Curvature at a point of `triangle` given by barycentric weights of its vertices (as
  /// returned by a closest-point query): the three vertex estimates blended by the weights
  /// (negative weights clamped to zero, then normalised). The mean curvature is the blend
  /// of the means; the principal values come from the blended curvature tensor in the
  /// blended normal's tangent plane. Allocates nothing. Throws InputError for a bad
  /// triangle index or weights with no positive part.
  [[nodiscard]] VertexCurvature estimate_at_point(std::span<const Vec3> positions, Index triangle,
                                                  const Vec3& barycentric) const;

 private:
  void check_positions(std::span<const Vec3> positions) const;
  [[nodiscard]] VertexCurvature estimate_unchecked(std::span<const Vec3> positions, Index vertex) const;
  /// Angle-weighted unit normal of v's incident faces at the current positions.
  [[nodiscard]] Vec3 vertex_normal(std::span<const Vec3> positions, Index v) const;

  int rings_;
  CurvatureFit fit_;
  std::size_t vertex_count_ = 0;
  std::vector<Triangle> triangles_;
  // Compressed rows: entries of vertex v are [offsets[v], offsets[v + 1]).
  std::vector<std::size_t> neighbour_offsets_;
  std::vector<Index> neighbours_;
  std::vector<std::size_t> neighbour_face_offsets_;
  std::vector<Index> neighbour_faces_;
  std::vector<std::size_t> incident_face_offsets_;
  std::vector<Index> incident_faces_;
};

}  // namespace tactus::mesh
