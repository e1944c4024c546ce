// End to end: the `tactus` binary as a user runs it.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/generators.hpp"
#include "mesh/io/mesh_io.hpp"

namespace fs = std::filesystem;

namespace {

struct Result {
  int exit_code;
  std::string out;
  std::string err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("tactus_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  Result run(const std::string& args) {
    const fs::path out = dir_ / "stdout.txt";
    const fs::path err = dir_ / "stderr.txt";
    const std::string cmd = std::string("CI=1 '") + TACTUS_BINARY + "' " + args + " >'" +
                            out.string() + "' 2>'" + err.string() + "' </dev/null";
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
  }

  fs::path dir_;
};

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

TEST_F(Cli, VersionSucceeds) {
  const auto r = run("version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("tactus 0."), std::string::npos) << r.out;
}

TEST_F(Cli, HelpListsSubcommands) {
  const auto r = run("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* sub : {"version", "inspect", "mesh", "run", "bench", "replay", "export"})
    EXPECT_NE(r.out.find(sub), std::string::npos) << sub;
  EXPECT_EQ(run("mesh --help").exit_code, 0);
}

TEST_F(Cli, BadFlagIsAUserErrorOnOneLine) {
  for (const char* args : {"--no-such-flag", "frobnicate", "", "inspect"}) {
    const auto r = run(args);
    EXPECT_EQ(r.exit_code, 1) << args;
    EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
  }
}

TEST_F(Cli, InspectMissingFileIsAUserError) {
  const auto r = run("inspect " + (dir_ / "nope.obj").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("nope.obj"), std::string::npos) << r.err;
}

TEST_F(Cli, InspectReportsAGoodTetrahedron) {
  std::ofstream(dir_ / "tet.node") << "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n";
  std::ofstream(dir_ / "tet.ele") << "1 4 0\n0 0 1 2 3\n";
  const auto r = run("inspect " + (dir_ / "tet.node").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("4 vertices"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1 tetrahedra"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("0.1666"), std::string::npos) << r.out;  // volume 1/6
  EXPECT_NE(r.out.find("no problems"), std::string::npos) << r.out;
}

TEST_F(Cli, InspectFlagsAnInvertedTetrahedron) {
  std::ofstream(dir_ / "bad.node") << "5 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n4 0 0 -1\n";
  std::ofstream(dir_ / "bad.ele") << "2 4 0\n0 0 1 2 3\n1 0 1 2 4\n";  // second one inverted
  const auto r = run("inspect " + (dir_ / "bad.node").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("tetrahedron 1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("inverted"), std::string::npos) << r.out;
}

TEST_F(Cli, InspectFlagsAnOpenSurfaceAndMalformedFile) {
  std::ofstream(dir_ / "open.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  auto r = run("inspect " + (dir_ / "open.obj").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;  // an open sheet is a valid surface, with a warning
  EXPECT_NE(r.out.find("boundary"), std::string::npos) << r.out;

  std::ofstream(dir_ / "broken.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
  r = run("inspect " + (dir_ / "broken.obj").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("broken.obj:4"), std::string::npos) << r.err;
}

TEST_F(Cli, InspectNamesElementsAsTheFileNumbersThem) {
  // OBJ counts from 1: the flat face is the third 'f', on line 9.
  std::ofstream(dir_ / "flat.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0.5 0.5 0\n# faces\n"
                                      "f 1 3 2\nf 1 2 4\nf 2 5 3\nf 1 4 3\nf 2 3 4\n";
  auto r = run("inspect " + (dir_ / "flat.obj").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("face 3 (line 9, vertices 2 5 3): degenerate"), std::string::npos) << r.out;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("flat.obj: 2 errors; the first: face 3 (line 9"), std::string::npos) << r.err;

  // OFF counts from 0.
  std::ofstream(dir_ / "flat.off") << "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0.5 0.5 0\n3 0 1 2\n3 1 3 2\n";
  r = run("inspect " + (dir_ / "flat.off").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("face 1 (line 8, vertices 1 3 2): degenerate"), std::string::npos) << r.out;

  // Gmsh: element and node tags as written.
  std::ofstream(dir_ / "mix.msh") << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n10 0 0 0\n20 1 0 0\n"
                                     "30 0 1 0\n40 0 0 1\n50 0 0 -1\n$EndNodes\n$Elements\n2\n"
                                     "7 4 2 0 1 10 20 30 40\n9 4 2 0 1 10 20 30 50\n$EndElements\n";
  r = run("inspect " + (dir_ / "mix.msh").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("element 9 (line 15, vertices 10 20 30 50): inverted"), std::string::npos) << r.out;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;

  // TetGen: from its first index (1 here).
  std::ofstream(dir_ / "one.node") << "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 0 0 -1\n";
  std::ofstream(dir_ / "one.ele") << "2 4 0\n1 1 2 3 4\n2 1 2 3 5\n";
  r = run("inspect " + (dir_ / "one.node").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("tetrahedron 2 (line 3, vertices 1 2 3 5): inverted"), std::string::npos) << r.out;
}

TEST_F(Cli, InspectFindsSelfIntersectionsAndCoincidentVertices) {
  using tactus::mesh::TriMesh;
  TriMesh two = tactus::mesh::sphere(1.0, 2);
  TriMesh other = tactus::mesh::sphere(1.0, 2);
  const auto offset = static_cast<tactus::mesh::Index>(two.vertices.size());
  for (const auto& v : other.vertices) two.vertices.push_back(v + tactus::Vec3(0.8, 0.1, 0.0));
  for (const auto& t : other.triangles) two.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  const fs::path obj = dir_ / "crossing.obj";
  tactus::mesh::write_mesh(obj, two);
  auto r = run("inspect " + obj.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("surface intersects itself:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(") intersect"), std::string::npos) << r.out;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("crossing.obj"), std::string::npos) << r.err;
  // Tetrahedralization refuses it the same way, before TetGen runs.
  r = run("mesh " + obj.string() + " -o " + (dir_ / "t.msh").string() + " --max-volume 0.01");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("intersects itself"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");

  // A vertex repeated a hair away and one no face uses: warnings, exit 0.
  std::ofstream(dir_ / "seam.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 1e-12 0 0\nv 5 5 5\n"
                                      "f 1 3 2\nf 5 2 4\nf 1 4 3\nf 2 3 4\n";
  r = run("inspect " + (dir_ / "seam.obj").string());
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("vertex 5: coincides with vertex 1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("vertex 6: unused"), std::string::npos) << r.out;
  EXPECT_EQ(r.err, "");
}

TEST_F(Cli, ConvertingSaysWhatHappenedToInvertedTetrahedra) {
  // All negative: the mirrored convention, flipped as a whole, said on stderr.
  std::ofstream(dir_ / "neg.node") << "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
  std::ofstream(dir_ / "neg.ele") << "1 4 0\n1 1 3 2 4\n";
  auto r = run("mesh " + (dir_ / "neg.node").string() + " -o " + (dir_ / "neg.vtu").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("flipped all 1 tetrahedra"), std::string::npos) << r.err;
  // A mix: written as they are, with a warning naming them as the file numbers them.
  std::ofstream(dir_ / "mix.node") << "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 0 0 -1\n";
  std::ofstream(dir_ / "mix.ele") << "3 4 0\n1 1 2 3 4\n2 1 2 3 5\n3 1 3 2 5\n";
  r = run("mesh " + (dir_ / "mix.node").string() + " -o " + (dir_ / "mix.vtk").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("1 inverted tetrahedra written as they are: 2 (file numbering)"), std::string::npos) << r.err;
  // A clean file: nothing on stderr.
  std::ofstream(dir_ / "ok.node") << "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
  std::ofstream(dir_ / "ok.ele") << "1 4 0\n1 1 2 3 4\n";
  r = run("mesh " + (dir_ / "ok.node").string() + " -o " + (dir_ / "ok.msh").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
}

TEST_F(Cli, GeneratesAndConvertsMeshes) {
  const fs::path stl = dir_ / "sphere.stl";
  auto r = run("mesh --generate sphere --size 0.05 --resolution 3 -o " + stl.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path ply = dir_ / "sphere.ply";
  r = run("mesh " + stl.string() + " -o " + ply.string() + " --binary");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto a = tactus::mesh::read_mesh(stl);
  const auto b = tactus::mesh::read_mesh(ply);
  ASSERT_TRUE(a.surface && b.surface);
  EXPECT_EQ(a.surface->vertices.size(), b.surface->vertices.size());
  EXPECT_EQ(a.surface->triangles.size(), b.surface->triangles.size());
  // r = 5 cm: an icosphere at 3 subdivisions holds within 2% of 4/3 pi r^3.
  EXPECT_NEAR(b.surface->signed_volume(), 4.0 / 3.0 * M_PI * 0.05 * 0.05 * 0.05, 0.02 * 5.3e-4);
}

TEST_F(Cli, TetrahedralizesTheOrganToANodeCount) {
  const fs::path surface = dir_ / "organ.obj";
  auto r = run("mesh --generate organ --size 0.22 --resolution 7 -o " + surface.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path volume = dir_ / "organ.msh";
  r = run("mesh " + surface.string() + " -o " + volume.string() + " --nodes 500");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto m = tactus::mesh::read_mesh(volume);
  ASSERT_TRUE(m.volume);
  EXPECT_NEAR(static_cast<double>(m.volume->vertices.size()), 500.0, 50.0);
  r = run("inspect " + volume.string());
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
}

TEST_F(Cli, TetrahedralizingAnOpenSurfaceIsAUserError) {
  std::ofstream(dir_ / "open.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const auto r = run("mesh " + (dir_ / "open.obj").string() + " -o " + (dir_ / "o.msh").string() +
                     " --max-volume 0.01");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
}

TEST_F(Cli, TetrahedralizationStopsAtTheTimeout) {
  const fs::path surface = dir_ / "sphere.stl";
  ASSERT_EQ(run("mesh --generate sphere --size 0.05 --resolution 3 -o " + surface.string()).exit_code, 0);
  const auto r = run("mesh " + surface.string() + " -o " + (dir_ / "s.msh").string() +
                     " --max-volume 1e-11 --timeout 0.2");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("did not finish within 0.2 s"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--timeout"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_FALSE(fs::exists(dir_ / "s.msh"));
}

TEST_F(Cli, MeshAndInspectRefuseBadInputOnStderrOnly) {
  std::ofstream(dir_ / "empty.obj") << "";
  std::ofstream(dir_ / "open.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(dir_ / "tet.node") << "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n";
  std::ofstream(dir_ / "tet.ele") << "1 4 0\n0 0 1 2 3\n";
  fs::create_directories(dir_ / "folder.obj");
  const std::string d = dir_.string() + "/";
  const std::vector<std::string> refused = {
      "inspect " + d + "nope.obj",
      "inspect " + d + "folder.obj",
      "inspect " + d + "empty.obj",
      "inspect " + d + "open.xyz",
      "mesh -o " + d + "a.obj",
      "mesh " + d + "open.obj --generate box -o " + d + "a.obj",
      "mesh --generate blob -o " + d + "a.obj",
      "mesh " + d + "tet.node -o " + d + "a.msh --max-volume 1",
      "mesh " + d + "open.obj -o " + d + "a.msh --max-volume 1",
      "mesh " + d + "tet.node -o " + d + "a.obj",
      "mesh " + d + "open.obj -o " + d + "no/such/folder/a.obj",
      "mesh " + d + "open.obj -o " + d + "a.msh --nodes 100 --max-volume 1",
      "mesh " + d + "open.obj -o " + d + "a.xyz",
      "mesh " + d + "empty.obj -o " + d + "a.stl",
  };
  for (const auto& args : refused) {
    const auto r = run(args);
    EXPECT_EQ(r.exit_code, 1) << args;
    EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
    EXPECT_EQ(r.err.rfind("tactus: ", 0), 0u) << args << ": " << r.err;
    EXPECT_EQ(r.out, "") << args;
  }
  EXPECT_FALSE(fs::exists(dir_ / "a.obj"));
  EXPECT_FALSE(fs::exists(dir_ / "a.msh"));
}

TEST_F(Cli, RunsTheDefaultScene) {
  const auto r = run("run --duration 1 --json " + (dir_ / "t.json").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("haptic[hand]"), std::string::npos) << r.out;  // the timing table
  EXPECT_NE(r.out.find("p99.9"), std::string::npos) << r.out;
  std::ifstream json(dir_ / "t.json");
  const std::string text((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\"loops\""), std::string::npos) << text;
}

TEST_F(Cli, RecordsReplaysAndExportsALockstepRun) {
  const std::string rec = (dir_ / "press.tacrec").string();
  ASSERT_EQ(run("run --lockstep --duration 1.5 --record " + rec).exit_code, 0);
  const auto replay = run("replay " + rec);
  EXPECT_EQ(replay.exit_code, 0) << replay.err;
  EXPECT_NE(replay.out.find("1501 of 1501 frames compared, 1501 forces identical"), std::string::npos) << replay.out;
  const auto exported = run("export " + rec + " --csv " + (dir_ / "f.csv").string());
  EXPECT_EQ(exported.exit_code, 0) << exported.err;
  std::ifstream csv(dir_ / "f.csv");
  std::string line;
  std::size_t lines = 0;
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, 1502u);  // header + frames
}

TEST_F(Cli, RunAndReplayRejectBadInputOnOneLine) {
  std::ofstream(dir_ / "junk.tacrec") << "not a recording at all";
  for (const std::string& args : std::vector<std::string>{"replay " + (dir_ / "junk.tacrec").string(),
                                 "run --device nonsense",
                                 "run --device replay:" + (dir_ / "junk.tacrec").string(),
                                 "export " + (dir_ / "junk.tacrec").string() + " --csv " + (dir_ / "x.csv").string(),
                                 "run " + (dir_ / "no_such_scene.toml").string()}) {
    const auto r = run(args);
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
  }
}

TEST_F(Cli, RunRejectsABadSceneWithItsLocation) {
  std::ofstream(dir_ / "bad.toml") << "[scene]\nname = \"x\"\n\n[materials.skin]\nyoung_modulus = -5\n";
  const auto r = run("run " + (dir_ / "bad.toml").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("bad.toml:"), std::string::npos) << r.err;
}

TEST_F(Cli, RunRejectsBrokenPropertyImagesOnOneLine) {
  // A touchable object whose property image file is garbage, and one whose surface is open.
  const std::string tail = R"(
[devices.hand]
type = "scripted"
trajectory = { type = "press", position = [0.0, 0.0, 0.06], depth = 0.005 }
[tools.finger]
type = "sphere"
device = "hand"
radius = 0.003
[algorithms.touch]
type = "proxy"
tool = "finger"
)";
  std::ofstream(dir_ / "garbage.h5") << "not an image file";
  std::ofstream(dir_ / "garbage.toml") << "[bodies.ball]\nkind = \"rigid\"\n"
                                          "mesh = { generator = \"sphere\", radius = 0.05 }\n"
                                          "properties = { file = \"garbage.h5\" }\n"
                                       << tail;
  auto r = run("run --lockstep " + (dir_ / "garbage.toml").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("garbage.h5"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not an HDF5 file"), std::string::npos) << r.err;
  std::ofstream(dir_ / "open.toml") << "[bodies.sheet]\nkind = \"rigid\"\n"
                                       "mesh = { generator = \"grid_plate\", size = [0.1, 0.1] }\n"
                                       "properties = { stiffness = 400.0 }\n"
                                    << tail;
  r = run("run --lockstep " + (dir_ / "open.toml").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("body 'sheet'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("closed"), std::string::npos) << r.err;
}

}  // namespace

namespace {

std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::stringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

double column(const std::vector<std::vector<std::string>>& rows, const std::string& name, std::size_t row) {
  for (std::size_t c = 0; c < rows[0].size(); ++c)
    if (rows[0][c] == name) return std::stod(rows.at(row).at(c));
  ADD_FAILURE() << "no column " << name;
  return 0.0;
}

TEST_F(Cli, SolvesTheCantileverStatically) {
  const fs::path csv = dir_ / "beam.csv";
  const fs::path vtu = dir_ / "beam.vtu";
  const auto r = run("solve " + std::string(TACTUS_SOURCE_DIR) + "/scenes/cantilever.toml --static --csv " +
                     csv.string() + " -o " + vtu.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(fs::exists(vtu));
  const auto rows = parse_csv(slurp(csv));
  ASSERT_EQ(rows.size(), 2u);
  // Equilibrium: the clamp's reaction returns the 1 mN load (computed from the internal
  // forces, so this checks the solve, to its 1e-8 residual).
  EXPECT_NEAR(column(rows, "clamp_fz", 1), 0.001, 1e-9);
  EXPECT_NEAR(column(rows, "clamp_fx", 1), 0.0, 1e-9);
  // Timoshenko: F L³/(3EI) + F L/(κGA) with κ = 5/6 = 4.031e-4 m. Conforming linear tets are
  // too stiff (the discrete compliance is a lower bound), and this coarse mesh (6 elements
  // through the thickness) sits within 20% below it; the refinement study is in the FEM tests.
  const double timoshenko = 0.001 * 1e-3 / (3 * 1e6 * 1e-8 / 12) + 0.001 * 0.1 / (5.0 / 6 * 1e6 / 2.6 * 1e-4);
  const double tip = -column(rows, "tip_uz", 1);
  EXPECT_LT(tip, timoshenko);
  EXPECT_GT(tip, 0.8 * timoshenko);
  EXPECT_EQ(column(rows, "converged", 1), 1.0);
}

TEST_F(Cli, SolvesDynamicallyWithAProbeFile) {
  std::ofstream(dir_ / "probes.csv") << "name,x,y,z\nmid,0.0,0.0,0.0\n";
  const auto r = run("solve " + std::string(TACTUS_SOURCE_DIR) + "/scenes/cantilever.toml --until 0.05 --every 0.01 --probe " +
                     (dir_ / "probes.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = parse_csv(r.out);
  ASSERT_GE(rows.size(), 6u);  // header, rest, and a row every 10 ms
  EXPECT_EQ(rows[0][0], "step");
  EXPECT_EQ(column(rows, "mid_uz", 1), 0.0);  // the rest state
  EXPECT_LT(column(rows, "tip_uz", rows.size() - 1), 0.0);
}

TEST_F(Cli, SolveRejectsABadProbeFile) {
  std::ofstream(dir_ / "probes.csv") << "name,x,y,z\nmid,0.0,zero,0.0\n";
  const auto r = run("solve " + std::string(TACTUS_SOURCE_DIR) + "/scenes/cantilever.toml --static --probe " +
                     (dir_ / "probes.csv").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("probes.csv:2: expected numbers"), std::string::npos) << r.err;
}

/// A 2 cm cube on its base, the node at the centre of its top pressed 1 cm down (two element
/// heights) in one load step.
std::string pressed_cube(const std::string& law, const std::string& extra) {
  return R"([materials.gel]
model = ")" + law + R"("
young_modulus = 1e4
poisson_ratio = 0.45
density = 1000

[bodies.cube]
kind = "fem"
material = "gel"
solver = "cholesky"
mesh = { generator = "box", size = [0.02, 0.02, 0.02], cells = [4, 4, 4] }

[[bodies.cube.fixed]]
name = "base"
side = "z_min"

[[bodies.cube.prescribed]]
name = "finger"
box = { min = [-0.001, -0.001, 0.009], max = [0.001, 0.001, 0.011] }
displacement = [0, 0, -0.010]
)" + extra;
}

TEST_F(Cli, StaticSolveHalvesALoadStepThatDoesNotConverge) {
  // Four Newton iterations are too few for the whole press at once: the step is halved and
  // the solve ends where eight load steps end.
  std::ofstream(dir_ / "halved.toml") << pressed_cube("neo_hookean", "[solve]\nmax_iterations = 4\n");
  const auto halved = run("solve --static " + (dir_ / "halved.toml").string());
  ASSERT_EQ(halved.exit_code, 0) << halved.err;
  EXPECT_NE(halved.err.find("load step halving(s) to converge"), std::string::npos) << halved.err;
  std::string stepped_scene = pressed_cube("neo_hookean", "");
  stepped_scene.insert(stepped_scene.find("mesh = {"), "load_steps = 8\n");
  std::ofstream(dir_ / "stepped.toml") << stepped_scene;
  const auto stepped = run("solve --static " + (dir_ / "stepped.toml").string());
  ASSERT_EQ(stepped.exit_code, 0) << stepped.err;
  const auto a = parse_csv(halved.out), b = parse_csv(stepped.out);
  const double fz = column(b, "finger_fz", b.size() - 1);
  EXPECT_LT(fz, -1.0);  // about 1.3 N to hold the finger down
  EXPECT_NEAR(column(a, "finger_fz", a.size() - 1), fz, 1e-7 * std::abs(fz));
  EXPECT_EQ(column(a, "converged", a.size() - 1), 1.0);
}

TEST_F(Cli, StaticSolveRefusesAnEquilibriumWithAnElementInsideOut) {
  // St. Venant-Kirchhoff balances this press only with elements under the finger turned
  // inside out: every halving ends there, and the solve stops with exit 1 and the reason.
  std::ofstream(dir_ / "stvk.toml") << pressed_cube("stvk", "[solve]\nmax_step_halvings = 3\n");
  const auto r = run("solve --static " + (dir_ / "stvk.toml").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("body 'cube' stopped at load step 1/1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("after 3 halvings"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("an element inside out"), std::string::npos) << r.err;
  const auto rows = parse_csv(r.out);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(column(rows, "converged", 1), 0.0);
  EXPECT_LT(column(rows, "load_fraction", 1), 1.0);  // the last equilibrium reached
}

TEST_F(Cli, BenchFemTimesTheSceneFemBodies) {
  const auto r = run("bench --fem " + std::string(TACTUS_SOURCE_DIR) + "/scenes/cantilever.toml --steps 5 --threads 1 "
                     "--solver cholesky --law stvk");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("ns/tet"), std::string::npos) << r.out;
  const auto row = r.out.find("\nbeam ");
  ASSERT_NE(row, std::string::npos) << r.out;
  std::istringstream cells(r.out.substr(row + 1));
  std::string body, law, solver;
  double nodes = 0, tets = 0, dt = 0, threads = 0, median = 0, p99 = 0, mean = 0, ns = 0, its = 0;
  cells >> body >> law >> solver >> nodes >> tets >> dt >> threads >> median >> p99 >> mean >> ns >> its;
  EXPECT_EQ(law, "stvk");
  EXPECT_EQ(solver, "cholesky");
  EXPECT_EQ(threads, 1);
  EXPECT_GT(tets, 0);
  EXPECT_GT(median, 0.0);
  EXPECT_LE(median, p99);
  EXPECT_GT(mean, 0.0);
  EXPECT_NEAR(ns, 1e6 * median / tets, 0.01 * ns + 1.0);  // the table's own arithmetic
  double share_sum = 0.0;
  for (int k = 0; k < 4; ++k) {
    std::string share;
    cells >> share;
    ASSERT_FALSE(share.empty());
    EXPECT_EQ(share.back(), '%');
    share_sum += std::stod(share.substr(0, share.size() - 1));
  }
  EXPECT_NEAR(share_sum, 100.0, 2.5);  // four rounded shares of one total

  // One factorization for four steps: the solver says so, and CG refuses it.
  const auto reused = run("bench --fem " + std::string(TACTUS_SOURCE_DIR) + "/scenes/cantilever.toml --steps 8 "
                          "--threads 1 --solver cholesky --factor-reuse 4");
  ASSERT_EQ(reused.exit_code, 0) << reused.err;
  EXPECT_NE(reused.out.find(" cholesky/4 "), std::string::npos) << reused.out;
  const auto refused = run("bench --fem " + std::string(TACTUS_SOURCE_DIR) + "/scenes/cantilever.toml --steps 1 "
                           "--solver cg --factor-reuse 4");
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find("reused only by linearized steps solved by cholesky"), std::string::npos) << refused.err;

  const auto none = run("bench --fem " + std::string(TACTUS_SOURCE_DIR) + "/scenes/nodule.toml --steps 1");
  EXPECT_EQ(none.exit_code, 1);
  EXPECT_NE(none.err.find("no FEM body"), std::string::npos) << none.err;
}

// `tactus run --force-map` on the nodule trainer: a PNG, its legend and the trainee feedback.
TEST_F(Cli, NoduleSceneWritesForceMapAndFeedback) {
  const fs::path scene = fs::path(TACTUS_SOURCE_DIR) / "scenes/nodule.toml";
  const fs::path png = dir_ / "map.png";
  const fs::path json = dir_ / "run.json";
  // The first lines of the scan are enough to draw the map and give feedback.
  const Result r = run("run '" + scene.string() + "' --lockstep --duration 2 --force-map '" + png.string() +
                       "' --json '" + json.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(slurp(png).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_NE(r.out.find("force map"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("viridis from 0 N"), std::string::npos);
  EXPECT_NE(r.out.find("palpation feedback:"), std::string::npos);
  EXPECT_NE(r.out.find("first contact over nodule skin.soft"), std::string::npos);
  EXPECT_NE(slurp(json).find("\"palpation\": {\"coverage\": "), std::string::npos);

  // A PNG that cannot be written is the user's error: exit 1 and a clear line.
  const Result bad = run("run '" + scene.string() + "' --lockstep --duration 0.2 --force-map '" +
                         (dir_ / "missing" / "map.png").string() + "'");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("could not write the PNG file"), std::string::npos) << bad.err;
}

// `tactus bench --plot`: the loops' latency histograms as a PNG, one panel per loop.
TEST_F(Cli, BenchPlotsTheLoopLatencies) {
  const fs::path png = dir_ / "latency.png";
  const Result r = run("bench --lockstep --duration 1 --plot '" + png.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("latency plot: " + png.string()), std::string::npos) << r.out;
  const std::string bytes = slurp(png);
  ASSERT_GE(bytes.size(), 24u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  // IHDR: width and height, big endian. The default scene has three loops (haptic,
  // simulation, interaction): three 170-pixel panels 44 apart under an 80-pixel header,
  // 52 pixels of axis title below.
  auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned>(static_cast<unsigned char>(bytes[at])) << 24) |
           (static_cast<unsigned>(static_cast<unsigned char>(bytes[at + 1])) << 16) |
           (static_cast<unsigned>(static_cast<unsigned char>(bytes[at + 2])) << 8) |
           static_cast<unsigned>(static_cast<unsigned char>(bytes[at + 3]));
  };
  EXPECT_EQ(be32(16), 760u);
  EXPECT_EQ(be32(20), 80u + 3u * (170u + 44u) - 44u + 52u);

  const Result bad = run("bench --lockstep --duration 0.2 --plot '" + (dir_ / "missing" / "p.png").string() + "'");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("could not write the PNG file"), std::string::npos) << bad.err;
}

TEST_F(Cli, FitWritesTheMaterialBlockAndThePlot) {
  // A straight loading curve under a flat punch: the linear law fits it exactly but for the
  // noise-free round-off, so the residual is tiny and E positive.
  std::ofstream(dir_ / "curve.csv") << "depth,force\n0.0001,0.01\n0.0002,0.02\n0.0003,0.03\n0.0004,0.04\n";
  std::ofstream(dir_ / "exp.toml") << "[indenter]\nshape = \"flat_punch\"\nradius = 0.006\n"
                                      "[specimen]\nsize = [0.03, 0.03]\nthickness = 0.01\ncells = [6, 6, 2]\n"
                                      "[material]\nmodel = \"linear\"\npoisson_ratio = 0.45\n"
                                      "[fit]\nfree = [\"young_modulus\"]\n[data]\nfile = \"curve.csv\"\n";
  const auto r = run("fit '" + (dir_ / "exp.toml").string() + "' -o '" + (dir_ / "block.toml").string() +
                     "' --name skin --plot '" + (dir_ / "fit.png").string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("[materials.skin]\nmodel = \"linear\"\nyoung_modulus = "), std::string::npos) << r.out;
  EXPECT_EQ(slurp(dir_ / "block.toml"), r.out);
  EXPECT_NE(r.err.find("residual: RMS"), std::string::npos) << r.err;
  EXPECT_GT(fs::file_size(dir_ / "fit.png"), 1000U);

  // Two experiments, one material: a residual line and a plot each; --plot names one PNG.
  std::ofstream(dir_ / "curve2.csv") << "depth,force\n0.0001,0.02\n0.0002,0.04\n0.0003,0.06\n";
  std::string second = slurp(dir_ / "exp.toml");
  second.replace(second.find("radius = 0.006"), 14, "radius = 0.009");
  second.replace(second.find("curve.csv"), 9, "curve2.csv");
  std::ofstream(dir_ / "exp2.toml") << second;
  const auto joint = run("fit '" + (dir_ / "exp.toml").string() + "' '" + (dir_ / "exp2.toml").string() + "'");
  EXPECT_EQ(joint.exit_code, 0) << joint.err;
  EXPECT_NE(joint.err.find("residual of " + (dir_ / "exp.toml").string()), std::string::npos) << joint.err;
  EXPECT_NE(joint.err.find("residual of " + (dir_ / "exp2.toml").string()), std::string::npos) << joint.err;
  EXPECT_TRUE(fs::exists(dir_ / "exp_fit.png"));
  EXPECT_TRUE(fs::exists(dir_ / "exp2_fit.png"));
  const auto one_plot = run("fit '" + (dir_ / "exp.toml").string() + "' '" + (dir_ / "exp2.toml").string() +
                            "' --plot '" + (dir_ / "x.png").string() + "'");
  EXPECT_EQ(one_plot.exit_code, 1);
  EXPECT_NE(one_plot.err.find("--plot names one PNG"), std::string::npos) << one_plot.err;

  std::ofstream(dir_ / "curve.csv") << "depth,force\n0.0001,0.01\n0.0002,nan\n0.0003,0.03\n";
  const auto bad = run("fit '" + (dir_ / "exp.toml").string() + "'");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_EQ(count_lines(bad.err), 1) << bad.err;
  EXPECT_NE(bad.err.find("curve.csv:3"), std::string::npos) << bad.err;
}

}  // namespace
