#pragma once
// Rectangular fabric sheets on a structured grid: the mesh of the hang, cantilever and
// picture-frame tests and of the scenes' hanging fabric.
#include <cstdint>
#include <vector>

#include "physics/cloth/cloth_model.hpp"

namespace tactus::physics {

struct SheetGrid {
  ClothMesh cloth;
  int nodes_u = 0, nodes_v = 0;  ///< nodes along warp and weft
  /// The node at grid position (i along warp, j along weft).
  [[nodiscard]] std::int32_t at(int i, int j) const { return j * nodes_u + i; }
};

enum class SheetBending { yarns, hinges };

/// A width × height sheet (warp along `warp_axis` over the width, weft along `weft_axis` over
/// the height, both unit and orthogonal) from `origin`, cut into cells of at most `spacing`,
/// each split into two triangles, the diagonals alternating so that the grid has no preferred
/// slant. (u, v) = distances along warp and weft. It bends along its warp and weft lines, or
/// (hinges) at every interior edge as seed 002 prints it. Throws InputError for
/// non-positive sizes or spacing, axes that are not orthonormal, or more than 4 million nodes.
SheetGrid rectangular_sheet(double width, double height, double spacing, const Vec3& origin = Vec3::Zero(),
                            const Vec3& warp_axis = Vec3::UnitX(), const Vec3& weft_axis = Vec3::UnitY(),
                            SheetBending bending = SheetBending::yarns);

/// Clamps the first `columns` (≥ 2) warp positions of the sheet level, as a stand's bar holds
/// a fabric: returns the nodes to fix, and marks the yarn bends at the clamp's edge (their
/// curvature doubled over half their area: the free side mirrored across the clamp).
std::vector<std::int32_t> clamp_warp_start(SheetGrid& grid, int columns = 2);

}  // namespace tactus::physics
