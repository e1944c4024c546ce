// Every way a scene can be wrong gives an InputError at the right file:line:column with
// the key path in the message.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "scene/scene.hpp"

namespace tactus::scene {
namespace {

// A valid scene; tests replace one line to break it. Line numbers below refer to it.
const std::string kBase = R"(# line 1
[materials.skin]
young_modulus = 5e4
poisson_ratio = 0.45
density = 1100

[bodies.block]
kind = "fem"
material = "skin"
mesh = { generator = "box", size = [0.1, 0.1, 0.05], cells = 2 }
time_step = 0.01
[[bodies.block.fixed]]
name = "base"
side = "z_min"

[devices.hand]
type = "scripted"
trajectory = { type = "press", position = [0, 0, 0.04], depth = 0.01 }

[tools.finger]
type = "sphere"
device = "hand"
mass = 0.01

[algorithms.touch]
type = "proxy"
tool = "finger"
bodies = ["block"]

[rates]
haptic = 1000
)";

/// kBase with line `line` (1-based) replaced by `text`.
std::string with_line(int line, const std::string& text) {
  std::string out;
  std::size_t start = 0;
  for (int i = 1;; ++i) {
    const std::size_t end = kBase.find('\n', start);
    if (end == std::string::npos) break;
    out += (i == line ? text : kBase.substr(start, end - start)) + "\n";
    start = end + 1;
  }
  return out;
}

std::string error_of(const std::string& text, const LoadOptions& options = {}) {
  try {
    parse_scene(text, "dir/x.toml", options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SceneErrors, BaseSceneIsValid) {
  EXPECT_EQ(error_of(kBase), "(no error)");
}

TEST(SceneErrors, NestingTooDeepIsRefusedBeforeParsing) {
  // A hundred thousand nested arrays overflowed the TOML parser's stack (SIGSEGV); the depth
  // is now bounded before parsing. Brackets inside strings and comments do not count.
  std::string deep = "a = ";  // appended, not concatenated: GCC 12 warns falsely on the latter
  deep.append(100000, '[');
  deep.append(100000, ']');
  EXPECT_EQ(error_of(deep), "dir/x.toml:1: arrays and tables nested more than 128 levels deep");
  std::string tables = "[scene]\nname = \"n\"\nx = ";
  for (int i = 0; i < 200; ++i) tables += "{ y = ";
  tables += "1";
  tables.append(200, '}');
  EXPECT_EQ(error_of(tables), "dir/x.toml:3: arrays and tables nested more than 128 levels deep");
  std::string comment = "# ";
  comment.append(300, '[');
  std::string quoted = with_line(1, comment);
  quoted += "[materials.z]\nmodel = \"";
  quoted.append(300, '{');
  quoted += "\"\n";
  EXPECT_EQ(error_of(quoted).find("nested"), std::string::npos) << error_of(quoted);
}

TEST(SceneErrors, PoissonRatioOutOfRange) {
  EXPECT_EQ(error_of(with_line(4, "poisson_ratio = 0.5")),
            "dir/x.toml:4:17: materials.skin.poisson_ratio: 0.5 is out of range: must be in (-1, 0.5)");
  EXPECT_EQ(error_of(with_line(4, "poisson_ratio = -1")),
            "dir/x.toml:4:17: materials.skin.poisson_ratio: -1 is out of range: must be in (-1, 0.5)");
}

TEST(SceneErrors, DeviceDampingMustBePositive) {
  EXPECT_EQ(error_of(with_line(17, "type = \"scripted\"\nmax_damping = 0")),
            "dir/x.toml:18:15: devices.hand.max_damping: 0 is out of range: must be > 0");
  const Model m = parse_scene(with_line(17, "type = \"scripted\"\nmax_damping = 40"), "dir/x.toml");
  EXPECT_EQ(m.devices.at(0).max_damping, 40.0);
}

TEST(SceneErrors, RasterApproachMustNotBeNegative) {
  const std::string raster = "trajectory = { type = \"raster\", min = [0, 0], max = [0.01, 0.01], z = 0.01, approach = ";
  EXPECT_EQ(error_of(with_line(18, raster + "-0.002 }")),
            "dir/x.toml:18:88: devices.hand.trajectory.approach: -0.002 is out of range: must be >= 0");
  const Model m = parse_scene(with_line(18, raster + "0.005 }"), "dir/x.toml");
  EXPECT_EQ(std::get<haptics::RasterPath>(std::get<ScriptedDevice>(m.devices.at(0).source).trajectory).approach,
            0.005);
}

TEST(SceneErrors, UnknownKeySuggestsTheClosest) {
  EXPECT_EQ(error_of(with_line(3, "youngs_modulus = 5e4")),
            "dir/x.toml:3:1: materials.skin.youngs_modulus: unknown key 'youngs_modulus'; did you mean "
            "'young_modulus'?");
  // A misspelt optional key: reported when the table is finished.
  EXPECT_EQ(error_of(with_line(11, "time_stepp = 0.01")),
            "dir/x.toml:11:1: bodies.block.time_stepp: unknown key 'time_stepp'; did you mean 'time_step'?");
  // Deep inside an inline table.
  EXPECT_EQ(error_of(with_line(18, "trajectory = { type = \"press\", positon = [0, 0, 0.04], depth = 0.01 }")),
            "dir/x.toml:18:32: devices.hand.trajectory.positon: unknown key 'positon'; did you mean 'position'?");
}

TEST(SceneErrors, UnknownTopLevelSection) {
  const std::string e = error_of(kBase + "[renderer]\nfps = 60\n");
  EXPECT_NE(e.find("dir/x.toml:32:"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key 'renderer'"), std::string::npos) << e;
}

TEST(SceneErrors, WrongType) {
  EXPECT_EQ(error_of(with_line(5, "density = \"heavy\"")),
            "dir/x.toml:5:11: materials.skin.density: expected a number, got a string");
  EXPECT_EQ(error_of(with_line(8, "kind = 3")), "dir/x.toml:8:8: bodies.block.kind: expected a string, got an integer");
  EXPECT_EQ(error_of(with_line(10, "mesh = { generator = \"box\", size = [0.1, \"a\", 0.05] }")),
            "dir/x.toml:10:42: bodies.block.mesh.size[1]: expected a number, got a string");
  EXPECT_EQ(error_of(with_line(10, "mesh = { generator = \"box\", size = [0.1, 0.05] }")),
            "dir/x.toml:10:36: bodies.block.mesh.size: expected an array of 3 numbers, got 2 elements");
}

TEST(SceneErrors, OutOfRangeValues) {
  EXPECT_EQ(error_of(with_line(3, "young_modulus = -5")),
            "dir/x.toml:3:17: materials.skin.young_modulus: -5 is out of range: must be > 0");
  EXPECT_EQ(error_of(with_line(5, "density = 0")),
            "dir/x.toml:5:11: materials.skin.density: 0 is out of range: must be > 0");
  EXPECT_EQ(error_of(with_line(23, "mass = 0")), "dir/x.toml:23:8: tools.finger.mass: 0 is out of range: must be > 0");
  EXPECT_EQ(error_of(with_line(31, "haptic = 50")),
            "dir/x.toml:31:10: rates.haptic: 50 is out of range: must be in [100, 10000]");
  EXPECT_EQ(error_of(with_line(11, "time_step = 0")),
            "dir/x.toml:11:13: bodies.block.time_step: 0 is out of range: must be in (0, 1]");
  EXPECT_EQ(error_of(kBase + "simulation = 2000\n"),
            "dir/x.toml:32:14: rates.simulation: 2000 is out of range: must be in [1, 1000]");
  EXPECT_EQ(error_of(kBase + "catch_up = 0.5\n"),
            "dir/x.toml:32:12: rates.catch_up: 0.5 is out of range: must be in [1, 10]");
  EXPECT_EQ(error_of(with_line(3, "young_modulus = nan")),
            "dir/x.toml:3:17: materials.skin.young_modulus: expected a finite number, got nan");
}

TEST(SceneErrors, UnknownEnumValue) {
  EXPECT_EQ(error_of(with_line(8, "kind = \"femm\"")),
            "dir/x.toml:8:8: bodies.block.kind: unknown value 'femm'; did you mean 'fem'? (expected one of: "
            "surface_mass_spring, tet_mass_spring, fem, rigid, embedded, cloth, cspace)");
}

TEST(SceneErrors, UndefinedReferences) {
  EXPECT_EQ(error_of(with_line(9, "material = \"skn\"")),
            "dir/x.toml:9:12: bodies.block.material: undefined material 'skn'; did you mean 'skin'?");
  EXPECT_EQ(error_of(with_line(22, "device = \"foot\"")),
            "dir/x.toml:22:10: tools.finger.device: undefined device 'foot'");
  EXPECT_EQ(error_of(with_line(27, "tool = \"fingr\"")),
            "dir/x.toml:27:8: algorithms.touch.tool: undefined tool 'fingr'; did you mean 'finger'?");
  EXPECT_EQ(error_of(with_line(28, "bodies = [\"block\", \"liver\"]")),
            "dir/x.toml:28:10: algorithms.touch.bodies: undefined body 'liver'");
}

TEST(SceneErrors, MissingRequiredKey) {
  EXPECT_EQ(error_of(with_line(5, "")), "dir/x.toml:2:1: materials.skin: missing required key 'density' (a number)");
}

TEST(SceneErrors, DuplicateNames) {
  // Two tables of the same name are already a TOML error; it keeps its location.
  const std::string e = error_of(kBase + "[materials.skin]\ndensity = 1\n");
  EXPECT_NE(e.find("dir/x.toml:32:"), std::string::npos) << e;
  EXPECT_EQ(error_of(kBase + "[[bodies.block.fixed]]\nname = \"base\"\nside = \"z_max\"\n"),
            "dir/x.toml:33:8: bodies.block.fixed[1].name: duplicate fixed region name 'base'");
  // A device drives one tool only.
  EXPECT_EQ(error_of(kBase + "[tools.other]\ntype = \"needle\"\ndevice = \"hand\"\n"),
            "dir/x.toml:34:10: tools.other.device: device 'hand' already drives tool 'finger'");
}

TEST(SceneErrors, TomlSyntaxError) {
  const std::string e = error_of(with_line(5, "density = = 3"));
  EXPECT_EQ(e.rfind("dir/x.toml:5:", 0), 0u) << e;
}

TEST(SceneErrors, FixedRegionSelectingNothing) {
  EXPECT_EQ(error_of(with_line(14, "box = { min = [1, 1, 1], max = [2, 2, 2] }")),
            "dir/x.toml:12:1: bodies.block.fixed[0]: fixed region 'base' (box) selects no node");
  EXPECT_EQ(error_of(with_line(14, "nodes = [0, 1, 99999]")),
            "dir/x.toml:14:16: bodies.block.fixed[0].nodes[2]: 99999 is out of range: must be in [0, 26]");
}

TEST(SceneErrors, MissingMeshFile) {
  const std::string e = error_of(with_line(10, "mesh = \"meshes/none.obj\""));
  EXPECT_EQ(e, "dir/x.toml:10:8: bodies.block.mesh: file not found: 'dir/meshes/none.obj'");
}

TEST(SceneErrors, MeshThatFailsToLoad) {
  const auto dir = std::filesystem::temp_directory_path() / "tactus_scene_bad_mesh";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "bad.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n";
  std::ofstream(dir / "scene.toml") << with_line(10, "mesh = \"bad.obj\"");
  try {
    load_scene(dir / "scene.toml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("scene.toml:10:8: bodies.block.mesh: cannot load mesh: "), std::string::npos) << what;
    // The mesh reader's own location survives inside the message.
    EXPECT_NE(what.find("bad.obj:4"), std::string::npos) << what;
  }
  std::filesystem::remove_all(dir);
}

TEST(SceneErrors, FileAccessCanBeDisabled) {
  LoadOptions no_files;
  no_files.allow_file_access = false;
  EXPECT_EQ(error_of(with_line(10, "mesh = \"x.obj\""), no_files),
            "dir/x.toml:10:8: bodies.block.mesh: file access is disabled; cannot read 'x.obj'");
}

TEST(SceneErrors, GeneratorBudget) {
  LoadOptions small;
  small.max_generated_cells = 1000;
  EXPECT_EQ(error_of(with_line(10, "mesh = { generator = \"box\", size = [1, 1, 1], cells = 20 }"), small),
            "dir/x.toml:10:55: bodies.block.mesh.cells: asks for about 8000 cells; the limit is 1000");
}

TEST(SceneErrors, MaterialForms) {
  // Two ways of giving the elastic constants at once.
  const std::string e = error_of(with_line(2, "[materials.skin]\nmodel = \"neo_hookean\"\nmu = 1e4\nkappa = 1e5"));
  EXPECT_NE(e.find("materials.skin: give the elastic constants one way only"), std::string::npos) << e;
  // Prony weights that leave no long-term modulus.
  const std::string p = error_of(kBase + "[materials.skin.viscoelastic]\nmodel = \"prony\"\n"
                                         "terms = [{ g = 0.6, tau = 0.1 }, { g = 0.5, tau = 1.0 }]\n");
  EXPECT_NE(p.find("dir/x.toml:34:9: materials.skin.viscoelastic.terms: the g values sum to 1.1"), std::string::npos)
      << p;
}

TEST(SceneErrors, BadWaypoints) {
  const std::string e = error_of(with_line(
      18, "trajectory = { type = \"waypoints\", points = [{ time = 1, position = [0, 0, 0] }, "
          "{ time = 0.5, position = [0, 0, 0.01] }] }"));
  EXPECT_NE(e.find("devices.hand.trajectory.points[1].time: waypoint times must increase strictly"),
            std::string::npos)
      << e;
}

}  // namespace
}  // namespace tactus::scene

namespace tactus::scene {
namespace {

TEST(SceneErrors, RealtimeAndWorkspaceRotation) {
  EXPECT_NE(error_of(kBase + "[realtime]\npriority = 120\n").find("realtime.priority: 120 is out of range"),
            std::string::npos);
  // Spinning longer than a haptic period (1 ms here) makes no sense.
  EXPECT_NE(error_of(kBase + "[realtime]\nspin = 0.002\n").find("realtime.spin"), std::string::npos);
  EXPECT_NE(error_of(kBase + "[realtime]\ndedicated = true\n").find("realtime.dedicated: unknown key"),
            std::string::npos);
  EXPECT_NE(error_of(kBase + "[devices.other]\ntype = \"scripted\"\ntrajectory = { type = \"circle\", center = [0, 0, 0], radius = 0.01 }\n"
                             "rotation = { axis = [0, 0, 0], degrees = 90 }\n")
                .find("rotation axis must not be zero"),
            std::string::npos);
}

}  // namespace
}  // namespace tactus::scene
