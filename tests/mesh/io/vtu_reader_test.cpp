// The VTU reader: files the VTK library wrote in each of its encodings (tests/data/meshes/
// SOURCES.md; counts from how they were made or checked apart from the reader), Tactus's
// own .vtu files read back, hand-written variants, and broken files refused with where
// and why.
#include <gtest/gtest.h>
#include <zlib.h>

#include <set>

#include "io_test_util.hpp"
#include "mesh/io/io_common.hpp"

namespace tactus::mesh::test {
namespace {

std::string base64(std::string_view bytes) {
  static constexpr char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t v = static_cast<std::uint8_t>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<std::uint32_t>(static_cast<std::uint8_t>(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) v |= static_cast<std::uint8_t>(bytes[i + 2]);
    out += digits[v >> 18];
    out += digits[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? digits[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? digits[v & 63] : '=';
  }
  return out;
}

std::string zlib_compress(std::string_view bytes) {
  uLongf size = compressBound(static_cast<uLong>(bytes.size()));
  std::string out(size, '\0');
  EXPECT_EQ(compress(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(bytes.data()),
                     static_cast<uLong>(bytes.size())),
            Z_OK);
  out.resize(size);
  return out;
}

template <class T>
std::string bytes_of(std::initializer_list<T> values, std::endian order = std::endian::little) {
  std::string out;
  for (const T v : values) io::append_bytes(out, v, order);
  return out;
}

/// One tetrahedron (points 0-3) and one triangle; `arrays` holds the <Points> and <Cells>.
std::string grid(const std::string& file_attrs, const std::string& arrays, const std::string& appended = "") {
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\"" + file_attrs +
         ">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"4\" NumberOfCells=\"2\">\n" + arrays +
         "</Piece>\n</UnstructuredGrid>\n" + appended + "</VTKFile>\n";
}

const std::string ascii_cells =
    "<Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2 3 0 2 1</DataArray>\n"
    "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">4 7</DataArray>\n"
    "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10 5</DataArray>\n</Cells>\n";
const std::string ascii_points =
    "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">\n"
    "0 0 0  1 0 0  0 1 0  0 0 1\n</DataArray>\n</Points>\n";

void expect_unit_tet(const MeshFile& f) {
  ASSERT_TRUE(f.volume && f.surface);
  EXPECT_EQ(f.volume->vertices, (std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}));
  EXPECT_EQ(f.volume->tets, (std::vector<Tet>{{0, 1, 2, 3}}));
  EXPECT_EQ(f.surface->triangles, (std::vector<Triangle>{{0, 2, 1}}));
}

// ---------------------------------------------------------------- files from VTK

/// The Gmsh cube written by the VTK library (vtk_cube_write.py): 339 points; 1125
/// tetrahedra (region 7), 540 triangles, 3 vertex cells; a point array to skip.
void expect_vtk_cube(const std::string& name) {
  SCOPED_TRACE(name);
  const MeshFile f = read_mesh(data_dir / name);
  EXPECT_EQ(f.format, MeshFormat::vtu);
  ASSERT_TRUE(f.volume && f.surface);
  EXPECT_EQ(f.volume->vertices.size(), 339u);
  EXPECT_EQ(f.volume->tets.size(), 1125u);
  EXPECT_EQ(f.surface->triangles.size(), 540u);
  EXPECT_EQ(f.skipped, "3 vertices");
  EXPECT_EQ(std::set<int>(f.volume->tet_regions.begin(), f.volume->tet_regions.end()), std::set<int>{7});
  EXPECT_NEAR(f.volume->volume(), 1.0, 1e-12);
  const Aabb box = f.volume->bounds();
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(box.min[k], 0.0, 1e-12);
    EXPECT_NEAR(box.max[k], 1.0, 1e-12);
  }
  for (std::size_t t = 0; t < f.volume->tets.size(); ++t) ASSERT_GT(f.volume->tet_volume(t), 0.0) << t;
}

TEST(VtuReader, VtkLibraryEncodings) {
  expect_vtk_cube("vtk_cube_binary_zlib_uint64.vtu");         // inline base64, zlib, UInt64 header
  expect_vtk_cube("vtk_cube_binary_uint32_big_endian.vtu");   // inline base64, UInt32, big endian
  expect_vtk_cube("vtk_cube_appended_raw_zlib_uint64.vtu");   // appended raw, zlib, UInt64
  expect_vtk_cube("vtk_cube_appended_base64_uint32.vtu");     // appended base64, UInt32
}

TEST(VtuReader, VtkDataFiles) {
  // Appended raw, UInt64 header, Float32 points: 35 points, 96 tetrahedra, point data.
  const MeshFile tet = read_mesh(data_dir / "vtkdata_tetrahedron_raw_uint64.vtu");
  ASSERT_TRUE(tet.volume);
  EXPECT_FALSE(tet.surface);
  EXPECT_EQ(tet.volume->vertices.size(), 35u);
  EXPECT_EQ(tet.volume->tets.size(), 96u);
  EXPECT_TRUE(tet.skipped.empty());
  // Appended base64 with zlib blocks and UInt32 headers, each encoded apart: one tet.
  const MeshFile one = read_mesh(data_dir / "vtkdata_cells_tetra_zlib_base64.vtu");
  ASSERT_TRUE(one.volume);
  EXPECT_EQ(one.volume->vertices.size(), 4u);
  EXPECT_EQ(one.volume->tets.size(), 1u);
  EXPECT_GT(one.volume->tet_volume(0), 0.0);
  // Triangles only: a surface.
  const MeshFile tri = read_mesh(data_dir / "vtkdata_triangle_raw_uint64.vtu");
  ASSERT_TRUE(tri.surface);
  EXPECT_FALSE(tri.volume);
  EXPECT_EQ(tri.surface->vertices.size(), 9u);
  EXPECT_EQ(tri.surface->triangles.size(), 8u);
  // Quadratic cells only: nothing to read, and the message says what is there.
  expect_read_error(data_dir / "vtkdata_quadratic_tetra_ascii.vtu",
                    "no tetrahedra or triangles to read (the file holds 1 quadratic tetrahedra, 2 quadratic triangles)",
                    {4});
}

TEST(VtuReader, SofaAsciiVolume) {
  // ASCII with Float32 points and Int32 cells; byte_order BigEndian does not matter to text.
  const MeshFile f = read_mesh(data_dir / "sofa_sea_monster_volume_ascii.vtu");
  ASSERT_TRUE(f.volume);
  EXPECT_EQ(f.volume->vertices.size(), 1175u);
  EXPECT_EQ(f.volume->tets.size(), 3376u);
  EXPECT_NEAR(f.volume->vertices[0].x(), -1.26196238, 1e-6);
}

// ---------------------------------------------------------------- Tactus's own files

TEST(VtuReader, TactusFilesReadBack) {
  const auto dir = scratch_dir();
  TetMesh v;
  v.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1.0 / 3.0, 1.0 / 7.0, 1e-17}};
  v.tets = {{0, 1, 2, 3}, {1, 3, 2, 4}};
  v.tet_regions = {3, -7};
  write_mesh(dir / "v.vtu", v);
  const MeshFile rv = read_mesh(dir / "v.vtu");
  ASSERT_TRUE(rv.volume);
  EXPECT_FALSE(rv.surface);
  EXPECT_EQ(rv.volume->vertices, v.vertices);  // shortest round-trip text: bit for bit
  EXPECT_EQ(rv.volume->tets, v.tets);
  EXPECT_EQ(rv.volume->tet_regions, v.tet_regions);
  v.tet_regions.clear();
  write_mesh(dir / "n.vtu", v);
  EXPECT_TRUE(read_mesh(dir / "n.vtu").volume->tet_regions.empty());

  TriMesh s;
  s.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  s.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  write_mesh(dir / "s.vtu", s);
  const MeshFile rs = read_mesh(dir / "s.vtu");
  ASSERT_TRUE(rs.surface);
  EXPECT_EQ(rs.surface->vertices, s.vertices);
  EXPECT_EQ(rs.surface->triangles, s.triangles);
}

// ---------------------------------------------------------------- hand-written variants

TEST(VtuReader, InlineAsciiWithChildElementsAndOtherArrays) {
  const auto dir = scratch_dir();
  // An InformationKey inside the points array ends its values; other point and cell data
  // (even a non-integer "region" elsewhere) and a comment are skipped.
  const std::string points =
      "<Points>\n<DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" format=\"ascii\">\n"
      "0 0 0 1 0 0 0 1 0 0 0 1\n<InformationKey name=\"L2_NORM_RANGE\"><Value index=\"0\">7 8 9</Value>"
      "</InformationKey>\n</DataArray>\n</Points>\n";
  const std::string data = "<!-- comment -->\n<PointData><DataArray type=\"Float32\" Name=\"region\" format=\"ascii\">"
                           "0.5 1 2 3</DataArray></PointData>\n"
                           "<CellData><DataArray type=\"Int64\" Name=\"region\" format=\"ascii\">4 5</DataArray>"
                           "<DataArray type=\"Float64\" Name=\"stress\" format=\"ascii\">1e9 2e9</DataArray></CellData>\n";
  const MeshFile f = read_mesh(write_bytes(dir / "a.vtu", grid("", data + points + ascii_cells)));
  expect_unit_tet(f);
  EXPECT_EQ(f.volume->tet_regions, std::vector<int>{4});
}

TEST(VtuReader, TwoPiecesAreJoined) {
  const auto dir = scratch_dir();
  const std::string piece2 =
      "<Piece NumberOfPoints=\"3\" NumberOfCells=\"1\">\n<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" "
      "format=\"ascii\">5 0 0 6 0 0 5 1 0</DataArray></Points>\n<Cells>\n"
      "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2</DataArray>\n"
      "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">3</DataArray>\n"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">5</DataArray>\n</Cells>\n</Piece>\n";
  std::string s = grid("", ascii_points + ascii_cells);
  s.insert(s.find("</UnstructuredGrid>"), piece2);
  const MeshFile f = read_mesh(write_bytes(dir / "p.vtu", s));
  ASSERT_TRUE(f.surface);
  EXPECT_EQ(f.surface->vertices.size(), 7u);
  EXPECT_EQ(f.surface->triangles, (std::vector<Triangle>{{0, 2, 1}, {4, 5, 6}}));
}

TEST(VtuReader, BinaryHeadersCompressionAndByteOrders) {
  const auto dir = scratch_dir();
  const std::string xyz = bytes_of<double>({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1});
  const std::string conn = bytes_of<std::int64_t>({0, 1, 2, 3, 0, 2, 1});
  const std::string offsets = bytes_of<std::int64_t>({4, 7});
  const std::string types = bytes_of<std::uint8_t>({10, 5});
  auto arrays = [&](auto&& encode) {
    return "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"binary\">" + encode(xyz) +
           "</DataArray></Points>\n<Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"binary\">\n  " +
           encode(conn) + "\n</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"binary\">" +
           encode(offsets) + "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"binary\">" +
           encode(types) + "</DataArray></Cells>\n";
  };
  // Uncompressed, UInt32 header, header and data in one base64 stream.
  expect_unit_tet(read_mesh(write_bytes(dir / "u32.vtu", grid("", arrays([](const std::string& b) {
    return base64(bytes_of<std::uint32_t>({static_cast<std::uint32_t>(b.size())}) + b);
  })))));
  // zlib in two blocks of at most 32 bytes, UInt64 header, header encoded apart.
  auto zlib64 = [](const std::string& b) {
    std::string header = bytes_of<std::uint64_t>({(b.size() + 31) / 32, 32, b.size() % 32});
    std::string blocks;
    for (std::size_t at = 0; at < b.size(); at += 32) {
      const std::string packed = zlib_compress(b.substr(at, 32));
      io::append_bytes(header, static_cast<std::uint64_t>(packed.size()), std::endian::little);
      blocks += packed;
    }
    return base64(header) + base64(blocks);
  };
  expect_unit_tet(read_mesh(write_bytes(dir / "z64.vtu", grid(" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"",
                                                               arrays(zlib64)))));
  // Big endian, Float32 points and Int32 cells in raw appended data.
  std::string appended;
  auto raw_big = [&](const std::string& type, const std::string& name, const std::string& b, int comps = 1) {
    const std::size_t offset = appended.size();
    io::append_bytes(appended, static_cast<std::uint32_t>(b.size()), std::endian::big);
    appended += b;
    return "<DataArray type=\"" + type + "\" Name=\"" + name + "\" NumberOfComponents=\"" + std::to_string(comps) +
           "\" format=\"appended\" offset=\"" + std::to_string(offset) + "\"/>\n";
  };
  const std::string big_arrays =
      "<Points>" + raw_big("Float32", "Points", bytes_of<float>({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, std::endian::big), 3) +
      "</Points><Cells>" + raw_big("Int32", "connectivity", bytes_of<std::int32_t>({0, 1, 2, 3, 0, 2, 1}, std::endian::big)) +
      raw_big("Int32", "offsets", bytes_of<std::int32_t>({4, 7}, std::endian::big)) +
      raw_big("UInt8", "types", bytes_of<std::uint8_t>({10, 5})) + "</Cells>\n";
  expect_unit_tet(read_mesh(write_bytes(
      dir / "big.vtu", grid(" byte_order=\"BigEndian\"", big_arrays,
                            "<AppendedData encoding=\"raw\">\n   _" + appended + "\n</AppendedData>\n"))));
}

// ---------------------------------------------------------------- broken files

TEST(VtuReader, BrokenXmlAndAttributes) {
  const auto dir = scratch_dir();
  const std::string ok = grid("", ascii_points + ascii_cells);
  expect_read_error(write_bytes(dir / "xml.vtu", "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\">\n<Piece>\n"),
                    "malformed XML", {4});
  expect_read_error(write_bytes(dir / "root.vtu", "<VTK type=\"UnstructuredGrid\"/>"), "root element is <VTK>", {1});
  expect_read_error(write_bytes(dir / "poly.vtu", "\n<VTKFile type=\"PolyData\"/>"), "type 'PolyData' is not read", {2});
  expect_read_error(write_bytes(dir / "empty.vtu", ""), "malformed XML", {1});
  expect_read_error(write_bytes(dir / "lz4.vtu", grid(" compressor=\"vtkLZ4DataCompressor\"", "")),
                    "compressor 'vtkLZ4DataCompressor' is not supported", {2});
  expect_read_error(write_bytes(dir / "header.vtu", grid(" header_type=\"UInt16\"", "")), "header_type must be UInt32 or UInt64", {2});
  expect_read_error(write_bytes(dir / "order.vtu", grid(" byte_order=\"Middle\"", "")), "byte_order must be", {2});
  expect_read_error(write_bytes(dir / "doctype.vtu", "<!DOCTYPE x [<!ENTITY a \"b\">]>\n<VTKFile/>"), "DOCTYPE", {1});
  std::string count = ok;
  count.replace(count.find("NumberOfPoints=\"4\""), 18, "NumberOfPoints=\"-4\"");
  expect_read_error(write_bytes(dir / "count.vtu", count), "NumberOfPoints must be a count, got '-4'", {4});
  std::string type = ok;
  type.replace(type.find("Float32"), 7, "Float16");
  expect_read_error(write_bytes(dir / "type.vtu", type), "DataArray 'Points': unknown type 'Float16'", {6});
  std::string noconn = ok;
  noconn.replace(noconn.find("connectivity"), 12, "connections");
  expect_read_error(write_bytes(dir / "noconn.vtu", noconn), "the piece has no cell connectivity array", {4});
}

TEST(VtuReader, BrokenAsciiValues) {
  const auto dir = scratch_dir();
  std::string token = grid("", ascii_points + ascii_cells);
  token.replace(token.find("0 1 0  0 0 1"), 5, "0 x 0");
  expect_read_error(write_bytes(dir / "token.vtu", token), "expected a finite number, got 'x'", {7});
  std::string few = grid("", ascii_points + ascii_cells);
  few.replace(few.find(">4 7<"), 5, ">4<");
  expect_read_error(write_bytes(dir / "few.vtu", few), "DataArray 'offsets' holds 1 values, expected 2", {12});
  std::string index = grid("", ascii_points + ascii_cells);
  index.replace(index.find("0 1 2 3 0 2 1"), 13, "0 1 2 9 0 2 1");
  expect_read_error(write_bytes(dir / "index.vtu", index), "cell 0 refers to point 9 of a piece with 4 points", {11});
  std::string offsets = grid("", ascii_points + ascii_cells);
  offsets.replace(offsets.find(">4 7<"), 5, ">4 9<");
  expect_read_error(write_bytes(dir / "offsets.vtu", offsets), "cell 1's offsets 4..9 lie outside the connectivity (7 values)",
                    {12});
  std::string negative = grid("", ascii_points + ascii_cells);
  negative.replace(negative.find(">10 5<"), 6, ">10 -5<");
  expect_read_error(write_bytes(dir / "negative.vtu", negative), "expected a non-negative integer, got '-5'", {13});
  std::string floaty = grid("", ascii_points + ascii_cells);
  floaty.replace(floaty.find("\"Int32\" Name=\"offsets\""), 7, "\"Float32\"");
  expect_read_error(write_bytes(dir / "floaty.vtu", floaty), "has type Float32; an integer type is needed", {12});
  std::string size = grid("", ascii_points + ascii_cells);
  size.replace(size.find(">4 7<"), 5, ">3 7<");
  expect_read_error(write_bytes(dir / "size.vtu", size), "cell 0 of type 10 has 3 points", {11});
}

TEST(VtuReader, BrokenBinaryData) {
  const auto dir = scratch_dir();
  const std::string types = bytes_of<std::uint8_t>({10, 5});
  auto with_types = [&](const std::string& file_attrs, const std::string& encoded) {
    std::string s = grid(file_attrs, ascii_points + ascii_cells);
    const std::size_t at = s.find("<DataArray type=\"UInt8\"");
    s.replace(at, s.find("</DataArray>", at) - at,
              "<DataArray type=\"UInt8\" Name=\"types\" format=\"binary\">" + encoded);
    return s;
  };
  const std::string header = base64(bytes_of<std::uint32_t>({2}) + types);
  std::string bad = with_types("", header);
  const std::size_t at = bad.find(header) + 3;
  bad[at] = '*';
  expect_read_error(write_bytes(dir / "char.vtu", bad), "invalid base64 character '*'", {{}, at});
  std::string pad = with_types("", header);
  pad.replace(pad.find(header), 4, "A===");
  expect_read_error(write_bytes(dir / "pad.vtu", pad), "invalid base64 padding", {{}, pad.find("A===")});
  const std::string shortened = base64(bytes_of<std::uint32_t>({200}) + types);
  const std::string trunc = with_types("", shortened);
  expect_read_error(write_bytes(dir / "trunc.vtu", trunc), "truncated data: DataArray 'types' needs 200 bytes");
  const std::string wrong_size = with_types("", base64(bytes_of<std::uint32_t>({3}) + types + "x"));
  expect_read_error(write_bytes(dir / "count.vtu", wrong_size), "DataArray 'types' holds 3 values, expected 2", {13});

  // zlib: corrupt data, and a header claiming more than deflate can expand to.
  const std::string z = " compressor=\"vtkZLibDataCompressor\"";
  std::string packed = zlib_compress(types);
  packed[2] = static_cast<char>(packed[2] ^ 0x55);
  packed.back() = static_cast<char>(packed.back() ^ 0x55);
  const std::string corrupt = base64(bytes_of<std::uint32_t>({1, 2, 2, static_cast<std::uint32_t>(packed.size())})) + base64(packed);
  const std::string corrupt_file = with_types(z, corrupt);
  expect_read_error(write_bytes(dir / "zlib.vtu", corrupt_file), "DataArray 'types': zlib error in block 0",
                    {{}, corrupt_file.find(corrupt) + 24});
  const std::string good = zlib_compress(types);
  const std::string bomb = base64(bytes_of<std::uint32_t>({1, 4000000000u, 0, static_cast<std::uint32_t>(good.size())})) +
                           base64(good);
  expect_read_error(write_bytes(dir / "bomb.vtu", with_types(z, bomb)), "more than zlib can expand");
  const std::string blocks = base64(bytes_of<std::uint32_t>({2000000000, 2, 2}));
  expect_read_error(write_bytes(dir / "blocks.vtu", with_types(z, blocks)), "truncated data: DataArray 'types' compressed block sizes");
}

TEST(VtuReader, BrokenAppendedData) {
  const auto dir = scratch_dir();
  auto appended = [&](std::uint64_t offset, const std::string& data, const std::string& tail = "\n</AppendedData>\n") {
    std::string s = grid("", ascii_points + ascii_cells, "<AppendedData encoding=\"raw\">\n _" + data + tail);
    const std::size_t at = s.find("<DataArray type=\"UInt8\"");
    s.replace(at, s.find("</DataArray>", at) + 12 - at,
              "<DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"" + std::to_string(offset) + "\"/>");
    return s;
  };
  const std::string types = bytes_of<std::uint32_t>({2}) + bytes_of<std::uint8_t>({10, 5});
  expect_unit_tet(read_mesh(write_bytes(dir / "ok.vtu", appended(0, types))));
  expect_read_error(write_bytes(dir / "offset.vtu", appended(99, types)),
                    "DataArray 'types': offset 99 lies past the end of the 7 bytes of appended data", {13});
  // The header wants 5 bytes; 2 and the newline before </AppendedData> are there.
  const std::string cut = appended(0, bytes_of<std::uint32_t>({5}) + "\x0a\x05");
  expect_read_error(write_bytes(dir / "cut.vtu", cut), "truncated data: DataArray 'types' needs 5 bytes, at most 3 left",
                    {{}, cut.find('_') + 5});
  const std::string open = appended(0, types, "");
  expect_read_error(write_bytes(dir / "open.vtu", open), "no '</AppendedData>' after the appended data",
                    {{}, open.find('_') + 1});
  std::string mark = appended(0, types);
  mark[mark.find('_')] = '#';
  expect_read_error(write_bytes(dir / "mark.vtu", mark), "appended data must start with '_'", {{}, mark.find('#')});
  std::string none = grid("", ascii_points + ascii_cells);
  none.replace(none.find("format=\"ascii\">10 5"), 19, "format=\"appended\" offset=\"0\">");
  expect_read_error(write_bytes(dir / "none.vtu", none), "is appended but the file has no <AppendedData>", {13});
}

TEST(VtuReader, DeeplyNestedElements) {
  // Elements nested deeper than the element stack's first allocation (once a read after
  // free under ASan, found by the fuzzer).
  const auto dir = scratch_dir();
  std::string nested;
  for (int i = 0; i < 40; ++i) nested += "<Extra>";
  nested += "<DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">1</DataArray>";
  for (int i = 0; i < 40; ++i) nested += "</Extra>";
  expect_unit_tet(read_mesh(write_bytes(dir / "n.vtu", grid("", nested + ascii_points + ascii_cells))));
}

TEST(VtuReader, TruncationNeverCrashes) {
  // Every prefix of real files in three encodings: an InputError or a mesh, nothing else.
  for (const char* name : {"vtkdata_cells_tetra_zlib_base64.vtu", "vtkdata_triangle_raw_uint64.vtu",
                           "vtkdata_quadratic_tetra_ascii.vtu"}) {
    const std::string whole = read_bytes(data_dir / name);
    for (std::size_t n = 0; n < whole.size(); n += 7) {
      try {
        (void)io::parse_vtu(std::string_view(whole).substr(0, n), name);
      } catch (const InputError&) {
      }
    }
  }
}

}  // namespace
}  // namespace tactus::mesh::test
