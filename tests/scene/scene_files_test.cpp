// Scene files on disk: the bundled scenes, the compiled-in default, relative mesh paths.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

#include "core/error.hpp"
#include "scene/scene.hpp"
#include "scene/scene_text.hpp"

namespace tactus::scene {
namespace {

namespace fs = std::filesystem;

const fs::path kScenes = fs::path(TACTUS_SOURCE_DIR) / "scenes";

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(SceneFiles, DefaultSceneMatchesBundledFile) {
  EXPECT_EQ(std::string(default_scene_text()), read_text(kScenes / "default.toml"));
}

TEST(SceneFiles, EveryBundledSceneLoads) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(kScenes)) {
    if (entry.path().extension() != ".toml") continue;
    SCOPED_TRACE(entry.path().string());
    try {
      const Model m = load_scene(entry.path());
      EXPECT_FALSE(m.bodies.empty());
      EXPECT_FALSE(summarize(m).empty());
    } catch (const InputError& e) {
      ADD_FAILURE() << e.what();
    }
    ++count;
  }
  EXPECT_GE(count, 3);
}

TEST(SceneFiles, AFlattenedScenarioIsItsBaseWithItsOwnKeys) {
  // S2 names femoral.toml as its base: flattened, its text holds no base and parses to the
  // same scene (the patient's bodies from the base, the name and devices its own).
  const fs::path s2 = kScenes / "femoral_s2_palpation.toml";
  const std::string text = read_text(s2);
  ASSERT_NE(text.find("base = \"femoral.toml\""), std::string::npos);
  const std::string flat = format_scene(flatten_scene(text, s2.string()));
  EXPECT_EQ(flat.find("base ="), std::string::npos);
  const Model original = load_scene(s2);
  const Model again = parse_scene(flat, "flat.toml", LoadOptions{kScenes, true, 20'000'000});
  EXPECT_EQ(again.name, original.name);
  ASSERT_EQ(again.bodies.size(), original.bodies.size());
  for (std::size_t i = 0; i < again.bodies.size(); ++i) {
    EXPECT_EQ(again.bodies[i].name, original.bodies[i].name);
    EXPECT_EQ(again.bodies[i].simulation_vertices().size(), original.bodies[i].simulation_vertices().size());
  }
  EXPECT_EQ(again.devices.size(), original.devices.size());
  EXPECT_EQ(again.rates.haptic, original.rates.haptic);
  // Other scenes keep their bodies, devices and algorithms in order too.
  for (const char* name : {"default.toml", "nodule.toml", "fabric.toml", "room.toml", "pulse_demo.toml"}) {
    const Model m = load_scene(kScenes / name);
    const Model flat_m = parse_scene(format_scene(flatten_scene(read_text(kScenes / name), (kScenes / name).string())),
                                     "flat.toml", LoadOptions{kScenes, true, 20'000'000});
    ASSERT_EQ(flat_m.bodies.size(), m.bodies.size()) << name;
    for (std::size_t i = 0; i < m.bodies.size(); ++i) EXPECT_EQ(flat_m.bodies[i].name, m.bodies[i].name) << name;
    ASSERT_EQ(flat_m.devices.size(), m.devices.size()) << name;
    for (std::size_t i = 0; i < m.devices.size(); ++i) EXPECT_EQ(flat_m.devices[i].name, m.devices[i].name) << name;
    ASSERT_EQ(flat_m.algorithms.size(), m.algorithms.size()) << name;
    for (std::size_t i = 0; i < m.algorithms.size(); ++i)
      EXPECT_EQ(flat_m.algorithms[i].name, m.algorithms[i].name) << name;
  }
  // A broken base is the same located error as for parse_scene.
  EXPECT_THROW(flatten_scene("[scene]\nbase = \"missing.toml\"\n", "x.toml"), InputError);
}

TEST(SceneFiles, BundledSceneContents) {
  const Model liver = load_scene(kScenes / "liver.toml");
  const Body& organ = *liver.find_body("liver");
  ASSERT_TRUE(organ.volume.has_value());
  EXPECT_NEAR(organ.surface.bounds().size().x(), 0.22, 0.01);  // liver-sized
  EXPECT_FALSE(organ.fixed.empty());

  const Model patch = load_scene(kScenes / "skin_patch.toml");
  const Body& nodule = *patch.find_body("nodule");
  EXPECT_NE(nodule.mesh_source.find("meshes/nodule.obj"), std::string::npos) << nodule.mesh_source;
  EXPECT_EQ(nodule.surface.triangles.size(), 20u);  // the icosahedron in the file
}

class SceneDir : public ::testing::Test {
 protected:
  void SetUp() override {
    // One folder per process and test: ctest runs the cases as parallel processes, and a
    // shared folder let one case's TearDown delete another's mesh.
    dir_ = fs::temp_directory_path() / ("tactus_scene_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_ / "scenes" / "meshes");
    // A unit tetrahedron's closed surface, outward oriented.
    std::ofstream(dir_ / "scenes" / "meshes" / "tet.obj")
        << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

const char* kSceneWithMesh = R"(
[bodies.stone]
kind = "rigid"
mesh = { file = "meshes/tet.obj", scale = 0.01 }
)";

TEST_F(SceneDir, MeshPathsAreRelativeToTheSceneFile) {
  std::ofstream(dir_ / "scenes" / "stone.toml") << kSceneWithMesh;
  const Model m = load_scene(dir_ / "scenes" / "stone.toml");
  const Body& stone = m.bodies.at(0);
  EXPECT_EQ(stone.surface.vertices.size(), 4u);
  EXPECT_NEAR(stone.surface.signed_volume(), 1e-6 / 6.0, 1e-15);
  EXPECT_EQ(fs::path(stone.mesh_source), dir_ / "scenes" / "meshes" / "tet.obj");

  // The same text parsed as if it lived elsewhere does not find the mesh...
  EXPECT_THROW(parse_scene(kSceneWithMesh, (dir_ / "other.toml").string()), InputError);
  // ...unless told where relative paths start.
  LoadOptions options;
  options.base_dir = dir_ / "scenes";
  EXPECT_NO_THROW(parse_scene(kSceneWithMesh, "memory", options));
}

TEST_F(SceneDir, SurfaceFileIsTetrahedralizedForVolumetricBodies) {
  std::ofstream(dir_ / "scenes" / "soft.toml") << R"(
[materials.m]
young_modulus = 1e4
density = 1000
[bodies.soft]
kind = "tet_mass_spring"
material = "m"
mesh = "meshes/tet.obj"
)";
  const Model m = load_scene(dir_ / "scenes" / "soft.toml");
  const Body& b = m.bodies.at(0);
  ASSERT_TRUE(b.volume.has_value());
  EXPECT_NEAR(b.volume->volume(), 1.0 / 6.0, 1e-9);
}

TEST_F(SceneDir, MissingSceneFile) {
  try {
    load_scene(dir_ / "nope.toml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nope.toml: cannot open file for reading"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tactus::scene

namespace tactus::scene {
namespace {

// The full example in docs/scene-format.md stays valid.
TEST(SceneFiles, DocumentedExampleParses) {
  const std::string doc = read_text(fs::path(TACTUS_SOURCE_DIR) / "docs" / "scene-format.md");
  const std::size_t heading = doc.find("## Full example");
  ASSERT_NE(heading, std::string::npos);
  const std::size_t begin = doc.find("```toml\n", heading);
  ASSERT_NE(begin, std::string::npos);
  const std::size_t end = doc.find("```", begin + 8);
  LoadOptions options;
  options.base_dir = kScenes;  // its mesh file is the bundled nodule
  const Model m = parse_scene(doc.substr(begin + 8, end - begin - 8), "scene-format.md", options);
  EXPECT_EQ(m.name, "palpation");
  EXPECT_EQ(m.bodies.size(), 2u);
}

}  // namespace
}  // namespace tactus::scene
