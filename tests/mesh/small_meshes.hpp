#pragma once
// Meshes small enough to check by hand, shared by the mesh tests.
#include "mesh/tri_mesh.hpp"

namespace tactus::mesh::test {

/// The closed surface of the unit corner tetrahedron, outward oriented.
inline TriMesh tetrahedron_surface() {
  TriMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

}  // namespace tactus::mesh::test
