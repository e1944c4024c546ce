// Files written by other tools (see tests/data/meshes/SOURCES.md). Expected counts come
// from the files' own headers; volumes and bounds from the shapes they describe.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "io_test_util.hpp"

namespace tactus::mesh::test {
namespace {

void expect_box(const Aabb& box, const Vec3& lo, const Vec3& hi, double tol = 1e-9) {
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(box.min[k], lo[k], tol) << "axis " << k;
    EXPECT_NEAR(box.max[k], hi[k], tol) << "axis " << k;
  }
}

void expect_all_positive(const TetMesh& m) {
  std::size_t negative = 0;
  for (std::size_t t = 0; t < m.tets.size(); ++t) negative += m.tet_volume(t) <= 0.0;
  EXPECT_EQ(negative, 0u);
}

TEST(MeshIoExternal, GmshMsh22Box) {
  const auto f = read_mesh(data_dir / "skfem_box.msh");
  ASSERT_TRUE(f.volume && f.surface);
  const TetMesh& m = *f.volume;
  EXPECT_EQ(m.vertices.size(), 358u);
  EXPECT_EQ(m.tets.size(), 1105u);
  EXPECT_EQ(m.faces.size(), 312u);
  EXPECT_EQ(f.surface->triangles.size(), 312u);
  // Physical groups: surfaces 1-3 ("front", "back", "top"), volume 4 ("all").
  EXPECT_EQ(std::set<int>(m.tet_regions.begin(), m.tet_regions.end()), std::set<int>{4});
  EXPECT_EQ(std::set<int>(m.face_markers.begin(), m.face_markers.end()), (std::set<int>{1, 2, 3}));
  expect_box(m.bounds(), Vec3(0, 0, 0), Vec3(1, 1, 1));
  EXPECT_NEAR(m.volume(), 1.0, 1e-12);
  expect_all_positive(m);
}

TEST(MeshIoExternal, GmshMsh41CubeWithSubdomain) {
  const auto f = read_mesh(data_dir / "skfem_cube_oriented_sub.msh");
  ASSERT_TRUE(f.volume);
  const TetMesh& m = *f.volume;
  EXPECT_EQ(m.vertices.size(), 81u);  // "$Nodes 27 81 1 81"
  EXPECT_EQ(m.tets.size(), 184u);
  EXPECT_EQ(m.faces.size(), 156u);
  EXPECT_EQ(std::set<int>(m.tet_regions.begin(), m.tet_regions.end()), std::set<int>{25});  // "subdom"
  EXPECT_TRUE(std::count(m.face_markers.begin(), m.face_markers.end(), 26) > 0);         // "subdomif"
  EXPECT_NEAR(m.volume(), 0.125, 1e-12);  // the sub-cube [0.1, 0.6]^3
  expect_all_positive(m);
  for (const auto& v : m.vertices) EXPECT_TRUE((Aabb{Vec3::Zero(), Vec3::Ones()}.contains(v)));
}

TEST(MeshIoExternal, TetGenExample) {
  for (const char* ext : {".node", ".ele", ".face"}) {
    const TetMesh m = read_mesh(data_dir / (std::string("tetgen_example.1") + ext)).volume.value();
    EXPECT_EQ(m.vertices.size(), 28u);
    EXPECT_EQ(m.tets.size(), 68u);
    EXPECT_EQ(m.faces.size(), 50u);
    EXPECT_EQ(m.face_markers.size(), 50u);
    EXPECT_TRUE(m.tet_regions.empty());
    EXPECT_GT(m.volume(), 0.0);
    expect_all_positive(m);
    const Aabb box = m.bounds();
    EXPECT_EQ(box.min, Vec3(0, 0, 0));
    EXPECT_EQ(m.vertices[27], Vec3(0.25, 1.5, 2.5));
  }
}

TEST(MeshIoExternal, ObjNegativeIndices) {
  const TriMesh m = read_mesh(data_dir / "trimesh_negative_indices.obj").surface.value();
  EXPECT_EQ(m.vertices.size(), 8u);
  EXPECT_EQ(m.triangles.size(), 12u);  // six quads
  expect_box(m.bounds(), Vec3(-1, -1, -1), Vec3(1, 1, 1));
  EXPECT_NEAR(std::abs(m.signed_volume()), 8.0, 1e-12);
}

TEST(MeshIoExternal, OffWithCommentsAndColours) {
  const TriMesh m = read_mesh(data_dir / "trimesh_comments.off").surface.value();
  EXPECT_EQ(m.vertices.size(), 8u);
  EXPECT_EQ(m.triangles.size(), 12u);
  expect_box(m.bounds(), Vec3(-1.632993, -1.632993, -1.154701), Vec3(1.632993, 1.632993, 1.154701));
  EXPECT_GT(m.signed_volume(), 0.0);
}

TEST(MeshIoExternal, StlBinaryStartingWithSolid) {
  EXPECT_EQ(read_bytes(data_dir / "trimesh_unit_cube.stl").substr(0, 5), "solid");
  const TriMesh m = read_mesh(data_dir / "trimesh_unit_cube.stl").surface.value();
  EXPECT_EQ(m.triangles.size(), 12u);
  EXPECT_EQ(m.vertices.size(), 8u);  // corners merged
  EXPECT_NEAR(m.signed_volume(), 1.0, 1e-6);
}

TEST(MeshIoExternal, StlAsciiTwoSolids) {
  const TriMesh m = read_mesh(data_dir / "trimesh_multibody.stl").surface.value();
  EXPECT_EQ(m.triangles.size(), 32u);  // 32 "facet normal" lines
  EXPECT_EQ(m.vertices.size(), 20u);
  EXPECT_GT(m.signed_volume(), 0.0);
}

TEST(MeshIoExternal, PlyBinaryFromMeshLab) {
  const TriMesh m = read_mesh(data_dir / "trimesh_cube_blender_uv_meshlab.ply").surface.value();
  EXPECT_EQ(m.vertices.size(), 24u);
  EXPECT_EQ(m.triangles.size(), 12u);
  expect_box(m.bounds(), Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5));
  EXPECT_NEAR(m.signed_volume(), 1.0, 1e-6);
}

TEST(MeshIoExternal, PlyAsciiSphereFromMeshLab) {
  const TriMesh m = read_mesh(data_dir / "trimesh_sphere.ply").surface.value();
  EXPECT_EQ(m.vertices.size(), 642u);
  EXPECT_EQ(m.triangles.size(), 1280u);
  expect_box(m.bounds(), Vec3(-1, -1, -1), Vec3(1, 1, 1), 1e-5);
  EXPECT_GT(m.signed_volume(), 4.0);
  EXPECT_LT(m.signed_volume(), 4.19);  // inscribed in the unit sphere
}

// Every external file survives a write/read cycle through each format that holds it.
TEST(MeshIoExternal, RoundTripThroughEveryWriter) {
  const auto dir = scratch_dir();
  const TriMesh s = read_mesh(data_dir / "trimesh_sphere.ply").surface.value();
  for (const char* name : {"s.obj", "s.off", "s.ply", "s.msh"}) {
    write_mesh(dir / name, s);
    const TriMesh r = read_mesh(dir / name).surface.value();
    EXPECT_EQ(r.vertices, s.vertices) << name;
    EXPECT_EQ(r.triangles, s.triangles) << name;
  }
  const TetMesh v = read_mesh(data_dir / "skfem_box.msh").volume.value();
  for (const char* name : {"v.msh", "v.node"}) {
    write_mesh(dir / name, v);
    const TetMesh r = read_mesh(dir / name).volume.value();
    EXPECT_EQ(r.vertices, v.vertices) << name;
    EXPECT_EQ(r.tets, v.tets) << name;
    EXPECT_EQ(r.tet_regions, v.tet_regions) << name;
    EXPECT_EQ(r.faces, v.faces) << name;
    EXPECT_EQ(r.face_markers, v.face_markers) << name;
  }
}

}  // namespace
}  // namespace tactus::mesh::test
