// The MSH reader's older and binary versions: files Gmsh wrote (tests/data/meshes/
// SOURCES.md; counts from Gmsh's own ASCII 2.2 re-export of each), hand-written 1.0 and
// 4.0 files, binary files built here in both byte orders, and broken files refused with
// where and why.
#include <gtest/gtest.h>

#include <set>

#include "io_test_util.hpp"
#include "mesh/io/io_common.hpp"

namespace tactus::mesh::test {
namespace {

/// The Gmsh cube (gmsh_cube.geo): 339 nodes, 540 triangles, 1125 tetrahedra.
void expect_gmsh_cube(const MeshFile& f, bool physical) {
  ASSERT_TRUE(f.volume && f.surface);
  const TetMesh& m = *f.volume;
  EXPECT_EQ(m.vertices.size(), 339u);
  EXPECT_EQ(m.tets.size(), 1125u);
  EXPECT_EQ(f.surface->triangles.size(), 540u);
  EXPECT_NEAR(m.volume(), 1.0, 1e-12);
  for (std::size_t t = 0; t < m.tets.size(); ++t) ASSERT_GT(m.tet_volume(t), 0.0) << t;
  if (physical) {
    EXPECT_EQ(std::set<int>(m.tet_regions.begin(), m.tet_regions.end()), std::set<int>{7});
    EXPECT_EQ(std::set<int>(m.face_markers.begin(), m.face_markers.end()), std::set<int>{1});
  } else {
    EXPECT_TRUE(m.tet_regions.empty());
  }
}

TEST(MshReader, GmshVersionsOfOneCube) {
  const MeshFile v1 = read_mesh(data_dir / "gmsh_cube_v1.msh");
  expect_gmsh_cube(v1, true);
  EXPECT_TRUE(v1.skipped.empty());
  expect_gmsh_cube(read_mesh(data_dir / "gmsh_cube_v40.msh"), true);
  expect_gmsh_cube(read_mesh(data_dir / "gmsh_cube_v41_binary.msh"), true);
  // Saved with Mesh.SaveAll: every element once, physical tag 0, points and lines too.
  const MeshFile all = read_mesh(data_dir / "gmsh_cube_v22_binary.msh");
  expect_gmsh_cube(all, false);
  EXPECT_EQ(all.skipped, "72 lines (type 1), 8 points (type 15)");
  // No physical group: the faces are labelled by the box's six surface entities (the
  // single volume entity labels nothing).
  const auto& markers = all.volume->face_markers;
  EXPECT_EQ(std::set<int>(markers.begin(), markers.end()), (std::set<int>{1, 2, 3, 4, 5, 6}));
}

TEST(MshReader, ElementaryTagsLabelRegionsWhereNoPhysicalGroupDoes) {
  // Two tetrahedra in two volume entities (elementary tags 5 and 9), physical tag 0.
  const std::string two_volumes =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n"
      "$EndNodes\n$Elements\n2\n1 4 2 0 5 1 2 3 4\n2 4 2 0 9 2 3 4 5\n$EndElements\n";
  const auto dir = scratch_dir();
  int files = 0;
  auto read_text = [&](const std::string& text) {
    std::string name = "f";  // appended: GCC 12 warns falsely on the inlined operator+
    name.append(std::to_string(files++)).append(".msh");
    return read_mesh(write_bytes(dir / name, text));
  };
  const TetMesh m = *read_text(two_volumes).volume;
  EXPECT_EQ(m.tet_regions, (std::vector<int>{5, 9}));
  // With a physical group anywhere, physical tags win (0 where an element has none).
  const std::string one_physical =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n"
      "$EndNodes\n$Elements\n2\n1 4 2 3 5 1 2 3 4\n2 4 2 0 9 2 3 4 5\n$EndElements\n";
  EXPECT_EQ(read_text(one_physical).volume->tet_regions, (std::vector<int>{3, 0}));
  // MSH 1.0 carries the same two columns (reg-phys, reg-elem).
  const std::string v1 = "$NOD\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n$ENDNOD\n$ELM\n2\n"
                         "1 4 0 5 4 1 2 3 4\n2 4 0 9 4 2 3 4 5\n$ENDELM\n";
  EXPECT_EQ(read_text(v1).volume->tet_regions, (std::vector<int>{5, 9}));
}

TEST(MshReader, AnElementTagUsedTwiceIsRefused) {
  const std::string twice =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n"
      "$EndNodes\n$Elements\n2\n7 4 2 0 5 1 2 3 4\n7 4 2 0 9 2 3 4 5\n$EndElements\n";
  expect_read_error(write_bytes(scratch_dir() / "twice.msh", twice), "element tag 7 names two elements (lines 14 and 15)",
                    {15});
}

TEST(MshReader, SofaMsh1Files) {
  // Tetrahedra only (counted with awk): "$NOD 40" and 54 tets; "$NOD 181" and 596 tets.
  const MeshFile truss = read_mesh(data_dir / "sofa_truss_tetra_v1.msh");
  ASSERT_TRUE(truss.volume);
  EXPECT_EQ(truss.volume->vertices.size(), 40u);
  EXPECT_EQ(truss.volume->tets.size(), 54u);
  const MeshFile liver = read_mesh(data_dir / "sofa_liver_v1.msh");
  ASSERT_TRUE(liver.volume);
  EXPECT_FALSE(liver.surface);
  EXPECT_EQ(liver.volume->vertices.size(), 181u);
  EXPECT_EQ(liver.volume->tets.size(), 596u);
}

TEST(MshReader, OmegaHMsh40WithPhysicalSurfaces) {
  // Gmsh 4.0 output kept in omega_h's tests: 43 nodes in 15 blocks, 60 triangles in
  // surfaces 10 (physical 1) and 11 (physical 2); entities carry bounding boxes.
  const MeshFile f = read_mesh(data_dir / "omegah_square_physical_msh40.msh");
  ASSERT_TRUE(f.surface);
  EXPECT_FALSE(f.volume);
  EXPECT_EQ(f.surface->vertices.size(), 43u);
  EXPECT_EQ(f.surface->triangles.size(), 60u);
  EXPECT_EQ(f.surface->triangles.front(), (Triangle{25, 26, 29}));  // "1 26 27 30", tags from 1
}

TEST(MshReader, HandWrittenMsh1And40) {
  const auto dir = scratch_dir();
  const MeshFile v1 = read_mesh(write_bytes(dir / "v1.msh",
                                            "$NOD\r\n4\r\n1 0 0 0\r\n2 1 0 0\r\n3 0 1 0\r\n9 0 0 1\r\n$ENDNOD\r\n"
                                            "$ELM\r\n3\r\n1 4 5 1 4 1 2 3 9\r\n2 2 6 1 3 1 3 2\r\n3 15 0 1 1 1\r\n$ENDELM\r\n"));
  ASSERT_TRUE(v1.volume);
  EXPECT_EQ(v1.volume->tets, (std::vector<Tet>{{0, 1, 2, 3}}));
  EXPECT_EQ(v1.volume->tet_regions, std::vector<int>{5});
  EXPECT_EQ(v1.volume->face_markers, std::vector<int>{6});
  EXPECT_EQ(v1.skipped, "1 points (type 15)");

  const MeshFile v40 = read_mesh(write_bytes(
      dir / "v40.msh",
      "$MeshFormat\n4 0 8\n$EndMeshFormat\n$Entities\n0 0 0 1\n3 0 0 0 1 1 1 1 8 0\n$EndEntities\n"
      "$Nodes\n1 4\n3 3 0 4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
      "$Elements\n1 1\n3 3 4 1\n1 1 2 3 4\n$EndElements\n"));
  ASSERT_TRUE(v40.volume);
  EXPECT_EQ(v40.volume->tets, (std::vector<Tet>{{0, 1, 2, 3}}));
  EXPECT_EQ(v40.volume->tet_regions, std::vector<int>{8});
}

/// A binary MSH file of one tetrahedron (physical 5) in byte order `order`; `version` 22 or 41.
std::string binary_tet(int version, std::endian order) {
  auto put = [&](std::string& out, auto v) { io::append_bytes(out, v, order); };
  std::string s = version == 22 ? "$MeshFormat\n2.2 1 8\n" : "$MeshFormat\n4.1 1 8\n";
  put(s, std::int32_t{1});
  s += "\n$EndMeshFormat\n";
  const double xyz[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  if (version == 22) {
    s += "$Nodes\n4\n";
    for (int i = 0; i < 4; ++i) {
      put(s, std::int32_t{i + 1});
      for (const double c : xyz[i]) put(s, c);
    }
    s += "\n$EndNodes\n$Elements\n2\n";
    for (const std::int32_t v : {15, 1, 2, 7, 5, 7, 1}) put(s, v);  // a point: type 15, 1 element, 2 tags
    for (const std::int32_t v : {4, 1, 2, 8, 5, 7, 1, 2, 3, 4}) put(s, v);
    return s + "\n$EndElements\n";
  }
  s += "$Entities\n";
  for (const std::uint64_t c : {0, 0, 0, 1}) put(s, c);
  put(s, std::int32_t{1});
  for (int k = 0; k < 6; ++k) put(s, 0.5);
  put(s, std::uint64_t{1});
  put(s, std::int32_t{5});
  put(s, std::uint64_t{0});
  s += "\n$EndEntities\n$Nodes\n";
  for (const std::uint64_t c : {1, 4, 1, 4}) put(s, c);
  for (const std::int32_t v : {3, 1, 0}) put(s, v);
  put(s, std::uint64_t{4});
  for (const std::uint64_t tag : {1, 2, 3, 4}) put(s, tag);
  for (const auto& p : xyz)
    for (const double c : p) put(s, c);
  s += "\n$EndNodes\n$Elements\n";
  for (const std::uint64_t c : {1, 1, 1, 1}) put(s, c);
  for (const std::int32_t v : {3, 1, 4}) put(s, v);
  for (const std::uint64_t v : {1, 1, 1, 2, 3, 4}) put(s, v);
  return s + "\n$EndElements\n";
}

TEST(MshReader, BinaryInBothByteOrders) {
  const auto dir = scratch_dir();
  for (const int version : {22, 41}) {
    for (const std::endian order : {std::endian::little, std::endian::big}) {
      SCOPED_TRACE(version);
      const MeshFile f = read_mesh(write_bytes(dir / "b.msh", binary_tet(version, order)));
      ASSERT_TRUE(f.volume);
      EXPECT_EQ(f.volume->vertices, (std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}));
      EXPECT_EQ(f.volume->tets, (std::vector<Tet>{{0, 1, 2, 3}}));
      EXPECT_EQ(f.volume->tet_regions, std::vector<int>{5});
      EXPECT_EQ(f.skipped, version == 22 ? "1 points (type 15)" : "");
    }
  }
}

TEST(MshReader, BrokenBinaryFiles) {
  const auto dir = scratch_dir();
  const std::string good = binary_tet(22, std::endian::little);
  const std::size_t marker = good.find("8\n") + 2;
  std::string endian = good;
  endian[marker] = 2;
  expect_read_error(write_bytes(dir / "endian.msh", endian), "endianness marker must be the integer 1, got 2", {{}, marker});
  const std::size_t nodes = good.find("$Nodes\n4\n") + 9;
  expect_read_error(write_bytes(dir / "trunc.msh", good.substr(0, nodes + 30)),
                    "truncated file: a node tag needs 4 bytes, only 2 left", {{}, nodes + 28});
  std::string tag = good;
  const std::size_t tet = good.rfind("\n$EndElements") - 16;  // the tet's four node tags
  tag[tet + 12] = 9;
  expect_read_error(write_bytes(dir / "tag.msh", tag), "tetrahedron 8 refers to node tag 9, which is not defined", {{}, tet + 12});
  std::string type = good;
  type[good.find("$Elements\n2\n") + 12] = 99;
  expect_read_error(write_bytes(dir / "type.msh", type), "element type 99 is unknown", {{}, good.find("$Elements\n2\n") + 12});
  std::string end = good;
  end.replace(end.find("$EndNodes"), 9, "$EndNodez");
  expect_read_error(write_bytes(dir / "end.msh", end), "expected '$EndNodes', got '$EndNodez'", {{}, good.find("$EndNodes")});
  // 4.1: a block holding more nodes than declared, and a huge count.
  std::string more = binary_tet(41, std::endian::little);
  const std::size_t block = more.find("$Nodes\n") + 7 + 32;
  more[block + 12] = 5;
  expect_read_error(write_bytes(dir / "more.msh", more), "node blocks hold more nodes than the 4 declared", {{}, block});
  std::string huge = binary_tet(41, std::endian::little);
  huge[huge.find("$Nodes\n") + 7 + 8 + 6] = 1;
  expect_read_error(write_bytes(dir / "huge.msh", huge), "node count too large", {{}, huge.find("$Nodes\n") + 15});
  expect_read_error(write_bytes(dir / "v40b.msh", "$MeshFormat\n4.0 1 8\n"), "binary MSH 4.0 is not supported", {2});
}

TEST(MshReader, BrokenTextFiles) {
  const auto dir = scratch_dir();
  expect_read_error(write_bytes(dir / "v1.msh", "$NOD\n1\n1 0 0 0\n$ENDNOD\n$ELM\n1\n1 4 1 1 4 1 1 1\n$ENDELM\n"),
                    "element 1 lists 3 nodes, its count says 4", {7});
  expect_read_error(write_bytes(dir / "v1end.msh", "$NOD\n1\n1 0 0 0\n$EndNodes\n"), "expected '$ENDNOD', got '$EndNodes'",
                    {4, {}, 1});
  expect_read_error(write_bytes(dir / "v40.msh", "$MeshFormat\n4 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n"),
                    "expected 'numEntityBlocks numNodes' (MSH 4.0)", {5});
  expect_read_error(write_bytes(dir / "v40n.msh", "$MeshFormat\n4 0 8\n$EndMeshFormat\n$Nodes\n1 1\n1 0 0 1\n1 0 0\n"),
                    "expected 4 values (tag and coordinates), got 3", {7});
}

TEST(MshReader, TruncationNeverCrashes) {
  for (const char* name : {"gmsh_cube_v22_binary.msh", "gmsh_cube_v41_binary.msh"}) {
    const std::string whole = read_bytes(data_dir / name);
    for (std::size_t n = 0; n < whole.size(); n += 97) {
      try {
        (void)io::parse_msh(std::string_view(whole).substr(0, n), name);
      } catch (const InputError&) {
      }
    }
  }
}

}  // namespace
}  // namespace tactus::mesh::test
