// Regions of one FEM body (bodies.<name>.regions): the tagged tetrahedra of its mesh (a label
// image's labels, Gmsh physical groups) each take their own material; and every way the table
// can be wrong, located.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "core/error.hpp"
#include "mesh/generators.hpp"
#include "mesh/io/mesh_io.hpp"
#include "scene/scene.hpp"

namespace tactus::scene {
namespace {

/// A 10 × 2 × 2 cm bar meshed with its near half tagged 1 and its far half 2, and a scene
/// file beside it that names it.
struct RegionScene {
  RegionScene() : dir(std::filesystem::temp_directory_path() / ("tactus_regions_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(dir);
    mesh::TetMesh m = mesh::box_volume(Vec3(0.1, 0.02, 0.02), 6, 2, 2);
    for (const auto& t : m.tets) {
      double x = 0.0;
      for (const auto v : t) x += 0.25 * m.vertices[static_cast<std::size_t>(v)].x();
      m.tet_regions.push_back(x < 0.0 ? 1 : 2);
    }
    mesh::write_mesh(dir / "bar.vtu", m);
    plain = m;
    plain.tet_regions.clear();
    mesh::write_mesh(dir / "plain.vtu", plain);
  }
  ~RegionScene() { std::filesystem::remove_all(dir); }
  [[nodiscard]] std::string text(const std::string& regions, const std::string& mesh = "bar.vtu",
                                 const std::string& kind = "fem") const {
    return R"([materials.muscle]
young_modulus = 1e4
poisson_ratio = 0.45
density = 1060
[materials.bone]
young_modulus = 1e7
poisson_ratio = 0.3
density = 1900
[materials.damped_bone]
young_modulus = 1e7
density = 1900
damping = { rayleigh_beta = 0.01 }
[bodies.leg]
kind = ")" + kind + R"("
material = "muscle"
mesh = ")" + mesh + R"("
[bodies.leg.regions]
)" + regions;
  }
  [[nodiscard]] Model load(const std::string& scene) const { return parse_scene(scene, (dir / "scene.toml").string()); }
  [[nodiscard]] std::string error(const std::string& scene) const {
    try {
      (void)load(scene);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(no error)";
  }
  std::filesystem::path dir;
  mesh::TetMesh plain;
};

TEST(RegionScene, TaggedTetrahedraTakeTheirRegionsMaterial) {
  const RegionScene s;
  const Model m = s.load(s.text("2 = \"bone\"\n"));
  const Body& leg = m.bodies.at(0);
  ASSERT_EQ(leg.region_materials.size(), 1u);
  EXPECT_EQ(leg.region_materials[0].first, 2);
  EXPECT_EQ(m.materials.at(leg.region_materials[0].second).name, "bone");
  ASSERT_TRUE(leg.volume.has_value());
  EXPECT_EQ(leg.volume->tet_regions.size(), leg.volume->tets.size());  // the tags came through the file
}

TEST(RegionScene, EveryWrongTableIsLocated) {
  const RegionScene s;
  const auto has = [](const std::string& message, const std::string& part) {
    return message.find(part) != std::string::npos;
  };
  std::string e = s.error(s.text("7 = \"bone\"\n"));
  EXPECT_TRUE(has(e, "bodies.leg.regions.7") && has(e, "has no region 7 (its regions: 1, 2)")) << e;
  e = s.error(s.text("skin = \"bone\"\n"));
  EXPECT_TRUE(has(e, "bodies.leg.regions.skin") && has(e, "integer tag")) << e;
  e = s.error(s.text("2 = \"marrow\"\n"));
  EXPECT_TRUE(has(e, "bodies.leg.regions.2") && has(e, "marrow")) << e;
  e = s.error(s.text("2 = \"damped_bone\"\n"));
  EXPECT_TRUE(has(e, "bodies.leg.regions.2") && has(e, "damping")) << e;
  e = s.error(s.text("2 = \"bone\"\n", "plain.vtu"));
  EXPECT_TRUE(has(e, "bodies.leg.regions") && has(e, "tags no regions")) << e;
  e = s.error(s.text("2 = \"bone\"\n", "bar.vtu", "tet_mass_spring"));
  EXPECT_TRUE(has(e, "bodies.leg.regions") && has(e, "takes one material")) << e;
}

}  // namespace
}  // namespace tactus::scene
