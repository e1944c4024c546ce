// Cloth bodies in scenes: a fabric from the database or from the scene's own curves, the
// sheet and its clamp; and every way they can be wrong, located.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "scene/scene.hpp"

namespace tactus::scene {
namespace {

// Line numbers below refer to this scene.
const std::string kCloth = R"([bodies.fabric]
kind = "cloth"
fabric = "denim"
size = [0.2, 0.1]
spacing = 0.01
origin = [0.0, 0.0, 0.3]
warp_axis = [0.0, 0.0, -1.0]
weft_axis = [1.0, 0.0, 0.0]
clamp = 2
)";

std::string with_line(const std::string& base, int line, const std::string& text) {
  std::string out;
  std::size_t start = 0;
  for (int i = 1;; ++i) {
    const std::size_t end = base.find('\n', start);
    if (end == std::string::npos) break;
    out += (i == line ? text : base.substr(start, end - start)) + "\n";
    start = end + 1;
  }
  return out;
}

std::string cloth_error(const std::string& text) {
  try {
    parse_scene(text, std::string(TACTUS_SOURCE_DIR) + "/scenes/x.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ClothScene, DatabaseFabricOnAClampedSheet) {
  const Model m = parse_scene(kCloth, std::string(TACTUS_SOURCE_DIR) + "/scenes/x.toml");
  ASSERT_EQ(m.bodies.size(), 1u);
  const Body& b = m.bodies[0];
  EXPECT_EQ(b.kind, BodyKind::cloth);
  ASSERT_TRUE(b.cloth);
  EXPECT_EQ(b.cloth->nodes_u, 21);
  EXPECT_EQ(b.cloth->nodes_v, 11);
  EXPECT_EQ(b.surface.vertices.size(), 21u * 11u);
  ASSERT_EQ(b.fixed.size(), 1u);
  EXPECT_EQ(b.fixed[0].nodes.size(), 22u);  // two rows of 11 along the weft
  // The clamp's first row is the sheet's top edge, at the origin's height.
  for (auto n : b.fixed[0].nodes) EXPECT_GE(b.surface.vertices[static_cast<std::size_t>(n)].z(), 0.29 - 1e-12);
  // Denim's KES weight W (mg/cm²) is the areal density ×100 (kg/m²).
  EXPECT_GT(b.cloth->model->material().areal_density, 0.0);
  EXPECT_FALSE(b.cloth->model->yarns().empty());
  EXPECT_NE(summarize(m).find("fabric: 'denim'"), std::string::npos) << summarize(m);
}

TEST(ClothScene, OwnCurvesInsteadOfADatabaseKey) {
  const std::string text = with_line(kCloth, 3, R"([bodies.fabric.curves]
areal_density = 0.2
warp = { strain = [0.0, 0.02, 0.05], tension = [0.0, 40.0, 300.0] }
weft = { strain = [0.0, 0.03, 0.06], tension = [0.0, 20.0, 200.0] }
shear = { angle = [0.0, 0.2], force = [0.0, 2.0] }
bend_warp = { curvature = [0.0, 100.0], moment = [0.0, 1e-3] }
bend_weft = { curvature = [0.0, 100.0], moment = [0.0, 5e-4] }
[bodies.fabric.geometry_follows]
)");
  // The curves table closes the body's table: the remaining keys belong to a later table.
  const std::string fixed = text.substr(0, text.find("[bodies.fabric.geometry_follows]"));
  std::string body = "[bodies.fabric]\nkind = \"cloth\"\nsize = [0.2, 0.1]\nspacing = 0.01\n";
  body += fixed.substr(fixed.find("[bodies.fabric.curves]"));
  const Model m = parse_scene(body, "x.toml");
  ASSERT_TRUE(m.bodies[0].cloth);
  EXPECT_DOUBLE_EQ(m.bodies[0].cloth->model->material().areal_density, 0.2);
  EXPECT_DOUBLE_EQ(m.bodies[0].cloth->model->material().warp.value(0.02), 40.0);
  EXPECT_TRUE(m.bodies[0].cloth->fabric.empty());
}

TEST(ClothScene, ShearHysteresisTakesTheFabrics2HGOnlyWhenAsked) {
  const std::string where = std::string(TACTUS_SOURCE_DIR) + "/scenes/x.toml";
  EXPECT_EQ(parse_scene(kCloth, where).bodies[0].cloth->model->material().shear_friction, 0.0);
  const Model m = parse_scene(kCloth + "shear_hysteresis = true\n", where);
  // Denim's 2HG is 3.575 gf/cm in warp and weft (data/fabrics.toml): H = 2HG/2 in N/m.
  EXPECT_NEAR(m.bodies[0].cloth->model->material().shear_friction, 0.5 * 3.575 * 0.980665, 1e-12);
  // ... and 2HG5 (5.938 gf/cm) at 5°.
  EXPECT_NEAR(m.bodies[0].cloth->model->material().shear_friction_5, 0.5 * 5.938 * 0.980665, 1e-12);
  EXPECT_EQ(m.bodies[0].cloth->model->internal_size(), m.bodies[0].cloth->model->triangles().size());

  // The scene's own curves give it, or the key is an error naming the missing value.
  const std::string own = "[bodies.fabric]\nkind = \"cloth\"\nsize = [0.2, 0.1]\nspacing = 0.01\n"
                          "shear_hysteresis = true\n"
                          "[bodies.fabric.curves]\nareal_density = 0.2\n"
                          "warp = { strain = [0.0, 0.02], tension = [0.0, 40.0] }\n"
                          "weft = { strain = [0.0, 0.03], tension = [0.0, 20.0] }\n"
                          "shear = { angle = [0.0, 0.2], force = [0.0, 2.0] }\n"
                          "bend_warp = { curvature = [0.0, 100.0], moment = [0.0, 1e-3] }\n"
                          "bend_weft = { curvature = [0.0, 100.0], moment = [0.0, 5e-4] }\n";
  const std::string missing = cloth_error(own);
  EXPECT_NE(missing.find(":5:20: bodies.fabric.shear_hysteresis: the scene's own curves give no `shear_friction`"),
            std::string::npos)
      << missing;
  const Model given = parse_scene(own + "shear_friction = 1.5\nshear_friction_5 = 2.5\n", "x.toml");
  EXPECT_DOUBLE_EQ(given.bodies[0].cloth->model->material().shear_friction, 1.5);
  EXPECT_DOUBLE_EQ(given.bodies[0].cloth->model->material().shear_friction_5, 2.5);
  const std::string alone = cloth_error(own + "shear_friction_5 = 2.5\n");
  EXPECT_NE(alone.find("bodies.fabric.curves.shear_friction_5: the friction at 5° needs `shear_friction`"),
            std::string::npos)
      << alone;
}

TEST(ClothScene, BadFabricsAreLocated) {
  EXPECT_EQ(cloth_error(with_line(kCloth, 3, "fabric = \"dennim\"")).find(":3:10: bodies.fabric.fabric: no fabric 'dennim'"),
            cloth_error(with_line(kCloth, 3, "fabric = \"dennim\"")).find(":3:10:"));
  EXPECT_NE(cloth_error(with_line(kCloth, 3, "fabric = \"dennim\"")).find("did you mean 'denim'?"), std::string::npos);
  EXPECT_NE(cloth_error(with_line(kCloth, 9, "clamp = 1")).find(":9:9: bodies.fabric.clamp: a clamp holds at least 2"),
            std::string::npos);
  EXPECT_NE(cloth_error(with_line(kCloth, 8, "weft_axis = [0.0, 0.5, -1.0]")).find("perpendicular"), std::string::npos);
  EXPECT_NE(cloth_error(with_line(kCloth, 5, "spacing = 0.2")).find("bodies.fabric.spacing"), std::string::npos);
  EXPECT_NE(cloth_error(with_line(kCloth, 2, "kind = \"cloth\"\nmaterial = \"skin\"")).find("takes its properties from"),
            std::string::npos);
  // A factorization kept over steps lets the fabric slip through the fingers: refused.
  const std::string reused =
      cloth_error(with_line(kCloth, 9, "clamp = 2\nsolver = \"cholesky\"\nfactor_reuse_steps = 2"));
  EXPECT_NE(reused.find(":11:22: bodies.fabric.factor_reuse_steps: a cloth body factorizes every step"),
            std::string::npos) << reused;

  // A tensile curve that is not monotone, named by its point.
  const std::string own = "[bodies.fabric]\nkind = \"cloth\"\nsize = [0.2, 0.1]\nspacing = 0.01\n"
                          "[bodies.fabric.curves]\nareal_density = 0.2\n"
                          "warp = { strain = [0.0, 0.02, 0.05], tension = [0.0, 40.0, 30.0] }\n"
                          "weft = { strain = [0.0, 0.03], tension = [0.0, 20.0] }\n"
                          "shear = { angle = [0.0, 0.2], force = [0.0, 2.0] }\n"
                          "bend_warp = { curvature = [0.0, 100.0], moment = [0.0, 1e-3] }\n"
                          "bend_weft = { curvature = [0.0, 100.0], moment = [0.0, 5e-4] }\n";
  EXPECT_NE(cloth_error(own).find(":7:8: bodies.fabric.curves.warp: the tension against strain: not monotone: point 3 (30) is below point 2 (40)"), std::string::npos)
      << cloth_error(own);
  std::string negative = own;
  negative.replace(negative.find("areal_density = 0.2"), 19, "areal_density = -0.2");
  EXPECT_NE(cloth_error(negative).find("areal_density: -0.2 is out of range"), std::string::npos)
      << cloth_error(negative);
}

TEST(ClothScene, DatabaseErrorsPointIntoTheDatabase) {
  const auto dir = std::filesystem::temp_directory_path() / "tactus_cloth_db_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "fabrics.toml") << "[bad]\nW = 20.0\n[bad.warp]\nEMT = 5.0\nLT = 0.6\nWT = 20.0\nB = 0.1\nG = 1.0\n"
                                         "[bad.weft]\nEMT = 5.0\nLT = 0.6\nWT = 7.5\nB = 0.1\nG = 1.0\n";
  const std::string scene = with_line(kCloth, 3, "fabric = \"bad\"\nfabric_database = \"fabrics.toml\"");
  std::string message;
  try {
    parse_scene(scene, (dir / "scene.toml").string());
  } catch (const InputError& e) {
    message = e.what();
  }
  // WT = 20 where LT·½·500·5/100 = 7.5: a misprint the loader refuses, in the database's lines.
  EXPECT_NE(message.find("fabrics.toml:6:6: bad.warp.WT: WT = 20 disagrees by 167 %"), std::string::npos) << message;
  std::filesystem::remove_all(dir);
}

TEST(ClothScene, NonManifoldMeshIsRefusedNamingTheEdge) {
  const auto dir = std::filesystem::temp_directory_path() / "tactus_cloth_mesh_test";
  std::filesystem::create_directories(dir);
  // Three triangles on the edge 1–2.
  std::ofstream(dir / "fin.obj") << "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0.1 0.1 0\nv 0.05 0.05 0.1\n"
                                    "f 1 2 3\nf 2 4 3\nf 2 3 5\n";
  const std::string scene = "[bodies.fabric]\nkind = \"cloth\"\nfabric = \"denim\"\nmesh = \"fin.obj\"\n"
                            "warp_axis = [1, 0, 0]\nweft_axis = [0, 1, 0]\n";
  std::string message;
  try {
    parse_scene(scene, (dir / "scene.toml").string());
  } catch (const InputError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("bodies.fabric.mesh"), std::string::npos) << message;
  EXPECT_NE(message.find("edge"), std::string::npos) << message;
  std::filesystem::remove_all(dir);
}

TEST(ClothScene, FabricProxyTouchesClothOnItsPatch) {
  const std::string touch = kCloth + R"([bodies.block]
kind = "rigid"
mesh = { generator = "box", size = [0.05, 0.05, 0.05], cells = 1 }
[devices.hand]
type = "scripted"
trajectory = { type = "press", position = [0.1, -0.02, 0.25], direction = [0, 1, 0], depth = 0.01 }
[tools.thumb]
type = "sphere"
device = "hand"
radius = 0.009
[algorithms.thumb_on_fabric]
type = "fabric_proxy"
tool = "thumb"
bodies = ["fabric"]
side = "back"
)";
  const std::string path = std::string(TACTUS_SOURCE_DIR) + "/scenes/x.toml";
  const Model m = parse_scene(touch, path);
  const auto* p = std::get_if<FabricProxyParams>(&m.algorithms.at(0).params);
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->side, -1);
  EXPECT_FALSE(p->static_friction.has_value());  // the fabric's own
  auto error = [&](const std::string& from, const std::string& to) {
    std::string text = touch;
    text.replace(text.find(from), from.size(), to);
    return cloth_error(text);
  };
  EXPECT_NE(error("bodies = [\"fabric\"]", "bodies = [\"block\"]").find("fabric_proxy touches cloth bodies; 'block' is 'rigid'"),
            std::string::npos);
  EXPECT_NE(error("side = \"back\"", "side = \"back\"\nlocal_model = \"plane\"").find("local patch"), std::string::npos);
  EXPECT_NE(error("side = \"back\"", "side = \"backside\"").find("algorithms.thumb_on_fabric.side"), std::string::npos);
  EXPECT_NE(error("side = \"back\"", "static_friction = 0.5").find("give both friction coefficients"), std::string::npos);
}

TEST(ClothScene, TwoFingersNameEachOtherOnOppositeSidesWithTheirOwnDevices) {
  const std::string pair = kCloth + R"([devices.thumb]
type = "scripted"
trajectory = { type = "press", position = [0.1, -0.02, 0.25], direction = [0, 1, 0], depth = 0.01 }
[devices.index]
type = "scripted"
trajectory = { type = "press", position = [0.1, 0.02, 0.25], direction = [0, -1, 0], depth = 0.01 }
[tools.thumb]
type = "sphere"
device = "thumb"
radius = 0.009
[tools.index]
type = "sphere"
device = "index"
radius = 0.008
[algorithms.thumb_on_fabric]
type = "fabric_proxy"
tool = "thumb"
bodies = ["fabric"]
side = "front"
partner = "index"
pad_normal = [0, 2, 0]
fabric_thickness = 0.001
[algorithms.index_on_fabric]
type = "fabric_proxy"
tool = "index"
bodies = ["fabric"]
side = "back"
partner = "thumb"
pad_normal = [0, -1, 0]
)";
  const std::string path = std::string(TACTUS_SOURCE_DIR) + "/scenes/x.toml";
  const Model m = parse_scene(pair, path);
  const auto& thumb = std::get<FabricProxyParams>(m.algorithms.at(0).params);
  ASSERT_TRUE(thumb.partner.has_value());
  EXPECT_EQ(m.tools.at(*thumb.partner).name, "index");
  EXPECT_EQ(thumb.pad_normal, Vec3(0, 1, 0));  // normalized
  EXPECT_EQ(thumb.fabric_thickness, 0.001);
  auto error = [&](const std::string& from, const std::string& to) {
    std::string text = pair;
    text.replace(text.find(from), from.size(), to);
    return cloth_error(text);
  };
  // The partner must name this tool back and touch the other side; each finger has its own device.
  EXPECT_NE(error("partner = \"thumb\"\npad_normal = [0, -1, 0]", "").find("must name tool 'thumb' as its partner"),
            std::string::npos);
  EXPECT_NE(error("side = \"back\"", "side = \"front\"").find("opposite sides"), std::string::npos);
  EXPECT_NE(error("device = \"index\"", "device = \"thumb\"").find("already drives tool 'thumb'"), std::string::npos);
  EXPECT_NE(error("partner = \"index\"", "partner = \"ring\"").find("algorithms.thumb_on_fabric.partner"),
            std::string::npos);
  EXPECT_NE(error("pad_normal = [0, 2, 0]", "").find("pad_normal"), std::string::npos);
  EXPECT_NE(error("pad_normal = [0, 2, 0]", "pad_normal = [0, 0, 0]").find("non-zero"), std::string::npos);
  // The pair's keys mean nothing without a partner.
  EXPECT_NE(error("partner = \"index\"\npad_normal = [0, 2, 0]\nfabric_thickness = 0.001", "fabric_thickness = 0.001")
                .find("two-finger pair only"),
            std::string::npos);
}

}  // namespace
}  // namespace tactus::scene
