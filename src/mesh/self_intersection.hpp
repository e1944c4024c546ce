#pragma once
// Where a triangle surface passes through itself, and which vertices coincide: the
// defects that make tetrahedralization fail although every triangle looks fine alone.
#include <cstddef>
#include <utility>
#include <vector>

#include "mesh/tri_mesh.hpp"

namespace tactus::mesh {

struct SelfIntersections {
  std::size_t count = 0;                                 ///< intersecting triangle pairs
  std::vector<std::pair<std::size_t, std::size_t>> first;  ///< the lowest pairs (a < b), sorted
};

/// Pairs of triangles that meet beyond what they share: triangles with a common edge or
/// vertex count only when they overlap past it (a fold onto itself, a crossing).
/// Vertices within `weld_tolerance` of each other count as one corner (duplicates are
/// reported on their own). Triangles flagged in `skip` (bad indices, not finite, flat)
/// take no part. A uniform grid of triangle boxes finds the candidates; orientation tests
/// in double decide, with results within rounding of zero taken as zero (touching counts
/// as meeting).
SelfIntersections find_self_intersections(const TriMesh& mesh, const std::vector<char>& skip,
                                          double weld_tolerance = 0.0, std::size_t keep = 10);

/// Coincident vertices: every vertex within `tolerance` (Euclidean) of a lower-numbered
/// one, paired with the lowest such vertex; sorted by the later vertex.
std::vector<std::pair<std::size_t, std::size_t>> find_duplicate_vertices(const std::vector<Vec3>& vertices,
                                                                         double tolerance);

}  // namespace tactus::mesh
