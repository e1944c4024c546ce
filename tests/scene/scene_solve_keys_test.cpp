// Loads, prescribed displacements and probes (the keys `tactus solve` reads).
#include <gtest/gtest.h>

#include <string>

#include "core/error.hpp"
#include "scene/scene.hpp"

namespace tactus::scene {
namespace {

const std::string kBlock = R"(
[materials.gel]
young_modulus = 1e4
density = 1000

[bodies.pad]
kind = "fem"
material = "gel"
mesh = { generator = "box", size = [0.1, 0.02, 0.02], cells = [10, 2, 2] }
load_steps = 4

[[bodies.pad.fixed]]
name = "wall"
side = "x_min"
)";

TEST(SceneSolveKeys, LoadsPrescribedAndProbesAreRead) {
  const Model m = parse_scene(kBlock + R"(
[[bodies.pad.loads]]
name = "tip"
side = "x_max"
force = [0, 0, -0.5]
ramp_time = 0.2

[[bodies.pad.prescribed]]
name = "pinch"
box = { min = [-0.001, -0.011, 0.009], max = [0.001, 0.011, 0.011] }
displacement = [0, 0, -0.001]

[[bodies.pad.probes]]
name = "end"
position = [0.05, 0, 0]
)",
                              "solve.toml");
  const Body& b = m.bodies.at(0);
  EXPECT_EQ(b.load_steps, 4);
  ASSERT_EQ(b.loads.size(), 1u);
  EXPECT_EQ(b.loads[0].name, "tip");
  EXPECT_EQ(b.loads[0].nodes.size(), 9u);  // the 3 × 3 nodes of the x_max face
  EXPECT_EQ(b.loads[0].force, Vec3(0, 0, -0.5));
  EXPECT_EQ(b.loads[0].ramp_time, 0.2);
  ASSERT_EQ(b.prescribed.size(), 1u);
  EXPECT_EQ(b.prescribed[0].nodes.size(), 3u);  // the top row of nodes at x = 0
  EXPECT_EQ(b.prescribed[0].displacement, Vec3(0, 0, -0.001));
  ASSERT_EQ(b.probes.size(), 1u);
  EXPECT_EQ(b.probes[0].position, Vec3(0.05, 0, 0));
  const std::string summary = summarize(m);
  EXPECT_NE(summary.find("load 'tip' (side x_max): 9 nodes"), std::string::npos) << summary;
  EXPECT_NE(summary.find("probe 'end'"), std::string::npos) << summary;
}

std::string error_of(const std::string& extra) {
  try {
    parse_scene(kBlock + extra, "solve.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(SceneSolveKeys, Errors) {
  EXPECT_NE(error_of("[[bodies.pad.loads]]\nside = \"x_max\"\n").find("bodies.pad.loads[0]"), std::string::npos);
  EXPECT_NE(error_of("[[bodies.pad.loads]]\nside = \"x_max\"\n").find("force"), std::string::npos);
  EXPECT_NE(error_of("[[bodies.pad.loads]]\nforce = [0, 0, 1]\n").find("missing a node selector"),
            std::string::npos);
  EXPECT_NE(error_of("[[bodies.pad.loads]]\nname = \"wall\"\nside = \"x_max\"\nforce = [0, 0, 1]\n")
                .find("duplicate region name 'wall'"),
            std::string::npos);
  EXPECT_NE(error_of("[[bodies.pad.prescribed]]\nside = \"x_min\"\ndisplacement = [0, 0, 1e-3]\n")
                .find("which fixed region 'wall' holds"),
            std::string::npos);
  EXPECT_NE(error_of("[[bodies.pad.loads]]\nbox = { min = [1, 1, 1], max = [2, 2, 2] }\nforce = [0, 0, 1]\n")
                .find("selects no node"),
            std::string::npos);
  EXPECT_NE(error_of("[[bodies.pad.probes]]\nposition = [0, 0, 0]\n[[bodies.pad.probes]]\nname = \"probe0\"\n"
                     "position = [0, 0, 0]\n")
                .find("duplicate probe name"),
            std::string::npos);
  const std::string ramp = error_of("[[bodies.pad.loads]]\nside = \"x_max\"\nforce = [0, 0, 1]\nramp_time = -1\n");
  EXPECT_NE(ramp.find("solve.toml:"), std::string::npos) << ramp;
  EXPECT_NE(ramp.find("ramp_time"), std::string::npos) << ramp;
}

}  // namespace
}  // namespace tactus::scene
