#include "mesh/tet_topology.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "mesh/generators.hpp"
#include "mesh/half_edge.hpp"
#include "mesh/validate.hpp"

namespace tactus::mesh {
namespace {

TEST(TetTopology, SingleTet) {
  TetMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  const TetTopology topo(m);
  EXPECT_EQ(topo.edges.size(), 6u);
  EXPECT_EQ(topo.faces.size(), 4u);
  for (Index n : topo.tet_neighbors[0]) EXPECT_EQ(n, -1);
  const BoundarySurface b = extract_boundary(m, topo);
  EXPECT_NEAR(b.surface.signed_volume(), 1.0 / 6.0, 1e-15);
}

TEST(TetTopology, BoxVolumeAdjacency) {
  const TetMesh m = box_volume(Vec3(1, 1, 1), 2, 2, 2);
  const TetTopology topo(m);
  // 8 cubes × 6 tets; lattice 3³ points; Euler for a ball: V - E + F - T = 1.
  EXPECT_EQ(m.tets.size(), 48u);
  EXPECT_EQ(static_cast<long>(m.vertices.size()) - static_cast<long>(topo.edges.size()) +
                static_cast<long>(topo.faces.size()) - static_cast<long>(m.tets.size()),
            1);
  for (Index t = 0; t < static_cast<Index>(m.tets.size()); ++t)
    for (int k = 0; k < 4; ++k) {
      const Index n = topo.tet_neighbors[t][k];
      if (n < 0) continue;
      // The neighbour points back across the same face.
      const auto& back = topo.tet_neighbors[n];
      EXPECT_NE(std::find(back.begin(), back.end(), t), back.end());
      EXPECT_EQ(topo.tet_faces[t][k], topo.tet_faces[n][std::find(back.begin(), back.end(), t) - back.begin()]);
    }
  for (Index v = 0; v < static_cast<Index>(m.vertices.size()); ++v)
    for (Index t : topo.vertex_tets(v)) EXPECT_NE(std::find(m.tets[t].begin(), m.tets[t].end(), v), m.tets[t].end());
  EXPECT_EQ(topo.vertex_tet_list.size(), 4 * m.tets.size());
}

TEST(TetTopology, BoundaryOfBoxVolumeIsClosedAndOutward) {
  const int nx = 3, ny = 2, nz = 4;
  const Vec3 size(0.3, 0.2, 0.5);
  const TetMesh m = box_volume(size, nx, ny, nz);
  const BoundarySurface b = extract_boundary(m);
  // Two triangles per surface cell.
  EXPECT_EQ(b.surface.triangles.size(), static_cast<std::size_t>(2 * 2 * (nx * ny + ny * nz + nx * nz)));
  EXPECT_NEAR(b.surface.signed_volume(), m.volume(), 1e-12);
  EXPECT_NEAR(m.volume(), size.prod(), 1e-12);
  const HalfEdgeMesh he(b.surface);
  EXPECT_TRUE(he.closed());
  EXPECT_EQ(he.euler_characteristic(), 2);
  EXPECT_TRUE(validate(b.surface, {.require_closed = true}).ok());
  // Vertex maps are inverse to each other; interior lattice points map to -1.
  for (std::size_t s = 0; s < b.surface_to_volume.size(); ++s) {
    EXPECT_EQ(b.volume_to_surface[b.surface_to_volume[s]], static_cast<Index>(s));
    EXPECT_EQ(b.surface.vertices[s], m.vertices[b.surface_to_volume[s]]);
  }
  std::size_t interior = 0;
  for (Index s : b.volume_to_surface) interior += s < 0;
  EXPECT_EQ(interior, static_cast<std::size_t>((nx - 1) * (ny - 1) * (nz - 1)));
  // Every boundary triangle's tet has that face among its own.
  for (std::size_t f = 0; f < b.face_tet.size(); ++f) {
    const Tet& t = m.tets[b.face_tet[f]];
    for (Index v : b.surface.triangles[f])
      EXPECT_NE(std::find(t.begin(), t.end(), b.surface_to_volume[v]), t.end());
  }
}

/// A 3 × 1 × 1 box of unit cubes tagged 1, 2, 3 along x.
TetMesh three_regions() {
  TetMesh m = box_volume(Vec3(3, 1, 1), 3, 1, 1);
  for (const Tet& t : m.tets) {
    double x = 0.0;
    for (const Index v : t) x += 0.25 * m.vertices[static_cast<std::size_t>(v)].x();
    m.tet_regions.push_back(x < -0.5 ? 1 : x < 0.5 ? 2 : 3);
  }
  return m;
}

TEST(TetTopology, RegionSurfacesAreTheInterfacesFacingOutOfTheirRegion) {
  const TetMesh m = three_regions();
  const TetTopology topo(m);
  // Region 2's whole boundary encloses its unit cube, outward.
  const BoundarySurface whole = extract_region_surface(m, topo, {2}, {kOutsideRegion, 1, 3});
  EXPECT_NEAR(whole.surface.signed_volume(), 1.0, 1e-12);
  EXPECT_TRUE(HalfEdgeMesh(whole.surface).closed());
  // Where 2 meets 3 only: the unit square at x = 0.5, its normals along +x (out of 2).
  const BoundarySurface wall = extract_region_surface(m, topo, {2}, {3});
  EXPECT_NEAR(wall.surface.area(), 1.0, 1e-12);
  for (std::size_t f = 0; f < wall.surface.triangles.size(); ++f) {
    EXPECT_GT(wall.surface.face_normal(f).x(), 0.999);
    for (const Index v : wall.surface.triangles[f]) EXPECT_DOUBLE_EQ(wall.surface.vertices[v].x(), 0.5);
    // The face's tet is region 2's, and the vertices are the tets' nodes.
    EXPECT_EQ(m.tet_regions[static_cast<std::size_t>(wall.face_tet[f])], 2);
  }
  for (std::size_t s = 0; s < wall.surface_to_volume.size(); ++s)
    EXPECT_EQ(wall.surface.vertices[s], m.vertices[wall.surface_to_volume[s]]);
  // The same wall seen from 3 faces the other way.
  const BoundarySurface back = extract_region_surface(m, topo, {3}, {2});
  EXPECT_NEAR(back.surface.area(), 1.0, 1e-12);
  EXPECT_LT(back.surface.face_normal(0).x(), -0.999);
  // Regions 1 and 2 together against the outside: the box's boundary less the cube of 3.
  const BoundarySurface outer = extract_region_surface(m, topo, {1, 2}, {kOutsideRegion});
  EXPECT_NEAR(outer.surface.area(), 2.0 * 4.0 + 1.0, 1e-12);
  // 1 and 3 do not meet.
  EXPECT_TRUE(extract_region_surface(m, topo, {1}, {3}).surface.triangles.empty());
  TetMesh untagged = m;
  untagged.tet_regions.clear();
  EXPECT_THROW((void)extract_region_surface(untagged, TetTopology(untagged), {1}, {2}), InputError);
}

TEST(TetTopology, RejectsFaceSharedByThreeTets) {
  TetMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}, {1, 1, 1}};
  m.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}, {0, 1, 2, 5}};
  try {
    TetTopology topo(m);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("face (0 1 2): non-manifold, shared by 3 tetrahedra"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace tactus::mesh
