#pragma once
// Mesh generators. Sizes in metres; every closed surface is outward oriented.
#include <array>
#include <vector>

#include "mesh/tet_mesh.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::mesh {

/// A quad sheet (the surface mass-spring of seed 004 uses quads).
struct QuadMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<Index, 4>> quads;  ///< counter-clockwise seen from +normal
  [[nodiscard]] TriMesh triangulated() const;
};

/// Plate in the z = 0 plane centred at the origin, normal +z, cells_x × cells_y cells.
QuadMesh grid_plate_quads(double size_x, double size_y, int cells_x, int cells_y);
TriMesh grid_plate(double size_x, double size_y, int cells_x, int cells_y);

/// Closed box surface centred at the origin with `cells` subdivisions per edge.
TriMesh box_surface(const Vec3& size, int cells = 1);
/// Box volume centred at the origin: cells_x × cells_y × cells_z cubes, each split into
/// tetrahedra conformingly.
TetMesh box_volume(const Vec3& size, int cells_x, int cells_y, int cells_z);
/// Icosphere centred at the origin; `subdivisions` 0 gives the icosahedron.
TriMesh sphere(double radius, int subdivisions);
/// Capped cylinder along +z from z = 0 to z = height.
TriMesh cylinder(double radius, double height, int segments, int rings);
/// A smooth closed organ-like shape (an implicit blend of ellipsoids), longest extent
/// `length` along x, centred at the origin; `resolution` cells along the length.
TriMesh organ(double length, int resolution);

}  // namespace tactus::mesh
