#pragma once
// Colours a surface carries per triangle: a multi-region body's regions (each tetrahedral
// region its material's colour, with a legend entry), and a fabric's stretch (its largest
// in-plane strain on the pressure ramp, blue unstretched to red at full scale).
#include <string>
#include <utility>
#include <vector>

#include "mesh/tri_mesh.hpp"
#include "scene/model.hpp"
#include "viewer/frame.hpp"

namespace tactus::viewer {

struct RegionColours {
  std::vector<Colour> triangles;  ///< per surface triangle; empty: one colour for the body
  std::vector<std::pair<std::string, Colour>> legend;  ///< "body: material" per region shown
};

/// For an fem body with `region_materials` (or a volume whose tets carry several region
/// tags): each surface triangle coloured by the region of the tetrahedron it bounds, by that
/// region's material name (body_colour: "bone" looks like bone). Empty otherwise.
[[nodiscard]] RegionColours region_colours(const scene::Model& model, const scene::Body& body);

/// Each triangle's largest principal Green–Lagrange strain from `rest` to `now` (same
/// numbering), as a colour: 0 (or compression) blue, `full_scale` and beyond red. `out` is
/// resized to the triangles; a degenerate rest triangle is blue.
void strain_colours(const std::vector<Vec3>& rest, const std::vector<Vec3>& now,
                    const std::vector<mesh::Triangle>& triangles, double full_scale, std::vector<Colour>& out);

/// The largest principal Green–Lagrange strain of one triangle's in-plane deformation.
[[nodiscard]] double largest_strain(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& a, const Vec3& b,
                                    const Vec3& c);

}  // namespace tactus::viewer
