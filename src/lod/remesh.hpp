#pragma once
// The two CGAL operations behind the impostor levels, behind a header free of CGAL so that
// CGAL's templates compile in one translation unit (remesh.cpp) alone.
#include <cstddef>

#include "mesh/tri_mesh.hpp"

namespace tactus::lod {

/// Quadric-error edge-collapse decimation (CGAL Surface_mesh_simplification with the
/// Garland–Heckbert plane policies) of a closed, outward-oriented, manifold mesh down to
/// about `target_triangles` triangles (fewer collapses when no collapse keeps the surface a
/// manifold of the same genus). The result is compacted: vertices and triangles renumbered
/// from 0, orientation kept.
[[nodiscard]] mesh::TriMesh decimate(const mesh::TriMesh& input, std::size_t target_triangles);

/// One step of Loop subdivision (CGAL Subdivision_method_3): four triangles per triangle,
/// the old vertices moved by Loop's mask toward the limit surface.
[[nodiscard]] mesh::TriMesh loop_subdivide(const mesh::TriMesh& input);

}  // namespace tactus::lod
