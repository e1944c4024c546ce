// The [precompute] table of scene files.
#include <gtest/gtest.h>

#include <numbers>
#include <string>
#include <variant>

#include "core/error.hpp"
#include "precompute/grid.hpp"
#include "scene/scene.hpp"
#include "test_body.hpp"

namespace tactus::precompute {
namespace {

std::string scene_with(const std::string& table) { return testing::block_scene(table); }

std::string error_of(const std::string& table) {
  try {
    (void)scene::parse_scene(scene_with(table), "test.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(PrecomputeScene, ReadsTheTable) {
  const auto m = scene::parse_scene(scene_with(R"(
contact_point = [0.001, 0.0, 0.011]
patch_radius = 0.011
spacing = 0.005
min = [-0.01, -0.01, 0.0]
max = [0.01, 0.01, 0.02]
load_steps = 3
interpolation = "rbf_cubic"
refine_points = 40
)"),
                                    "test.toml");
  ASSERT_TRUE(m.precompute);
  const auto& s = *m.precompute;
  EXPECT_EQ(s.body, "block");
  const Vec3 node = m.bodies[0].volume->vertices[static_cast<std::size_t>(s.contact_node)];
  EXPECT_TRUE(node.isApprox(Vec3(0.0, 0.0, 0.01)));
  EXPECT_EQ(s.patch_nodes.size(), 6u);  // the node and its neighbours 1 cm away: four on the top face, one below
  EXPECT_EQ(s.load_steps, 3);
  EXPECT_EQ(s.interpolation, Interpolation::rbf_cubic);
  EXPECT_EQ(s.refine_points, 40);
}

TEST(PrecomputeScene, ReadsAProbe) {
  const std::string grid = "contact_point = [0, 0, 0.01]\nspacing = 0.005\nmin = [-0.01, -0.01, 0.0]\n"
                           "max = [0.01, 0.01, 0.02]\npatch_radius = 0.011\n";
  const auto m = scene::parse_scene(scene_with(grid + "probe_axis = [0, 0, -2]\nprobe_tilt = 15\n"
                                                      "probe_tilt_levels = 5\n"),
                                    "test.toml");
  ASSERT_TRUE(m.precompute);
  EXPECT_TRUE(m.precompute->probe.enabled());
  EXPECT_EQ(m.precompute->probe.axis, Vec3(0, 0, -1));
  EXPECT_NEAR(m.precompute->probe.max_tilt, 15.0 * std::numbers::pi / 180.0, 1e-15);
  EXPECT_EQ(m.precompute->probe.level_count(), 25u);
  EXPECT_FALSE(scene::parse_scene(scene_with(grid), "test.toml").precompute->probe.enabled());

  auto fails = [&](const std::string& keys, const std::string& key, const std::string& why) {
    const std::string e = error_of(grid + keys);
    EXPECT_NE(e.find(key), std::string::npos) << e;
    EXPECT_NE(e.find(why), std::string::npos) << e;
  };
  fails("probe_tilt = 10\n", "probe_tilt", "probe_axis");
  fails("probe_axis = [0, 0, -1]\n", "probe_tilt", "");
  fails("probe_axis = [0, 0, 0]\nprobe_tilt = 10\n", "probe_axis", "non-zero");
  fails("probe_axis = [0, 0, -1]\nprobe_tilt = 95\n", "probe_tilt", "");
  fails("probe_axis = [0, 0, -1]\nprobe_tilt = 10\nprobe_tilt_levels = 4\n", "probe_tilt_levels", "odd");
  const std::string no_patch = error_of("contact_point = [0, 0, 0.01]\nspacing = 0.005\nmin = [-0.01, -0.01, 0.0]\n"
                                        "max = [0.01, 0.01, 0.02]\nprobe_axis = [0, 0, -1]\nprobe_tilt = 10\n");
  EXPECT_NE(no_patch.find("patch_radius"), std::string::npos) << no_patch;
}

TEST(PrecomputeScene, ReadsASecondPoint) {
  const std::string grid = "contact_point = [-0.01, 0, 0.01]\nspacing = 0.003\nmin = [-0.013, -0.003, 0.004]\n"
                           "max = [-0.007, 0.003, 0.0101]\n";
  const std::string second = "second_point = [0.0098, 0.0002, 0.0101]\nsecond_min = [0.007, -0.003, 0.004]\n"
                             "second_max = [0.013, 0.003, 0.0101]\n";
  const auto m = scene::parse_scene(scene_with(grid + second), "test.toml");
  ASSERT_TRUE(m.precompute);
  const auto& s = *m.precompute;
  ASSERT_TRUE(s.pair.enabled());
  const auto& nodes = m.bodies[0].volume->vertices;
  EXPECT_TRUE(nodes[static_cast<std::size_t>(s.pair.node)].isApprox(Vec3(0.01, 0.0, 0.01)));
  EXPECT_EQ(s.pair.patch_nodes, std::vector<std::int32_t>{s.pair.node});
  EXPECT_EQ(s.pair.bounds_min, Vec3(0.007, -0.003, 0.004));
  EXPECT_EQ(s.finger, 0);
  EXPECT_FALSE(scene::parse_scene(scene_with(grid), "test.toml").precompute->pair.enabled());

  auto fails = [&](const std::string& keys, const std::string& key, const std::string& why) {
    const std::string e = error_of(keys);
    EXPECT_NE(e.find(key), std::string::npos) << e;
    EXPECT_NE(e.find(why), std::string::npos) << e;
  };
  fails(grid + "second_min = [0.007, -0.003, 0.004]\n", "second_min", "second_point");
  fails(grid + "second_point = [0.01, 0, 0.01]\nsecond_max = [0.013, 0.003, 0.0101]\n", "second_min", "");
  fails(grid + "second_point = [0.01, 0, 0.01]\nsecond_min = [0.013, -0.003, 0.004]\nsecond_max = [0.007, 0.003, "
               "0.0101]\n",
        "second_max", "exceed");
  // A box that leaves the second point's grid a single point along z.
  fails(grid + "second_point = [0.01, 0, 0.01]\nsecond_min = [0.007, -0.003, 0.009]\nsecond_max = [0.013, 0.003, "
               "0.0101]\n",
        "spacing", "the second point's node");
  fails(grid + "second_point = [0.01, 0, -0.01]\nsecond_min = [0.007, -0.003, -0.013]\nsecond_max = [0.013, 0.003, "
               "-0.007]\n",
        "second_point", "fixed region");
  // Patches that overlap: 11 mm patches of nodes 20 mm apart share the node between them.
  fails(grid + second + "patch_radius = 0.011\n", "second_point", "share node");
  fails(grid + second + "patch_radius = 0.011\nprobe_axis = [0, 0, -1]\nprobe_tilt = 10\n", "second_point",
        "either a probe or a second point");
}

TEST(PrecomputeScene, BadTablesAreInputErrors) {
  const std::string grid = "spacing = 0.005\nmin = [-0.01, -0.01, 0.0]\nmax = [0.01, 0.01, 0.02]\n";
  EXPECT_NE(error_of("spacing = 0.005\n").find("contact_point"), std::string::npos);
  EXPECT_NE(error_of("contact_point = [0, 0, -0.01]\n" + grid).find("fixed region"), std::string::npos);
  EXPECT_NE(error_of("contact_point = [0, 0, 0.01]\nspacing = 1e-5\nmin = [-0.01, -0.01, 0.0]\n"
                     "max = [0.01, 0.01, 0.02]\n")
                .find("more than"),
            std::string::npos);
  EXPECT_NE(error_of("contact_point = [0, 0, 0.01]\n" + grid + "interpolation = \"cubic\"\n").find("rbf_cubic"),
            std::string::npos);
  EXPECT_NE(error_of("contact_point = [0, 0, 0.01]\n" + grid + "spacng = 1\n").find("spacng"), std::string::npos);
}

// The bundled liver scene's space (docs/precompute.md, "The liver scene"): a coarse mesh of
// liver.toml's organ, small enough to precompute in minutes, and a grid that the palpating
// finger reaches.
TEST(PrecomputeScene, BundledLiverSpace) {
  const scene::Model fine = scene::load_scene(std::string(TACTUS_SOURCE_DIR) + "/scenes/liver.toml");
  const scene::Model coarse = scene::load_scene(std::string(TACTUS_SOURCE_DIR) + "/scenes/liver_cspace.toml");
  ASSERT_TRUE(coarse.precompute);
  const auto& organ = *coarse.find_body("liver");
  ASSERT_TRUE(organ.volume);
  // The same organ: the bounds of liver.toml's surface within a millimetre.
  EXPECT_LT((organ.surface.bounds().min - fine.find_body("liver")->surface.bounds().min).norm(), 1e-3);
  EXPECT_LT((organ.surface.bounds().max - fine.find_body("liver")->surface.bounds().max).norm(), 1e-3);
  EXPECT_LT(organ.volume->vertices.size(), 600u);  // liver.toml has 3064 nodes
  const auto& s = *coarse.precompute;
  const Vec3 contact = organ.volume->vertices[static_cast<std::size_t>(s.contact_node)];
  EXPECT_GT(contact.z(), 0.035);  // on the top (the organ is 42.3 mm high above its centre)
  const auto grid = Grid::through(contact, s.bounds_min, s.bounds_max, s.spacing);
  EXPECT_GE(grid.size(), 50u);
  EXPECT_LE(grid.size(), 120u);
  // The finger's radius: on this coarse mesh no other node is that close to the contact node.
  EXPECT_EQ(s.patch_nodes, std::vector<std::int32_t>{s.contact_node});

  // The scripted hand scans inside the grid's box from its first point on: outside it the
  // space renders no force (a start at y = -30 mm felt nothing for the first 5 s).
  ASSERT_EQ(coarse.devices.size(), 1u);
  const scene::Device& hand = coarse.devices[0];
  EXPECT_EQ(hand.scale, 1.0);
  EXPECT_TRUE(hand.offset.isZero());
  const auto* op = std::get_if<scene::SimulatedOperatorDevice>(&hand.source);
  ASSERT_NE(op, nullptr);
  const auto* raster = std::get_if<scene::RasterPath>(&op->target);
  ASSERT_NE(raster, nullptr);
  const Vec3 lo = grid.lower(), hi = grid.upper();
  for (const Vec2& corner : {raster->min, raster->max, Vec2(raster->min.x(), raster->max.y()),
                             Vec2(raster->max.x(), raster->min.y())}) {
    SCOPED_TRACE(::testing::Message() << "raster corner (" << corner.x() << ", " << corner.y() << ")");
    EXPECT_GE(corner.x(), lo.x());
    EXPECT_LE(corner.x(), hi.x());
    EXPECT_GE(corner.y(), lo.y());
    EXPECT_LE(corner.y(), hi.y());
  }
  EXPECT_GE(raster->z, lo.z());
  EXPECT_LE(raster->z, hi.z());
}

}  // namespace
}  // namespace tactus::precompute
