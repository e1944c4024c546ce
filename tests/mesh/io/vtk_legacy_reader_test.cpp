// The legacy VTK reader: files SOFA, the VTK library and Gmsh wrote (tests/data/meshes/
// SOURCES.md; counts from their headers), Tactus's own .vtk files read back, the binary and
// 5.1 layouts, and broken files refused with where and why.
#include <gtest/gtest.h>

#include <bit>

#include "io_test_util.hpp"
#include "mesh/io/io_common.hpp"

namespace tactus::mesh::test {
namespace {

TEST(VtkLegacyReader, SofaAsciiGridOfLinesTrianglesAndTetrahedra) {
  // POINTS 413, CELL_TYPES 5703: 1942 lines (3), 2645 triangles (5), 1116 tetrahedra (10).
  const MeshFile f = read_mesh(data_dir / "sofa_A.vtk");
  EXPECT_EQ(f.format, MeshFormat::vtk);
  ASSERT_TRUE(f.volume && f.surface);
  EXPECT_EQ(f.volume->vertices.size(), 413u);
  EXPECT_EQ(f.volume->tets.size(), 1116u);
  EXPECT_EQ(f.surface->triangles.size(), 2645u);
  EXPECT_EQ(f.skipped, "1942 lines");
  for (std::size_t t = 0; t < f.volume->tets.size(); ++t) EXPECT_GT(f.volume->tet_volume(t), 0.0) << t;
  EXPECT_NEAR(f.volume->vertices.front().x(), 25.0303438, 1e-6);  // the first point as printed
}

TEST(VtkLegacyReader, VtkLibraryBinaryPolydata) {
  // POINTS 5008 float, POLYGONS 10000 40000: triangles, big endian.
  const MeshFile f = read_mesh(data_dir / "sofa_liver.vtk");
  ASSERT_TRUE(f.surface);
  EXPECT_FALSE(f.volume);
  EXPECT_EQ(f.surface->vertices.size(), 5008u);
  EXPECT_EQ(f.surface->triangles.size(), 10000u);
  EXPECT_TRUE(f.skipped.empty());
  const Aabb box = f.surface->bounds();
  for (int k = 0; k < 3; ++k) EXPECT_LT(box.max[k] - box.min[k], 250.0);  // a liver in mm, not garbage
  EXPECT_GT(box.max.z() - box.min.z(), 100.0);
}

TEST(VtkLegacyReader, FilesWithNoTetrahedraOrTrianglesSayWhatTheyHold) {
  // The VTK library's binary voxels (with cell, field and point data after the cells) and
  // Gmsh's quads: nothing to read, and the message says what is there.
  expect_read_error(data_dir / "sofa_vox8_binary.vtk", "the file holds 8 voxels");
  expect_read_error(data_dir / "sofa_test_quad_gmsh.vtk", "the file holds 288 quads");
}

TEST(VtkLegacyReader, TactusFilesReadBack) {
  const auto dir = scratch_dir();
  TetMesh v;
  v.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1.0 / 3.0, 1.0 / 7.0, 1e-17}};
  v.tets = {{0, 1, 2, 3}, {1, 3, 2, 4}};  // both positive
  write_mesh(dir / "v.vtk", v);
  const MeshFile rv = read_mesh(dir / "v.vtk");
  ASSERT_TRUE(rv.volume);
  EXPECT_EQ(rv.volume->vertices, v.vertices);  // shortest round-trip text: bit for bit
  EXPECT_EQ(rv.volume->tets, v.tets);
  EXPECT_TRUE(rv.volume->tet_regions.empty());
  v.tet_regions = {3, -7};  // written as cell data, read back
  write_mesh(dir / "regions.vtk", v);
  EXPECT_EQ(read_mesh(dir / "regions.vtk").volume.value().tet_regions, v.tet_regions);
  // The external volume with its physical regions, through the VTK writer and reader.
  const TetMesh box = read_mesh(data_dir / "skfem_box.msh").volume.value();
  write_mesh(dir / "box.vtk", box);
  const TetMesh back = read_mesh(dir / "box.vtk").volume.value();
  EXPECT_EQ(back.vertices, box.vertices);
  EXPECT_EQ(back.tets, box.tets);
  EXPECT_EQ(back.tet_regions, box.tet_regions);
  TriMesh s;
  s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-0.125, 2.5e-9, 3}};
  s.triangles = {{0, 1, 2}, {0, 2, 3}};
  write_mesh(dir / "s.vtk", s);
  const MeshFile rs = read_mesh(dir / "s.vtk");
  ASSERT_TRUE(rs.surface);
  EXPECT_EQ(rs.surface->vertices, s.vertices);
  EXPECT_EQ(rs.surface->triangles, s.triangles);
}

template <class T>
void put_be(std::string& out, T value) {
  io::append_bytes(out, value, std::endian::big);
}

/// A binary POLYDATA square of two triangles as one triangle strip (0 1 2 3), doubles.
std::string binary_strip() {
  std::string f = "# vtk DataFile Version 3.0\nstrip\nBINARY\nDATASET POLYDATA\nPOINTS 4 double\n";
  for (const double c : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0}) put_be(f, c);
  f += "\nTRIANGLE_STRIPS 1 5\n";
  for (const std::int32_t i : {4, 0, 1, 2, 3}) put_be(f, i);
  f += "\nPOINT_DATA 4\nSCALARS t float 1\nLOOKUP_TABLE default\n";
  for (int i = 0; i < 4; ++i) put_be(f, 1.0f);
  return f;
}

TEST(VtkLegacyReader, BinaryTriangleStripsAlternateTheirWinding) {
  const auto dir = scratch_dir();
  const MeshFile f = read_mesh(write_bytes(dir / "strip.vtk", binary_strip()));
  ASSERT_TRUE(f.surface);
  EXPECT_EQ(f.surface->vertices[3], Vec3(1, 1, 0));
  ASSERT_EQ(f.surface->triangles.size(), 2u);
  EXPECT_EQ(f.surface->triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(f.surface->triangles[1], (Triangle{2, 1, 3}));  // both face +z
}

TEST(VtkLegacyReader, Version51OffsetsAndConnectivity) {
  const auto dir = scratch_dir();
  const std::string file =
      "# vtk DataFile Version 5.1\nnew layout\nASCII\nDATASET UNSTRUCTURED_GRID\n"
      "FIELD FieldData 1\nTIME 1 1 double\n0.5\nMETADATA\nINFORMATION 0\n\n"
      "POINTS 5 float\n0 0 0 1 0 0 0 1 0\n0 0 1 1 1 1\n"
      "CELLS 4 10\nOFFSETS vtktypeint64\n0 4 7 10\nCONNECTIVITY vtktypeint64\n0 1 2 3 1 2 4 0 4 3\n"
      "CELL_TYPES 3\n10\n5\n5\n";
  const MeshFile f = read_mesh(write_bytes(dir / "new.vtk", file));
  ASSERT_TRUE(f.volume && f.surface);
  EXPECT_EQ(f.volume->tets.size(), 1u);
  EXPECT_EQ(f.surface->triangles.size(), 2u);
  EXPECT_EQ(f.surface->triangles[1], (Triangle{0, 4, 3}));
}

TEST(VtkLegacyReader, BrokenFilesAreRefusedWithWhereAndWhy) {
  const auto dir = scratch_dir();
  const std::string header = "# vtk DataFile Version 2.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n";
  const std::string points = "POINTS 3 float\n0 0 0 1 0 0 0 1 0\n";
  expect_read_error(write_bytes(dir / "a.vtk", "solid x\n"), "not a legacy VTK file", At{1});
  expect_read_error(write_bytes(dir / "b.vtk", "# vtk DataFile Version 2.0\nt\nTEXT\n"), "ASCII or BINARY", At{3});
  expect_read_error(write_bytes(dir / "c.vtk", "# vtk DataFile Version 2.0\nt\nASCII\nDATASET STRUCTURED_POINTS\n"),
                    "holds no cells to read", At{4});
  expect_read_error(write_bytes(dir / "d.vtk", header + "POINTS 3 float\n0 0 0 1 0\n"), "truncated file");
  expect_read_error(write_bytes(dir / "e.vtk", header + "POINTS 2 float\n0 0 0\n1 nan 0\n"), "expected a coordinate",
                    At{7});
  expect_read_error(write_bytes(dir / "f.vtk", header + points + "CELLS 1 4\n3 0 1 7\nCELL_TYPES 1\n5\n"),
                    "point index 7 out of range (3 points)");
  expect_read_error(write_bytes(dir / "g.vtk", header + points + "CELLS 1 4\n9 0 1 2\n"),
                    "cell 0 has 9 points, more than the 4 integers");
  expect_read_error(write_bytes(dir / "h.vtk", header + points + "CELLS 1 4\n3 0 1 2\nCELL_TYPES 2\n5\n5\n"),
                    "1 cells but 2 cell types");
  expect_read_error(write_bytes(dir / "i.vtk", header + points + "CELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n10\n"),
                    "cell 0 of type 10 has 3 points");
  expect_read_error(write_bytes(dir / "j.vtk", header + points + "SPLINES 1\n"), "unexpected 'SPLINES'", At{7});
  expect_read_error(write_bytes(dir / "k.vtk", header + "CELLS 0 0\nCELL_TYPES 0\n"), "no POINTS section");
  // A binary file cut short names the byte where its data ran out.
  const std::string strip = binary_strip();
  const std::size_t cut = strip.find("TRIANGLE_STRIPS") + 30;
  // Two of the strip's five integers are whole; the third needs the byte after them.
  expect_read_error(write_bytes(dir / "l.vtk", strip.substr(0, cut)), "truncated file",
                    At{{}, strip.find("TRIANGLE_STRIPS") + 20 + 8});
}

}  // namespace
}  // namespace tactus::mesh::test
