#pragma once
// Quality tetrahedral meshes of closed surfaces, through TetGen.
#include <cstddef>
#include <optional>
#include <string>

#include "mesh/tet_mesh.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::mesh {

struct TetrahedralizeOptions {
  std::optional<double> max_volume;  ///< m³; none = only the quality bound limits size
  double radius_edge_ratio = 1.414;  ///< TetGen's q bound on circumradius / shortest edge
  double min_dihedral_deg = 0.0;     ///< 0 keeps TetGen's default
  bool preserve_surface = false;     ///< no Steiner points on the boundary (TetGen's Y)
  bool quiet = true;                 ///< TetGen prints nothing
};

/// TetGen's command-line switches for these options (always a PLC, zero-based).
std::string tetgen_switches(const TetrahedralizeOptions& options);

/// Tetrahedralizes a closed, manifold, outward-oriented surface. Throws InputError when
/// the surface is not closed or manifold, or when TetGen rejects it (self-intersections,
/// tiny features); every output tet is positively oriented.
TetMesh tetrahedralize(const TriMesh& closed_surface, const TetrahedralizeOptions& options = {});

struct NodeCountResult {
  TetMesh mesh;
  double max_volume;  ///< the bound that produced it
};

/// Searches max_volume (bisection on its logarithm) for a mesh whose node count is within
/// `tolerance` (relative) of `target_nodes`. The surface is kept as given by default:
/// TetGen's quality refinement of a curved surface otherwise adds several times its
/// vertex count on the boundary alone, so the surface's resolution sets the floor.
/// Throws InputError when the coarsest mesh already has too many nodes, or when no bound
/// comes within tolerance.
NodeCountResult tetrahedralize_to_node_count_detailed(const TriMesh& closed_surface, std::size_t target_nodes,
                                                      double radius_edge_ratio = 1.414, double tolerance = 0.1,
                                                      bool preserve_surface = true);
TetMesh tetrahedralize_to_node_count(const TriMesh& closed_surface, std::size_t target_nodes,
                                     double radius_edge_ratio = 1.414, double tolerance = 0.1,
                                     bool preserve_surface = true);

}  // namespace tactus::mesh
