// bodies.<name>.nodules and [feedback]: what they load into, and a clear error at the
// offending key for each way they can be wrong.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "scene/scene.hpp"

namespace tactus::scene {
namespace {

const std::string kSheet = R"([materials.skin]
model = "mass_spring"
young_modulus = 4e5
density = 1100

[bodies.skin]
kind = "surface_mass_spring"
material = "skin"
mesh = { generator = "grid_plate", size = [0.08, 0.08], cells = 8, quads = true }
[[bodies.skin.fixed]]
name = "border"
border = true
)";

Model parse(const std::string& extra) { return parse_scene(kSheet + extra, "nodules.toml"); }

/// The error's text ("file:line:col: reason"); fails the test when it parses.
std::string error_of(const std::string& extra) {
  try {
    parse(extra);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for:\n" << extra;
  return {};
}

TEST(NoduleKeys, RigidAndSoftNodulesLoad) {
  const Model m = parse(R"(
[[bodies.skin.nodules]]
name = "hard"
center = [0.01, 0.0, -0.008]
radius = 0.006
rigid = true

[[bodies.skin.nodules]]
center = [-0.01, 0.0, -0.006]
radius = 0.004
young_modulus = 6e4

[feedback]
safe_force = 2.5
)");
  const Body& b = m.bodies.at(0);
  ASSERT_EQ(b.nodules.size(), 2u);
  EXPECT_EQ(b.nodules[0].name, "hard");
  EXPECT_TRUE(b.nodules[0].rigid);
  EXPECT_EQ(b.nodules[0].center, Vec3(0.01, 0.0, -0.008));
  EXPECT_EQ(b.nodules[0].radius, 0.006);
  EXPECT_EQ(b.nodules[1].name, "nodule1");
  EXPECT_FALSE(b.nodules[1].rigid);
  EXPECT_EQ(b.nodules[1].young_modulus, 6e4);
  EXPECT_EQ(b.nodules[1].poisson_ratio, 0.45);
  EXPECT_EQ(m.feedback.safe_force, 2.5);
  EXPECT_EQ(parse("").feedback.safe_force, 0.0);
}

TEST(NoduleKeys, EachMistakeIsNamedWhereItIs) {
  const std::string nodule = "\n[[bodies.skin.nodules]]\ncenter = [0, 0, -0.01]\nradius = 0.005\n";
  EXPECT_NE(error_of(nodule).find("give 'rigid = true' or the Young's modulus"), std::string::npos);
  EXPECT_NE(error_of(nodule + "rigid = false\n").find("soft nodule (rigid = false) needs its Young's modulus"),
            std::string::npos);
  const std::string both = error_of(nodule + "rigid = true\nyoung_modulus = 1e5\n");
  EXPECT_NE(both.find("nodules.toml:18:"), std::string::npos) << both;
  EXPECT_NE(both.find("bodies.skin.nodules[0].young_modulus"), std::string::npos) << both;
  EXPECT_NE(error_of(nodule + "rigid = true\npoisson_ratio = 0.3\n").find("takes no Poisson ratio"), std::string::npos);
  EXPECT_NE(error_of("\n[[bodies.skin.nodules]]\ncenter = [0, 0, -0.01]\nradius = -1\nrigid = true\n").find("must be > 0"),
            std::string::npos);
  EXPECT_NE(error_of("\n[[bodies.skin.nodules]]\nradius = 0.005\nrigid = true\n").find("center"), std::string::npos);
  EXPECT_NE(error_of(nodule + "rigid = true\nsize = 3\n").find("unknown key 'size'"), std::string::npos);
  EXPECT_NE(error_of(nodule + "rigid = true\nname = \"a b\"\n").find("1 to 64 letters"), std::string::npos);
  EXPECT_NE(error_of(nodule + "rigid = true\nname = \"n\"" + nodule + "rigid = true\nname = \"n\"\n")
                .find("duplicate nodule name 'n'"),
            std::string::npos);
  // A nodule around the held border.
  EXPECT_NE(error_of("\n[[bodies.skin.nodules]]\nname = \"edge\"\ncenter = [0.04, 0.0, 0.0]\nradius = 0.003\nrigid = true\n")
                .find("nodule 'edge' encloses node"),
            std::string::npos);
  EXPECT_NE(error_of("\n[feedback]\nsafe_force = -1\n").find("feedback.safe_force"), std::string::npos);
  EXPECT_NE(error_of("\n[feedback]\nsafe_forse = 1\n").find("did you mean 'safe_force'"), std::string::npos);
}

TEST(NoduleKeys, OnlySheetsTakeNodules) {
  const std::string text = R"([materials.tissue]
young_modulus = 3e4
density = 1000

[bodies.block]
kind = "fem"
material = "tissue"
mesh = { generator = "box", size = [0.1, 0.1, 0.04], cells = 1 }
[[bodies.block.nodules]]
center = [0, 0, 0]
radius = 0.01
rigid = true
)";
  try {
    parse_scene(text, "fem.toml");
    FAIL() << "nodules on a fem body were accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nodules lie under a 'surface_mass_spring' sheet; a 'fem' body takes none"),
              std::string::npos)
        << e.what();
  }
}

TEST(NoduleKeys, BundledNoduleSceneLoads) {
  const Model m = load_scene(std::filesystem::path(TACTUS_SOURCE_DIR) / "scenes/nodule.toml");
  ASSERT_EQ(m.bodies.size(), 1u);
  ASSERT_EQ(m.bodies[0].nodules.size(), 2u);
  EXPECT_TRUE(m.bodies[0].nodules[0].rigid);
  EXPECT_FALSE(m.bodies[0].nodules[1].rigid);
  EXPECT_LT(m.bodies[0].nodules[1].radius, m.bodies[0].nodules[0].radius);
  EXPECT_GT(m.feedback.safe_force, 0.0);
}

}  // namespace
}  // namespace tactus::scene
