#pragma once
// Rectangular fabric sheets on a structured grid: the mesh of the hang, cantilever and
// picture-frame tests and of the scenes' hanging fabric.
#include <cstdint>

#include "physics/cloth/cloth_model.hpp"

namespace tactus::physics {

struct SheetGrid {
  ClothMesh cloth;
  int nodes_u = 0, nodes_v = 0;  ///< nodes along warp and weft
  /// The node at grid position (i along warp, j along weft).
  [[nodiscard]] std::int32_t at(int i, int j) const { return j * nodes_u + i; }
};

/// A width × height sheet (warp along `warp_axis` over the width, weft along `weft_axis` over
/// the height, both unit and orthogonal) from `origin`, cut into cells of at most `spacing`,
/// each split into two triangles. (u, v) = distances along warp and weft. Throws InputError for
/// non-positive sizes or spacing, axes that are not orthonormal, or more than 4 million nodes.
SheetGrid rectangular_sheet(double width, double height, double spacing, const Vec3& origin = Vec3::Zero(),
                            const Vec3& warp_axis = Vec3::UnitX(), const Vec3& weft_axis = Vec3::UnitY());

}  // namespace tactus::physics
