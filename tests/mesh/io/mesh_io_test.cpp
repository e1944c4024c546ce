#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "io_test_util.hpp"

namespace tactus::mesh::test {
namespace {

namespace fs = std::filesystem;

// A closed, outward-oriented tetrahedron surface.
TriMesh tet_surface(double s = 1.0) {
  TriMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(s, 0, 0), Vec3(0, s, 0), Vec3(0, 0, s)};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

// Coordinates that need all 17 digits.
TriMesh awkward_surface() {
  TriMesh m = tet_surface();
  m.vertices[1] = Vec3(0.1, 1.0 / 3.0, -2.0e-300);
  m.vertices[2] = Vec3(std::nextafter(1.0, 2.0), 123456789.123456789, -0.0);
  m.vertices[3] = Vec3(1e300, -std::numeric_limits<double>::denorm_min(), 7.0);
  return m;
}

// Two positive tets sharing a face, with labels.
TetMesh two_tets() {
  TetMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(1.0 / 3.0, 1.0 / 3.0, -0.7)};
  m.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}};
  m.tet_regions = {5, 9};
  m.faces = {{0, 3, 2}, {1, 2, 3}, {0, 1, 4}};
  m.face_markers = {2, 2, 7};
  return m;
}

void expect_same(const TriMesh& a, const TriMesh& b) {
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  for (std::size_t i = 0; i < a.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(std::bit_cast<std::uint64_t>(a.vertices[i][k] + 0.0),
                                          std::bit_cast<std::uint64_t>(b.vertices[i][k] + 0.0))
        << "vertex " << i;
  EXPECT_EQ(a.triangles, b.triangles);
}

void expect_same(const TetMesh& a, const TetMesh& b) {
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  for (std::size_t i = 0; i < a.vertices.size(); ++i) EXPECT_EQ(a.vertices[i], b.vertices[i]) << "vertex " << i;
  EXPECT_EQ(a.tets, b.tets);
  EXPECT_EQ(a.tet_regions, b.tet_regions);
  EXPECT_EQ(a.faces, b.faces);
  EXPECT_EQ(a.face_markers, b.face_markers);
}

// STL rebuilds vertices from corners: same triangles, corner by corner, and no extra
// vertices, but the vertex numbering follows first use.
void expect_same_soup(const TriMesh& got, const TriMesh& want) {
  EXPECT_EQ(got.vertices.size(), want.vertices.size());
  ASSERT_EQ(got.triangles.size(), want.triangles.size());
  for (std::size_t t = 0; t < got.triangles.size(); ++t)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(got.vertices[got.triangles[t][c]], want.vertices[want.triangles[t][c]]) << t << " " << c;
}

TriMesh read_surface(const fs::path& p) {
  auto f = read_mesh(p);
  EXPECT_TRUE(f.surface.has_value()) << p;
  return f.surface.value_or(TriMesh{});
}

TetMesh read_volume(const fs::path& p) {
  auto f = read_mesh(p);
  EXPECT_TRUE(f.volume.has_value()) << p;
  return f.volume.value_or(TetMesh{});
}

// Every prefix of a valid file must either read or throw InputError: nothing else.
void expect_prefixes_safe(const fs::path& path, const std::string& data, std::size_t step = 1) {
  for (std::size_t cut = 0; cut < data.size(); cut += step) {
    write_bytes(path, data.substr(0, cut));
    try {
      (void)read_mesh(path);
    } catch (const InputError&) {
    } catch (const std::exception& e) {
      ADD_FAILURE() << "cut at " << cut << ": " << e.what();
    }
  }
}

// ---------------------------------------------------------------- format detection

TEST(MeshIoFormat, Extensions) {
  EXPECT_EQ(format_from_path("a/b.OBJ"), MeshFormat::obj);
  EXPECT_EQ(format_from_path("b.stl"), MeshFormat::stl);
  EXPECT_EQ(format_from_path("b.off"), MeshFormat::off);
  EXPECT_EQ(format_from_path("b.ply"), MeshFormat::ply);
  EXPECT_EQ(format_from_path("b.msh"), MeshFormat::msh);
  EXPECT_EQ(format_from_path("b.1.node"), MeshFormat::tetgen);
  EXPECT_EQ(format_from_path("b.ele"), MeshFormat::tetgen);
  EXPECT_EQ(format_from_path("b.face"), MeshFormat::tetgen);
  EXPECT_EQ(format_from_path("b.vtk"), MeshFormat::vtk);
  EXPECT_EQ(format_from_path("b.vtu"), MeshFormat::vtu);
  EXPECT_STREQ(format_name(MeshFormat::msh), "Gmsh MSH");
}

TEST(MeshIoFormat, UnknownExtensionListsSupported) {
  try {
    (void)format_from_path("mesh.xyz");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "mesh.xyz");
    EXPECT_NE(e.reason().find("'.xyz'"), std::string::npos);
    for (const char* ext : {".obj", ".stl", ".off", ".ply", ".msh", ".node", ".vtk", ".vtu"})
      EXPECT_NE(e.reason().find(ext), std::string::npos) << ext;
  }
  EXPECT_THROW((void)read_mesh("noext"), InputError);
}

TEST(MeshIoFormat, MissingFileAndSurfaceOnlyFormats) {
  const auto dir = scratch_dir();
  expect_read_error(dir / "absent.obj", "cannot open");
  expect_read_error(dir / "absent.vtu", "cannot open");
  EXPECT_THROW(write_mesh(dir / "t.obj", two_tets()), InputError);
}

// ---------------------------------------------------------------- OBJ

TEST(MeshIoObj, ReadsFaceFormsNegativeIndicesAndPolygons) {
  const auto p = write_bytes(scratch_dir() / "a.obj",
                             "# comment\nmtllib x.mtl\no thing\nv 0 0 0\nv 1 0 0 1.0\nv 1 1 0 0.5 0.5 0.5\n"
                             "v 0 1 0\nvt 0 0\nvn 0 0 1\ng grp\ns off\nusemtl m\n"
                             "f 1/1/1 2/1/1 3/1/1 4/1/1   # quad\n"
                             "f 1//1 3//1 4//1\nf -4 -3 -2\nl 1 2\n");
  const TriMesh m = read_surface(p);
  ASSERT_EQ(m.vertices.size(), 4u);
  EXPECT_EQ(m.vertices[2], Vec3(1, 1, 0));
  const std::vector<Triangle> want = {{0, 1, 2}, {0, 2, 3}, {0, 2, 3}, {0, 1, 2}};
  EXPECT_EQ(m.triangles, want);
}

TEST(MeshIoObj, RoundTripIsExact) {
  const auto p = scratch_dir() / "r.obj";
  write_mesh(p, awkward_surface());
  expect_same(read_surface(p), awkward_surface());
}

TEST(MeshIoObj, Errors) {
  const auto dir = scratch_dir();
  expect_read_error(write_bytes(dir / "num.obj", "v 0 0 0\nv 0 0 abc\n"), "expected a coordinate, got 'abc'",
                    {2, {}, 7});
  expect_read_error(write_bytes(dir / "nan.obj", "v 0 nan 0\n"), "NaN or infinite", {1, {}, 5});
  expect_read_error(write_bytes(dir / "inf.obj", "v 0 0 -inf\n"), "NaN or infinite", {1});
  expect_read_error(write_bytes(dir / "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"),
                    "face vertex index 4 out of range (3 vertices", {4, {}, 7});
  expect_read_error(write_bytes(dir / "neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"),
                    "face vertex index -4 out of range", {4});
  expect_read_error(write_bytes(dir / "zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"),
                    "face vertex index 0 out of range", {4});
  expect_read_error(write_bytes(dir / "short.obj", "v 0 0 0\nf 1 1\n"), "at least 3 vertices", {2});
  expect_read_error(write_bytes(dir / "fewv.obj", "v 0 0\n"), "needs 3 coordinates", {1});
  expect_read_error(write_bytes(dir / "idx.obj", "v 0 0 0\nf 1 x 1\n"), "expected a vertex index, got 'x'", {2});
  expect_read_error(write_bytes(dir / "kw.obj", "v 0 0 0\n\x01\x02garbage 1\n"), "unknown keyword", {2, {}, 1});
  // Nothing to read is an error, not an empty surface with infinite bounds.
  expect_read_error(write_bytes(dir / "empty.obj", "# nothing\n"), "no faces to read (0 vertices, no 'f' statement)");
  expect_read_error(write_bytes(dir / "points.obj", "v 0 0 0\nv 1 0 0\n"), "no faces to read (2 vertices");
}

TEST(MeshIoObj, TruncationNeverCrashes) {
  const auto dir = scratch_dir();
  const auto src = dir / "full.obj";
  write_mesh(src, awkward_surface());
  expect_prefixes_safe(dir / "cut.obj", read_bytes(src));
}

// ---------------------------------------------------------------- STL

std::string binary_stl(const std::vector<std::array<float, 9>>& tris, const std::string& header = "bin") {
  std::string out = header;
  out.resize(80, ' ');
  const auto n = static_cast<std::uint32_t>(tris.size());
  out.append(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : tris) {
    const float normal[3] = {0, 0, 0};
    out.append(reinterpret_cast<const char*>(normal), 12);
    out.append(reinterpret_cast<const char*>(t.data()), 36);
    out.append(2, '\0');
  }
  return out;
}

TEST(MeshIoStl, AsciiMergesCoincidentCorners) {
  const auto p = write_bytes(scratch_dir() / "a.stl",
                             "solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n"
                             "   vertex 0 1 0\n  endloop\n endfacet\n facet normal 0 0 1\n  outer loop\n"
                             "   vertex 1 0 0\n   vertex 1 1 0\n   vertex -0 1 0\n  endloop\n endfacet\nendsolid x\n"
                             "solid second\nendsolid\n");
  const TriMesh m = read_surface(p);
  EXPECT_EQ(m.vertices.size(), 4u);
  const std::vector<Triangle> want = {{0, 1, 2}, {1, 3, 2}};
  EXPECT_EQ(m.triangles, want);
}

TEST(MeshIoStl, BinaryDetectedBySizeEvenWithSolidHeader) {
  const auto p = write_bytes(scratch_dir() / "b.stl",
                             binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}, {1, 0, 0, 1, 1, 0, 0, 1, 0}}, "solid lying"));
  const TriMesh m = read_surface(p);
  EXPECT_EQ(m.vertices.size(), 4u);
  ASSERT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(m.triangles[1], (Triangle{1, 3, 2}));
}

TEST(MeshIoStl, RoundTripAsciiAndBinary) {
  const auto dir = scratch_dir();
  write_mesh(dir / "a.stl", awkward_surface());
  expect_same_soup(read_surface(dir / "a.stl"), awkward_surface());
  TriMesh f = tet_surface(0.25);  // float-representable, so binary is exact too
  f.vertices[3] = Vec3(0.1f, -3.5f, 1e-3f);
  write_mesh(dir / "b.stl", f, {.binary = true});
  EXPECT_EQ(read_bytes(dir / "b.stl").size(), 84u + 50u * 4u);
  expect_same_soup(read_surface(dir / "b.stl"), f);
}

TEST(MeshIoStl, Errors) {
  const auto dir = scratch_dir();
  std::string bin = binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}, {1, 0, 0, 1, 1, 0, 0, 1, 0}});
  expect_read_error(write_bytes(dir / "trunc.stl", bin.substr(0, bin.size() - 7)), "declares 2 triangles", {{}, 177});
  std::string nan = bin;
  const float q = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(nan.data() + 84 + 50 + 12 + 4, &q, 4);  // second triangle, first corner, y
  expect_read_error(write_bytes(dir / "nan.stl", nan), "NaN or infinite", {{}, 84 + 50 + 16});
  std::string huge = bin;
  const std::uint32_t big = 0xffffffffU;
  std::memcpy(huge.data() + 80, &big, 4);
  expect_read_error(write_bytes(dir / "huge.stl", huge), "declares 4294967295 triangles");
  expect_read_error(write_bytes(dir / "short.stl", std::string("\x01\x02\x03", 3)), "too short");
  expect_read_error(write_bytes(dir / "empty.stl", ""), "empty file");
  expect_read_error(write_bytes(dir / "kw.stl", "solid a\n facet normal 0 0 1\n  outer loop\n   vertx 0 0 0\n"),
                    "expected 'vertex', got 'vertx'", {4, {}, 4});
  expect_read_error(write_bytes(dir / "num.stl", "solid a\n facet normal 0 0 1\n  outer loop\n   vertex 0 q 0\n"),
                    "expected a coordinate, got 'q'", {4, {}, 13});
  expect_read_error(write_bytes(dir / "eof.stl", "solid a\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n"),
                    "end of file inside a facet", {4});
  expect_read_error(write_bytes(dir / "two.stl",
                                "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n"),
                    "needs 3", {6});
}

TEST(MeshIoStl, TruncationNeverCrashes) {
  const auto dir = scratch_dir();
  write_mesh(dir / "a.stl", tet_surface());
  expect_prefixes_safe(dir / "cut.stl", read_bytes(dir / "a.stl"), 3);
  write_mesh(dir / "b.stl", tet_surface(), {.binary = true});
  expect_prefixes_safe(dir / "cutb.stl", read_bytes(dir / "b.stl"));
}

// ---------------------------------------------------------------- OFF

TEST(MeshIoOff, ReadsCommentsColoursAndPolygons) {
  const auto p = write_bytes(scratch_dir() / "a.off",
                             "OFF # header\n# comment\n\n4 2 0\n0 0 0\n1 0 0 \n1 1 0 0.5 0.5 0.5\n0 1 0\n"
                             "4 0 1 2 3 255 0 0\n3 0 2 3\n");
  const TriMesh m = read_surface(p);
  EXPECT_EQ(m.vertices.size(), 4u);
  const std::vector<Triangle> want = {{0, 1, 2}, {0, 2, 3}, {0, 2, 3}};
  EXPECT_EQ(m.triangles, want);
  const auto q = write_bytes(scratch_dir() / "b.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(read_surface(q).triangles.size(), 1u);
}

TEST(MeshIoOff, RoundTripIsExact) {
  const auto p = scratch_dir() / "r.off";
  write_mesh(p, awkward_surface());
  expect_same(read_surface(p), awkward_surface());
}

TEST(MeshIoOff, Errors) {
  const auto dir = scratch_dir();
  expect_read_error(write_bytes(dir / "h.off", "OFX\n"), "expected 'OFF' header", {1, {}, 1});
  expect_read_error(write_bytes(dir / "bin.off", "OFF BINARY\n"), "binary OFF", {1});
  expect_read_error(write_bytes(dir / "cnt.off", "OFF\n3 x 0\n"), "expected face count", {2, {}, 3});
  expect_read_error(write_bytes(dir / "trunc.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n"),
                    "end of file while reading 3 vertices: got 2", {4});
  expect_read_error(write_bytes(dir / "truncf.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                    "end of file while reading 2 faces: got 1");
  expect_read_error(write_bytes(dir / "range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
                    "face 0 vertex index 3 out of range [0, 3)", {6, {}, 7});
  expect_read_error(write_bytes(dir / "nan.off", "OFF\n1 0 0\n0 nan 0\n"), "NaN or infinite", {3});
  expect_read_error(write_bytes(dir / "few.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n"),
                    "lists 3 indices, expected 4", {6});
  // A huge count must not be allocated up front: the data runs out first.
  expect_read_error(write_bytes(dir / "huge.off", "OFF\n2000000000 1 0\n0 0 0\n"),
                    "end of file while reading 2000000000 vertices: got 1");
  expect_read_error(write_bytes(dir / "huger.off", "OFF\n1000000000000 1 0\n0 0 0\n"), "too large", {2});
}

TEST(MeshIoOff, TruncationNeverCrashes) {
  const auto dir = scratch_dir();
  write_mesh(dir / "a.off", awkward_surface());
  expect_prefixes_safe(dir / "cut.off", read_bytes(dir / "a.off"));
}

// ---------------------------------------------------------------- PLY

TEST(MeshIoPly, AsciiSkipsOtherPropertiesAndElements) {
  const auto p = write_bytes(scratch_dir() / "a.ply",
                             "ply\nformat ascii 1.0\ncomment hi\nobj_info x\nelement vertex 4\n"
                             "property float32 nx\nproperty double x\nproperty list uchar float extra\n"
                             "property float y\nproperty float z\nproperty uchar red\n"
                             "element face 2\nproperty uchar flags\nproperty list uint8 uint32 vertex_indices\n"
                             "property list uchar float texcoord\n"
                             "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n"
                             "9 0 2 1 1 0 0 255\n9 1 0 0 0 0\n9 1 1 5 1 0 0\n9 0 0 1 0 0\n"
                             "1 4 0 1 2 3 0\n0 3 0 2 3 2 0.5 0.5\n0 1\n");
  const TriMesh m = read_surface(p);
  ASSERT_EQ(m.vertices.size(), 4u);
  EXPECT_EQ(m.vertices[2], Vec3(1, 1, 0));
  const std::vector<Triangle> want = {{0, 1, 2}, {0, 2, 3}, {0, 2, 3}};
  EXPECT_EQ(m.triangles, want);
}

TEST(MeshIoPly, BinaryLittleEndianWithMixedTypes) {
  std::string d =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty short tag\n"
      "property float y\nproperty float z\nelement face 1\nproperty list int uint16 vertex_indices\n"
      "property list uchar double junk\nend_header\n";
  auto put = [&](auto v) { d.append(reinterpret_cast<const char*>(&v), sizeof v); };
  const float xyz[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1.5f, 0}};
  for (const auto& v : xyz) {
    put(v[0]);
    put(std::int16_t{-3});
    put(v[1]);
    put(v[2]);
  }
  put(std::int32_t{3});
  for (std::uint16_t i : {0, 1, 2}) put(i);
  put(std::uint8_t{2});
  put(1.0);
  put(2.0);
  const auto p = write_bytes(scratch_dir() / "b.ply", d);
  const TriMesh m = read_surface(p);
  ASSERT_EQ(m.vertices.size(), 3u);
  EXPECT_EQ(m.vertices[2], Vec3(0, 1.5, 0));
  EXPECT_EQ(m.triangles, (std::vector<Triangle>{{0, 1, 2}}));
  // Cut anywhere in the body: a truncation error naming a byte offset.
  const std::size_t body = d.find("end_header\n") + 11;
  for (std::size_t cut = body; cut < d.size(); ++cut) {
    try {
      (void)read_mesh(write_bytes(scratch_dir() / "cut.ply", d.substr(0, cut)));
      ADD_FAILURE() << "cut at " << cut;
    } catch (const InputError& e) {
      EXPECT_TRUE(e.where().byte_offset.has_value()) << e.what();
      EXPECT_NE(e.reason().find("truncated"), std::string::npos) << e.what();
    }
  }
}

TEST(MeshIoPly, RoundTripAsciiAndBinary) {
  const auto dir = scratch_dir();
  write_mesh(dir / "a.ply", awkward_surface());
  expect_same(read_surface(dir / "a.ply"), awkward_surface());
  write_mesh(dir / "b.ply", awkward_surface(), {.binary = true});
  EXPECT_NE(read_bytes(dir / "b.ply").find("binary_little_endian"), std::string::npos);
  expect_same(read_surface(dir / "b.ply"), awkward_surface());
}

TEST(MeshIoPly, Errors) {
  const auto dir = scratch_dir();
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                           "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  expect_read_error(write_bytes(dir / "magic.ply", "plx\n"), "first line must be 'ply'", {1});
  expect_read_error(write_bytes(dir / "be.ply", "ply\nformat binary_big_endian 1.0\n"), "binary_big_endian", {2, {}, 8});
  expect_read_error(write_bytes(dir / "kw.ply", "ply\nformat ascii 1.0\nelemnt vertex 3\n"), "unknown keyword 'elemnt'",
                    {3, {}, 1});
  expect_read_error(write_bytes(dir / "type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty flot x\n"),
                    "unknown property type 'flot'", {4});
  expect_read_error(write_bytes(dir / "noz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                                 "property float y\nend_header\n0 0\n"),
                    "no property 'z'", {3});
  expect_read_error(write_bytes(dir / "hdr.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"), "before 'end_header'");
  expect_read_error(write_bytes(dir / "range.ply", head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
                    "face 0 of 1: vertex index 3 out of range [0, 3)", {13});
  expect_read_error(write_bytes(dir / "num.ply", head + "0 0 0\n1 0 0\n0 one 0\n"), "expected a coordinate, got 'one'",
                    {12, {}, 3});
  expect_read_error(write_bytes(dir / "fit.ply", head + "0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n"), "does not fit", {13});
  expect_read_error(write_bytes(dir / "trunc.ply", head + "0 0 0\n1 0 0\n"), "truncated file");
  const std::string huge_head = "ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\n"
                                "property double x\nproperty double y\nproperty double z\nend_header\n";
  expect_read_error(write_bytes(dir / "huge.ply", huge_head + std::string(30, '\0')),
                    "truncated file: vertex 1 of 2000000000", {{}, huge_head.size() + 24});
}

TEST(MeshIoPly, EmptyElementWithHugeCountIsNotIterated) {
  const auto p = write_bytes(scratch_dir() / "e.ply",
                             "ply\nformat ascii 1.0\nelement nothing 2000000000\nelement vertex 1\n"
                             "property float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n");
  EXPECT_EQ(read_surface(p).vertices, (std::vector<Vec3>{Vec3(1, 2, 3)}));
}

TEST(MeshIoPly, TruncationNeverCrashes) {
  const auto dir = scratch_dir();
  write_mesh(dir / "a.ply", tet_surface());
  expect_prefixes_safe(dir / "cut.ply", read_bytes(dir / "a.ply"));
  write_mesh(dir / "b.ply", tet_surface(), {.binary = true});
  expect_prefixes_safe(dir / "cutb.ply", read_bytes(dir / "b.ply"));
}

// ---------------------------------------------------------------- Gmsh MSH

TEST(MeshIoMsh, Reads22WithPhysicalTagsAndSkipsOtherElements) {
  const auto p = write_bytes(scratch_dir() / "a.msh",
                             "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 5 \"body\"\n$EndPhysicalNames\n"
                             "$Nodes\n5\n10 0 0 0\n20 1 0 0\n30 0 1 0\n40 0 0 1\n50 1 1 1\n$EndNodes\n"
                             "$Elements\n4\n1 15 2 0 1 10\n2 1 2 0 1 10 20\n3 2 2 7 3 10 30 20\n"
                             "4 4 2 5 1 10 20 30 40\n$EndElements\n$NodeData\n1\n\"x\"\n$EndNodeData\n");
  const auto f = read_mesh(p);
  ASSERT_TRUE(f.volume && f.surface);
  EXPECT_EQ(f.format, MeshFormat::msh);
  EXPECT_EQ(f.volume->vertices.size(), 5u);
  EXPECT_EQ(f.volume->tets, (std::vector<Tet>{{0, 1, 2, 3}}));
  EXPECT_EQ(f.volume->tet_regions, (std::vector<int>{5}));
  EXPECT_EQ(f.volume->faces, (std::vector<Triangle>{{0, 2, 1}}));
  EXPECT_EQ(f.volume->face_markers, (std::vector<int>{7}));
  EXPECT_EQ(f.surface->triangles, (std::vector<Triangle>{{0, 2, 1}}));
  EXPECT_EQ(f.skipped, "1 lines (type 1), 1 points (type 15)");
}

TEST(MeshIoMsh, Reads41EntitiesAndNonContiguousTags) {
  const auto p = write_bytes(scratch_dir() / "b.msh",
                             "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n1 0 1 1\n"
                             "1 0 0 0 0\n4 0 0 0 1 1 1 1 11 0\n2 0 0 0 1 1 1 2 3 4 0\n$EndEntities\n"
                             "$Nodes\n2 4 2 90\n0 1 0 1\n90\n5 5 5\n3 2 0 3\n2\n7\n8\n0 0 0\n1 0 0\n0 1 0\n"
                             "$EndNodes\n$Elements\n3 3 1 3\n0 1 15 1\n1 90\n2 4 2 1\n2 2 8 7\n3 2 4 1\n3 2 7 8 90\n"
                             "$EndElements\n");
  const auto f = read_mesh(p);
  ASSERT_TRUE(f.volume);
  EXPECT_EQ(f.volume->vertices[0], Vec3(5, 5, 5));
  EXPECT_EQ(f.volume->tets, (std::vector<Tet>{{1, 2, 3, 0}}));
  EXPECT_EQ(f.volume->tet_regions, (std::vector<int>{3}));
  EXPECT_EQ(f.volume->faces, (std::vector<Triangle>{{1, 3, 2}}));
  EXPECT_EQ(f.volume->face_markers, (std::vector<int>{11}));
}

TEST(MeshIoMsh, RoundTrip22And41) {
  const auto dir = scratch_dir();
  for (int version : {22, 41}) {
    // Appended, not "v" + std::to_string(...): GCC 12 at -O3 warns falsely on the latter
    // (-Wstringop-overflow) once this file shares a unity batch.
    const auto p = dir / std::string("v").append(std::to_string(version)).append(".msh");
    TetMesh m = two_tets();
    m.vertices[4] = Vec3(1.0 / 3.0, 0.1, -0.7);
    write_mesh(p, m, {.msh_version = version});
    const auto f = read_mesh(p);
    ASSERT_TRUE(f.volume);
    expect_same(*f.volume, m);
    // Unlabelled meshes read back unlabelled.
    TetMesh plain = m;
    plain.tet_regions.clear();
    plain.face_markers.clear();
    write_mesh(p, plain, {.msh_version = version});
    expect_same(read_volume(p), plain);
    write_mesh(p, awkward_surface(), {.msh_version = version});
    const auto s = read_mesh(p);
    EXPECT_FALSE(s.volume);
    expect_same(*s.surface, awkward_surface());
  }
  EXPECT_THROW(write_mesh(dir / "x.msh", two_tets(), {.msh_version = 30}), InputError);
}

TEST(MeshIoMsh, Errors) {
  const auto dir = scratch_dir();
  const std::string fmt = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  expect_read_error(write_bytes(dir / "ver.msh", "$MeshFormat\n3.0 0 8\n"), "unsupported MSH version '3.0'", {2, {}, 1});
  expect_read_error(write_bytes(dir / "v1.msh", "$NOD\n"), "end of file while reading $NOD", {1});
  expect_read_error(write_bytes(dir / "first.msh", "$Nodes\n"), "before '$MeshFormat'", {1});
  expect_read_error(write_bytes(dir / "junk.msh", fmt + "hello\n"), "expected a section", {4, {}, 1});
  expect_read_error(write_bytes(dir / "tag.msh", fmt + "$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n"
                                                       "$Elements\n1\n1 2 2 0 0 1 2 9\n$EndElements\n"),
                    "triangle 1 refers to node tag 9, which is not defined", {12, {}, 15});
  expect_read_error(write_bytes(dir / "trunc.msh", fmt + "$Nodes\n3\n1 0 0 0\n2 1 0 0\n"),
                    "end of file while reading 3 nodes: got 2", {7});
  expect_read_error(write_bytes(dir / "huge.msh", fmt + "$Nodes\n2000000000\n1 0 0 0\n"),
                    "2000000000 nodes: got 1");
  expect_read_error(write_bytes(dir / "end.msh", fmt + "$Nodes\n1\n1 0 0 0\n$EndElements\n"),
                    "expected '$EndNodes', got '$EndElements'", {7});
  expect_read_error(write_bytes(dir / "nan.msh", fmt + "$Nodes\n1\n1 0 inf 0\n$EndNodes\n"), "NaN or infinite",
                    {6, {}, 5});
  expect_read_error(write_bytes(dir / "dup.msh", fmt + "$Nodes\n2\n1 0 0 0\n1 0 0 0\n$EndNodes\n"), "defined twice",
                    {7});
  expect_read_error(write_bytes(dir / "nodes.msh", fmt), "no '$Nodes' section");
  expect_read_error(write_bytes(dir / "tetn.msh", fmt + "$Nodes\n1\n1 0 0 0\n$EndNodes\n$Elements\n1\n1 4 0 1 1 1\n"),
                    "tetrahedron 1: expected 4 nodes, got 3", {10});
  expect_read_error(write_bytes(dir / "count41.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 2\n"
                                                     "0 1 0 1\n1\n0 0 0\n$EndNodes\n"),
                    "declares 2 nodes but its blocks hold 1");
  expect_read_error(write_bytes(dir / "skip.msh", fmt + "$Comments\nabc\n"), "missing '$EndComments'");
  // Only elements of other types: an error naming them, not a surface of 0 triangles.
  expect_read_error(write_bytes(dir / "other.msh", fmt + "$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n"
                                                         "$Elements\n2\n1 99 2 0 0 1 2 3\n2 3 2 0 0 1 2 3 1\n$EndElements\n"),
                    "no triangles (type 2) or tetrahedra (type 4) to read (the file holds 1 quadrangles (type 3), "
                    "1 elements of type 99)");
}

TEST(MeshIoMsh, TruncationNeverCrashes) {
  const auto dir = scratch_dir();
  write_mesh(dir / "a.msh", two_tets(), {.msh_version = 41});
  expect_prefixes_safe(dir / "cut.msh", read_bytes(dir / "a.msh"));
  write_mesh(dir / "b.msh", two_tets(), {.msh_version = 22});
  expect_prefixes_safe(dir / "cutb.msh", read_bytes(dir / "b.msh"));
}

// ---------------------------------------------------------------- TetGen

TEST(MeshIoTetGen, ReadsAnySiblingWithAttributesMarkersAndComments) {
  const auto dir = scratch_dir();
  write_bytes(dir / "m.1.node", "# points\n5 3 1 1\n0 0 0 0 2.5 1\n1 1 0 0 0 1 # c\n2 0 1 0 0 1\n3 0 0 1 0 1\n"
                                "4 0.33 0.33 -0.7 0 0\n");
  write_bytes(dir / "m.1.ele", "2 4 1\n0 0 1 2 3 -1\n1 0 2 1 4 2.0\n# end\n");
  write_bytes(dir / "m.1.face", "2 1\n0 0 3 2 4\n1 1 2 3 5\n");
  for (const char* ext : {".node", ".ele", ".face"}) {
    auto p = dir / "m.1";
    p += ext;
    const TetMesh m = read_volume(p);
    EXPECT_EQ(m.vertices.size(), 5u);
    EXPECT_EQ(m.tets, (std::vector<Tet>{{0, 1, 2, 3}, {0, 2, 1, 4}}));
    EXPECT_EQ(m.tet_regions, (std::vector<int>{-1, 2}));
    EXPECT_EQ(m.faces, (std::vector<Triangle>{{0, 3, 2}, {1, 2, 3}}));
    EXPECT_EQ(m.face_markers, (std::vector<int>{4, 5}));
  }
}

TEST(MeshIoTetGen, OneBasedTenNodeAndAdjacencyColumns) {
  const auto dir = scratch_dir();
  write_bytes(dir / "q.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
  write_bytes(dir / "q.ele", "1 10 0\n1 1 2 3 4 1 2 3 4 1 2\n");
  write_bytes(dir / "q.face", "1 0\n1 1 3 2 1 -1\n");
  const TetMesh m = read_volume(dir / "q.node");
  EXPECT_EQ(m.tets, (std::vector<Tet>{{0, 1, 2, 3}}));
  EXPECT_TRUE(m.tet_regions.empty());
  EXPECT_EQ(m.faces, (std::vector<Triangle>{{0, 2, 1}}));
  EXPECT_TRUE(m.face_markers.empty());
}

TEST(MeshIoTetGen, RoundTripAndSurface) {
  const auto dir = scratch_dir();
  TetMesh m = two_tets();
  m.vertices[4] = Vec3(0.1, 0.2, -1e-17);
  write_mesh(dir / "r.ele", m);
  EXPECT_TRUE(fs::exists(dir / "r.node") && fs::exists(dir / "r.face"));
  expect_same(read_volume(dir / "r.node"), m);
  write_mesh(dir / "s.node", awkward_surface());
  EXPECT_FALSE(fs::exists(dir / "s.ele"));
  expect_same(read_surface(dir / "s.face"), awkward_surface());
}

TEST(MeshIoTetGen, Errors) {
  const auto dir = scratch_dir();
  const std::string node = "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n";
  write_bytes(dir / "a.node", node);
  write_bytes(dir / "a.ele", "1 4 0\n0 0 1 2 4\n");
  expect_read_error(dir / "a.node", "tetrahedron 0 refers to point 4, out of range [0, 4)", {2, {}, 9}, dir / "a.ele");
  write_bytes(dir / "a.ele", "3 4 0\n0 0 1 2 3\n");
  expect_read_error(dir / "a.ele", "end of file while reading 3 tetrahedra: got 1", {2}, dir / "a.ele");
  write_bytes(dir / "a.ele", "1 4 1\n0 0 1 2 3 1.5\n");
  expect_read_error(dir / "a.ele", "region attribute must be an integer", {2}, dir / "a.ele");
  write_bytes(dir / "a.ele", "1 4 0\n0 0 1 2 3\n");
  write_bytes(dir / "a.face", "1 1\n0 0 1 2\n");
  expect_read_error(dir / "a.face", "face line needs 5 values, got 4", {2}, dir / "a.face");
  fs::remove(dir / "a.face");
  write_bytes(dir / "a.node", "4 3 0 0\n0 0 0 0\n2 1 0 0\n");
  expect_read_error(dir / "a.node", "expected point number 1, got 2", {3, {}, 1});
  write_bytes(dir / "a.node", "4 2 0 0\n");
  expect_read_error(dir / "a.node", "only 3-dimensional", {1});
  write_bytes(dir / "a.node", "2000000000 3 0 0\n0 0 0 0\n");
  expect_read_error(dir / "a.node", "end of file while reading 2000000000 points: got 1");
  write_bytes(dir / "a.node", "1 3 0 0\n0 0 0 nan\n");
  expect_read_error(dir / "a.node", "NaN or infinite", {2, {}, 7});
  write_bytes(dir / "lonely.node", node);
  expect_read_error(dir / "lonely.node", "neither exists");
}

TEST(MeshIoTetGen, TruncationNeverCrashes) {
  const auto dir = scratch_dir();
  write_mesh(dir / "a.node", two_tets());
  const std::string ele = read_bytes(dir / "a.ele");
  expect_prefixes_safe(dir / "a.ele", ele);
  write_bytes(dir / "a.ele", ele);
  expect_prefixes_safe(dir / "a.node", read_bytes(dir / "a.node"));
}

// ---------------------------------------------------------------- orientation

TEST(MeshIoOrientation, AllNegativeFileIsFlippedMixedIsKept) {
  const auto dir = scratch_dir();
  const std::string nodes = "5 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n4 0.3 0.3 -0.7\n";
  write_bytes(dir / "neg.node", nodes);
  write_bytes(dir / "neg.ele", "2 4 0\n0 0 2 1 3\n1 0 1 2 4\n");  // both negative
  const TetMesh flipped = read_volume(dir / "neg.node");
  EXPECT_EQ(flipped.tets, (std::vector<Tet>{{0, 2, 3, 1}, {0, 1, 4, 2}}));
  for (std::size_t t = 0; t < flipped.tets.size(); ++t) EXPECT_GT(flipped.tet_volume(t), 0.0);
  write_bytes(dir / "mix.node", nodes);
  write_bytes(dir / "mix.ele", "2 4 0\n0 0 1 2 3\n1 0 1 2 4\n");  // one inverted relative to the other
  const TetMesh mixed = read_volume(dir / "mix.node");
  EXPECT_EQ(mixed.tets, (std::vector<Tet>{{0, 1, 2, 3}, {0, 1, 2, 4}}));
  EXPECT_LT(mixed.tet_volume(1), 0.0);
}

// ---------------------------------------------------------------- VTK

TEST(MeshIoVtk, WritesTrianglesAndTets) {
  const auto dir = scratch_dir();
  write_mesh(dir / "s.vtk", tet_surface());
  const std::string s = read_bytes(dir / "s.vtk");
  EXPECT_NE(s.find("DATASET UNSTRUCTURED_GRID"), std::string::npos);
  EXPECT_NE(s.find("POINTS 4 double"), std::string::npos);
  EXPECT_NE(s.find("CELLS 4 16\n3 0 2 1\n"), std::string::npos);
  EXPECT_NE(s.find("CELL_TYPES 4\n5\n5\n5\n5\n"), std::string::npos);
  write_mesh(dir / "v.vtk", two_tets());
  const std::string v = read_bytes(dir / "v.vtk");
  EXPECT_NE(v.find("CELLS 2 10\n4 0 1 2 3\n4 0 2 1 4\n"), std::string::npos);
  EXPECT_NE(v.find("CELL_TYPES 2\n10\n10\n"), std::string::npos);
  EXPECT_NE(v.find("SCALARS region int 1\nLOOKUP_TABLE default\n5\n9\n"), std::string::npos);
  write_mesh(dir / "v.vtu", two_tets());
  const std::string u = read_bytes(dir / "v.vtu");
  EXPECT_NE(u.find("NumberOfPoints=\"5\" NumberOfCells=\"2\""), std::string::npos);
  EXPECT_NE(u.find("Name=\"offsets\" format=\"ascii\">\n4\n8\n"), std::string::npos);
  EXPECT_NE(u.find("Name=\"types\" format=\"ascii\">\n10\n10\n"), std::string::npos);
  EXPECT_NE(u.find("0.3333333333333333"), std::string::npos);  // full precision
  write_mesh(dir / "s.vtu", tet_surface());
  EXPECT_NE(read_bytes(dir / "s.vtu").find("Name=\"types\" format=\"ascii\">\n5\n5\n5\n5\n"), std::string::npos);
}

TEST(MeshIoVtk, WriteVtuWithArraysReadsBackItsMeshAndValues) {
  const auto dir = scratch_dir();
  const TetMesh m = two_tets();
  std::vector<Index> cells;
  for (const auto& t : m.tets) cells.insert(cells.end(), t.begin(), t.end());
  VtuFields fields;
  VtuArray displacement{"displacement", 3, {}};
  for (std::size_t i = 0; i < m.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) displacement.values.push_back(m.vertices[i][k] / 3.0 - 0.1 * static_cast<double>(k));
  fields.point_data.push_back(displacement);
  fields.cell_data.push_back({"strain", 1, {1.0 / 7.0, -2.5e-300}});
  write_vtu(dir / "a.vtu", m.vertices, cells, 4, fields);
  // The geometry through the reader, the arrays as written (every double in full).
  const MeshFile back = read_mesh(dir / "a.vtu");
  ASSERT_TRUE(back.volume);
  EXPECT_EQ(back.volume->vertices, m.vertices);
  EXPECT_EQ(back.volume->tets, m.tets);
  const std::string text = read_bytes(dir / "a.vtu");
  EXPECT_NE(text.find("<PointData>\n<DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\""),
            std::string::npos);
  EXPECT_NE(text.find("<CellData>\n<DataArray type=\"Float64\" Name=\"strain\" NumberOfComponents=\"1\" "
                      "format=\"ascii\">\n0.14285714285714285\n-2.5e-300\n</DataArray>"),
            std::string::npos);
  // Points as vertices (cell type 1).
  write_vtu(dir / "p.vtu", {Vec3(0, 0, 0), Vec3(1, 2, 3)}, {0, 1}, 1, {{{"force", 3, {0, 0, 1, 0, 0, 1}}}, {}});
  EXPECT_NE(read_bytes(dir / "p.vtu").find("Name=\"types\" format=\"ascii\">\n1\n1\n"), std::string::npos);
  // Arrays of the wrong length, cells out of range.
  VtuFields wrong = fields;
  wrong.cell_data[0].values.push_back(1.0);
  EXPECT_THROW(write_vtu(dir / "b.vtu", m.vertices, cells, 4, wrong), std::invalid_argument);
  EXPECT_THROW(write_vtu(dir / "b.vtu", m.vertices, {0, 1, 2, 9}, 4, {}), std::invalid_argument);
  EXPECT_THROW(write_vtu(dir / "b.vtu", m.vertices, {0, 1}, 2, {}), std::invalid_argument);
  EXPECT_THROW(write_vtu(dir / "missing" / "c.vtu", m.vertices, cells, 4, {}), InputError);
}

}  // namespace
}  // namespace tactus::mesh::test
