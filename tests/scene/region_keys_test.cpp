// Regions of one FEM body (bodies.<name>.regions): the tagged tetrahedra of its mesh (a label
// image's labels, Gmsh physical groups) each take their own material; and every way the table
// can be wrong, located.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <fstream>
#include <string>

#include <unistd.h>

#include "core/error.hpp"
#include "imaging/label_image.hpp"
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

// A region's surface as an embedded layer (a fascia between two tissues) and the nodes of a
// region held (the tissue on a bone).
TEST(RegionScene, LayersAreCutFromTheHostsRegionsAndARegionCanBeHeld) {
  const RegionScene s;
  const Model m = s.load(s.text("2 = \"bone\"\n") + R"(
[[bodies.leg.fixed]]
name = "on_bone"
region = 2
[bodies.wall]
kind = "embedded"
host = "leg"
mesh = { region = 1, facing = 2 }
[bodies.near_half]
kind = "embedded"
host = "leg"
mesh = { region = 1 }
[bodies.skin]
kind = "embedded"
host = "leg"
mesh = { region = [1, 2], facing = 0 }
)");
  const Body& leg = *m.find_body("leg");
  // The far half's nodes: x ≥ 0 on the 6 × 2 × 2 lattice, 4 columns of 3 × 3.
  ASSERT_EQ(leg.fixed.size(), 1u);
  EXPECT_EQ(leg.fixed[0].nodes.size(), 36u);
  for (const auto n : leg.fixed[0].nodes) EXPECT_GE(leg.volume->vertices[static_cast<std::size_t>(n)].x(), -1e-12);
  // The wall between the halves: the 2 × 2 cm square at x = 0, facing out of region 1 (+x).
  const Body& wall = *m.find_body("wall");
  EXPECT_NEAR(wall.surface.area(), 4e-4, 1e-15);
  for (std::size_t f = 0; f < wall.surface.triangles.size(); ++f) EXPECT_GT(wall.surface.face_normal(f).x(), 0.999);
  EXPECT_EQ(wall.mesh_source, "body 'leg', region 1 facing 2");
  // Carried exactly: each vertex is a node of the host.
  EXPECT_LT(wall.host_mapping->max_outside_distance(), 1e-15);
  // Region 1's closed boundary (facing everything else by default) and the whole outside.
  EXPECT_NEAR(m.find_body("near_half")->surface.signed_volume(), 0.05 * 0.02 * 0.02, 1e-15);
  EXPECT_NEAR(m.find_body("skin")->surface.signed_volume(), 0.1 * 0.02 * 0.02, 1e-15);
}

TEST(RegionScene, EveryWrongRegionSurfaceOrHeldRegionIsLocated) {
  const RegionScene s;
  const auto error = [&](const std::string& extra) { return s.error(s.text("2 = \"bone\"\n") + extra); };
  const auto has = [](const std::string& message, const std::string& part) {
    return message.find(part) != std::string::npos;
  };
  const std::string layer = "[bodies.layer]\nkind = \"embedded\"\nhost = \"leg\"\n";
  std::string e = error(layer + "mesh = { region = 7 }\n");
  EXPECT_TRUE(has(e, "bodies.layer.mesh.region") && has(e, "has no region 7 (its regions: 1, 2)")) << e;
  e = error(layer + "mesh = { region = 1, facing = [1, 2] }\n");
  EXPECT_TRUE(has(e, "bodies.layer.mesh.facing") && has(e, "region 1 is in both")) << e;
  e = error(layer + "mesh = { region = 1, facing = 9 }\n");
  EXPECT_TRUE(has(e, "bodies.layer.mesh.facing") && has(e, "no region 9")) << e;
  e = error(layer + "mesh = { region = 1, translate = [0.0, 0.0, 0.01] }\n");
  EXPECT_TRUE(has(e, "bodies.layer.mesh") && has(e, "takes no scale, rotate or translate")) << e;
  e = error(layer + "mesh = { region = 1, file = \"bar.vtu\" }\n");
  EXPECT_TRUE(has(e, "bodies.layer.mesh") && has(e, "not both 'file' and 'region'")) << e;
  e = error("[bodies.lump]\nkind = \"rigid\"\nmesh = { region = 1 }\n");
  EXPECT_TRUE(has(e, "bodies.lump.mesh.region") && has(e, "for 'embedded' bodies and 'mapped' surfaces")) << e;
  e = error("[[bodies.leg.fixed]]\nregion = 5\n");
  EXPECT_TRUE(has(e, "bodies.leg.fixed[0].region") && has(e, "has no region 5")) << e;
  e = error("[[bodies.leg.fixed]]\nregion = 1\nside = \"x_min\"\n");
  EXPECT_TRUE(has(e, "bodies.leg.fixed[0]") && has(e, "only one node selector")) << e;
  e = s.error("[materials.muscle]\nyoung_modulus = 1e4\ndensity = 1060\n[bodies.leg]\nkind = \"fem\"\n"
              "material = \"muscle\"\nmesh = \"plain.vtu\"\n[[bodies.leg.fixed]]\nregion = 1\n");
  EXPECT_TRUE(has(e, "bodies.leg.fixed[0].region") && has(e, "tags no regions")) << e;
}

/// A 24 × 8 × 8 mm bar of 1 mm voxels labelled 1, 2, 3 along x (8 mm cubes), as NIfTI.
void write_three_labels(const std::filesystem::path& path) {
  imaging::LabelImage image;
  image.size = {24, 8, 8};
  image.spacing = Vec3::Constant(1e-3);
  image.origin = Vec3::Constant(0.5e-3);
  for (std::size_t k = 0; k < 8; ++k)
    for (std::size_t j = 0; j < 8; ++j)
      for (std::size_t i = 0; i < 24; ++i) image.labels.push_back(static_cast<std::int32_t>(1 + i / 8));
  imaging::write_nifti(path, image);
}

TEST(RegionScene, ALabelImageIsMeshedByLabelAtLoad) {
  const RegionScene s;
  write_three_labels(s.dir / "bar.nii.gz");
  const std::string scene = R"([materials.muscle]
young_modulus = 1e4
density = 1060
[bodies.bar]
kind = "fem"
material = "muscle"
mesh = { labels = "bar.nii.gz", cell_size = 0.003, cell_size_label = { 2 = 0.002 } }
[bodies.middle]
kind = "embedded"
host = "bar"
mesh = { region = 2 }
)";
  const Model m = s.load(scene);
  const Body& bar = *m.find_body("bar");
  ASSERT_TRUE(bar.volume.has_value());
  std::map<int, double> volume;
  for (std::size_t t = 0; t < bar.volume->tets.size(); ++t) volume[bar.volume->tet_regions[t]] += bar.volume->tet_volume(t);
  ASSERT_EQ(volume.size(), 3u);
  // Each label is an 8 mm cube. The outer edges are rounded by about a voxel (CGAL 5.5 has no
  // feature lines, docs/label-images.md): 12 edges × (1 − π/4) voxel² × 8 voxels take about
  // 4 % of a cube's 512 voxels, more at the ends, which have more outer edges.
  for (const auto& [label, v] : volume) EXPECT_NEAR(v, 512e-9, 0.1 * 512e-9) << "label " << label;
  EXPECT_NEAR(m.find_body("middle")->surface.signed_volume(), volume.at(2), 1e-15);
  EXPECT_NE(bar.mesh_source.find("meshed by label"), std::string::npos);

  const auto has = [](const std::string& message, const std::string& part) {
    return message.find(part) != std::string::npos;
  };
  std::string e = s.error(scene + "[bodies.apart]\nkind = \"embedded\"\nhost = \"bar\"\n"
                                  "mesh = { region = 1, facing = 3 }\n");
  EXPECT_TRUE(has(e, "bodies.apart.mesh.region") && has(e, "region 1 facing 3: the regions do not meet")) << e;
  // One body of `kind` whose mesh table is `mesh`.
  const auto body = [](const std::string& kind, const std::string& mesh) {
    return "[materials.muscle]\nyoung_modulus = 1e4\ndensity = 1060\n[bodies.bar]\nkind = \"" + kind +
           "\"\nmaterial = \"muscle\"\nmesh = " + mesh + "\n";
  };
  e = s.error(body("fem", "{ labels = \"bar.nii.gz\", cell_size = 1e-6 }"));
  EXPECT_TRUE(has(e, "bodies.bar.mesh.cell_size") && has(e, "the limit is")) << e;
  e = s.error(body("fem", "{ labels = \"bar.nii.gz\", cell_size = 0.002, cell_size_label = { 9 = 0.001, skin = 0.001 } }"));
  EXPECT_TRUE(has(e, "bodies.bar.mesh.cell_size_label.skin") && has(e, "nonzero integer")) << e;
  e = s.error(body("fem", "{ labels = \"bar.nii.gz\", cell_size = 0.002, facet_distance_label = { 7 = 0.001 } }"));
  EXPECT_TRUE(has(e, "bodies.bar.mesh.labels") && has(e, "a facet distance is given for label 7")) << e;
  e = s.error(body("fem", "{ labels = \"missing.nii.gz\", cell_size = 0.002 }"));
  EXPECT_TRUE(has(e, "bodies.bar.mesh.labels") && has(e, "missing.nii.gz")) << e;
  e = s.error(body("surface_mass_spring", "{ labels = \"bar.nii.gz\", cell_size = 0.002 }"));
  EXPECT_TRUE(has(e, "bodies.bar.mesh.labels") && has(e, "for 'fem' and 'tet_mass_spring' bodies")) << e;
}

}  // namespace
}  // namespace tactus::scene
