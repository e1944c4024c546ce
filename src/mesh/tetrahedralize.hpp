#pragma once
// Quality tetrahedral meshes of closed surfaces, through TetGen.
#include <cstddef>
#include <optional>
#include <string>

#include "mesh/tet_mesh.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::mesh {

/// Bounds on one tetrahedralization. TetGen can refine a thin-walled surface at a strict
/// quality bound for as long as memory lasts, so with a bound it runs in a child process
/// that is killed when the time is up (or that fails to allocate past the cap); the
/// mesh it returns is the same as in-process.
struct TetGenBudget {
  double seconds = 0.0;          ///< wall clock for the whole call; 0 = no limit, in-process
  std::size_t memory_bytes = 0;  ///< the child's address space; 0 = no cap
  [[nodiscard]] bool bounded() const { return seconds > 0.0 || memory_bytes > 0; }
};

struct TetrahedralizeOptions {
  std::optional<double> max_volume;  ///< m³; none = only the quality bound limits size
  double radius_edge_ratio = 1.414;  ///< TetGen's q bound on circumradius / shortest edge
  double min_dihedral_deg = 0.0;     ///< 0 keeps TetGen's default
  bool preserve_surface = false;     ///< no Steiner points on the boundary (TetGen's Y)
  bool quiet = true;                 ///< TetGen prints nothing
  TetGenBudget budget;               ///< none by default
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
/// Throws InputError when the coarsest mesh already has too many nodes, when no bound
/// comes within tolerance, or when the budget (for the whole search) runs out.
NodeCountResult tetrahedralize_to_node_count_detailed(const TriMesh& closed_surface, std::size_t target_nodes,
                                                      double radius_edge_ratio = 1.414, double tolerance = 0.1,
                                                      bool preserve_surface = true, const TetGenBudget& budget = {});
TetMesh tetrahedralize_to_node_count(const TriMesh& closed_surface, std::size_t target_nodes,
                                     double radius_edge_ratio = 1.414, double tolerance = 0.1,
                                     bool preserve_surface = true, const TetGenBudget& budget = {});

}  // namespace tactus::mesh
