#pragma once
// Closed surfaces from implicit functions: ellipsoid blends, marching tetrahedra and
// volume-preserving smoothing.
#include <functional>
#include <vector>

#include "mesh/tri_mesh.hpp"

namespace tactus::mesh {

struct Ellipsoid {
  Vec3 center;
  Vec3 radii;
  /// Approximate signed distance (exact on the surface, negative inside).
  [[nodiscard]] double distance(const Vec3& p) const;
};

/// Smooth minimum (polynomial, blend width k) of the ellipsoids' distances: a union with
/// rounded creases where they meet.
double smooth_union_field(const std::vector<Ellipsoid>& parts, double k, const Vec3& p);

/// The zero level set of `field` (negative inside) over `box` on a grid of spacing `cell`,
/// by marching tetrahedra over cubes split conformingly into six tets. The grid is padded
/// so that the field is positive on its border: the result is closed, manifold and
/// outward oriented, with no degenerate triangles.
TriMesh marching_tetrahedra(const std::function<double(const Vec3&)>& field, const Aabb& box, double cell);

/// Taubin λ/μ smoothing: Laplacian smoothing without the shrinkage. Keeps connectivity.
void taubin_smooth(TriMesh& mesh, int iterations, double lambda = 0.5, double mu = -0.53);

}  // namespace tactus::mesh
