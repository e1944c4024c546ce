// Valid scenes: defaults, resolved meshes and regions, references, the default scene.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "scene/scene.hpp"

namespace tactus::scene {
namespace {

const char* kMinimal = R"(
[materials.gel]
young_modulus = 1e4
density = 1000

[bodies.pad]
kind = "fem"
material = "gel"
mesh = { generator = "box", size = [0.1, 0.1, 0.02], cells = [4, 4, 2] }

[devices.hand]
type = "network"

[tools.finger]
type = "sphere"
device = "hand"

[algorithms.feel]
type = "proxy"
tool = "finger"
)";

TEST(SceneLoad, DefaultsAreApplied) {
  const Model m = parse_scene(kMinimal, "scenes/minimal.toml");
  EXPECT_EQ(m.name, "minimal");  // the file's stem when [scene] gives none
  EXPECT_EQ(m.rates.haptic, 1000.0);
  EXPECT_EQ(m.rates.simulation, 100.0);
  EXPECT_EQ(m.rates.interaction, 120.0);
  EXPECT_EQ(m.rates.visual, 60.0);
  EXPECT_EQ(m.gravity, Vec3(0, 0, -9.81));

  ASSERT_EQ(m.materials.size(), 1u);
  const Material& gel = m.materials[0];
  EXPECT_EQ(gel.law, physics::FemLaw::corotational);
  EXPECT_EQ(gel.poisson_ratio, 0.45);
  EXPECT_NEAR(gel.shear_modulus, 1e4 / (2 * 1.45), 1e-9);
  EXPECT_NEAR(gel.bulk_modulus, 1e4 / (3 * 0.1), 1e-6);
  EXPECT_EQ(gel.damping.rayleigh_alpha, 0.0);
  EXPECT_EQ(gel.viscoelastic.model, ViscoelasticModel::none);

  ASSERT_EQ(m.bodies.size(), 1u);
  const Body& pad = m.bodies[0];
  EXPECT_EQ(pad.stepping.integrator, physics::Integrator::implicit_euler);
  EXPECT_DOUBLE_EQ(pad.time_step, 0.01);  // 1 / rates.simulation
  EXPECT_EQ(pad.stepping.solver, physics::LinearSolver::conjugate_gradient);
  EXPECT_EQ(pad.mass_matrix, MassMatrix::lumped);
  EXPECT_TRUE(pad.fixed.empty());
  ASSERT_TRUE(pad.volume.has_value());
  EXPECT_EQ(pad.volume->vertices.size(), 5u * 5u * 3u);
  EXPECT_NEAR(pad.volume->volume(), 0.1 * 0.1 * 0.02, 1e-12);
  EXPECT_NEAR(pad.surface.signed_volume(), 0.1 * 0.1 * 0.02, 1e-12);  // boundary is outward
  EXPECT_EQ(pad.surface_to_volume.size(), pad.surface.vertices.size());

  ASSERT_EQ(m.devices.size(), 1u);
  const Device& hand = m.devices[0];
  EXPECT_EQ(hand.max_force, 10.0);
  EXPECT_EQ(hand.max_stiffness, 2000.0);
  EXPECT_EQ(hand.max_damping, 100.0);
  const auto& net = std::get<NetworkDevice>(hand.source);
  EXPECT_EQ(net.address, "127.0.0.1");  // loopback unless the scene says otherwise

  const auto& finger = std::get<SphereTool>(m.tools.at(0).shape);
  EXPECT_EQ(finger.radius, 0.008);
  EXPECT_EQ(finger.finger.young_modulus, 1.0e6);
  EXPECT_EQ(m.tools[0].devices, std::vector<std::size_t>{0});

  const Algorithm& feel = m.algorithms.at(0);
  EXPECT_TRUE(feel.enabled);
  EXPECT_TRUE(feel.bodies.empty());
  EXPECT_EQ(std::get<ProxyParams>(feel.params).stiffness, 500.0);
  EXPECT_TRUE(m.recording.path.empty());
}

TEST(SceneLoad, DefaultSceneParsesWithExpectedCounts) {
  const Model m = default_scene();
  EXPECT_EQ(m.name, "default");
  ASSERT_EQ(m.bodies.size(), 1u);
  const Body& block = m.bodies[0];
  ASSERT_TRUE(block.volume.has_value());
  EXPECT_EQ(block.volume->vertices.size(), 11u * 11u * 5u);
  EXPECT_GT(block.volume->tets.size(), 0u);
  EXPECT_EQ(block.volume->tets.size() % 400u, 0u);  // whole cubes
  ASSERT_EQ(block.fixed.size(), 1u);
  EXPECT_EQ(block.fixed[0].nodes.size(), 11u * 11u);  // the z_min face

  const std::string s = summarize(m);
  EXPECT_NE(s.find("scene 'default'"), std::string::npos) << s;
  EXPECT_NE(s.find("haptic 1000 Hz, simulation 100 Hz, interaction 120 Hz, visual 60 Hz"), std::string::npos) << s;
  EXPECT_NE(s.find("soft_tissue: corotational, E 30000 Pa, nu 0.45"), std::string::npos) << s;
  EXPECT_NE(s.find("block: fem, material soft_tissue"), std::string::npos) << s;
  EXPECT_NE(s.find("tet mesh: 605 vertices, " + std::to_string(block.volume->tets.size()) + " tets"),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("fixed 'base' (side z_min): 121 nodes"), std::string::npos) << s;
  EXPECT_NE(s.find("volume: 0.0004 m^3"), std::string::npos) << s;
  EXPECT_NE(s.find("finger: sphere, radius 0.008 m"), std::string::npos) << s;
  EXPECT_NE(s.find("hand: scripted (press trajectory)"), std::string::npos) << s;
  EXPECT_NE(s.find("touch: proxy, tool finger"), std::string::npos) << s;
  // The real-time settings are the real-time run's business: a lockstep run does not use them.
  EXPECT_NE(s.find("real time: SCHED_FIFO"), std::string::npos) << s;
  EXPECT_EQ(summarize(m, /*real_time=*/false).find("SCHED_FIFO"), std::string::npos);
}

TEST(SceneLoad, BodiesKeepFileOrder) {
  const Model m = parse_scene(R"(
[materials.a]
young_modulus = 1e4
density = 1000
[bodies.zeta]
kind = "rigid"
mesh = { generator = "sphere", radius = 0.01, subdivisions = 1 }
[bodies.alpha]
kind = "rigid"
mesh = { generator = "sphere", radius = 0.02, subdivisions = 1 }
)",
                              "order.toml");
  ASSERT_EQ(m.bodies.size(), 2u);
  EXPECT_EQ(m.bodies[0].name, "zeta");
  EXPECT_EQ(m.bodies[1].name, "alpha");
  EXPECT_FALSE(m.bodies[0].material.has_value());
  EXPECT_EQ(m.find_body("alpha"), &m.bodies[1]);
  EXPECT_EQ(m.find_body("beta"), nullptr);
}

TEST(SceneLoad, MeshTransformAndRegions) {
  const Model m = parse_scene(R"(
[materials.skin]
young_modulus = 5e4
density = 1100
[bodies.sheet]
kind = "surface_mass_spring"
material = "skin"
mesh = { generator = "grid_plate", size = [0.1, 0.05], cells = [10, 5], quads = true, translate = [0, 0, 0.02], scale = 2 }
springs = ["longitudinal", "diagonal"]
[[bodies.sheet.fixed]]
border = true
[[bodies.sheet.fixed]]
name = "corner"
nodes = [0]
[[bodies.sheet.fixed]]
name = "left"
side = "x_min"
[[bodies.sheet.fixed]]
name = "middle"
box = { min = [-0.01, -0.2, 0], max = [0.01, 0.2, 1] }
)",
                              "sheet.toml");
  const Body& b = m.bodies.at(0);
  ASSERT_TRUE(b.quads.has_value());
  EXPECT_EQ(b.quads->quads.size(), 50u);
  EXPECT_EQ(b.surface.triangles.size(), 100u);
  const Aabb box = b.surface.bounds();
  EXPECT_NEAR(box.min.x(), -0.1, 1e-12);  // scaled by 2 about the origin
  EXPECT_NEAR(box.max.y(), 0.05, 1e-12);
  EXPECT_NEAR(box.min.z(), 0.02, 1e-12);  // then translated
  ASSERT_EQ(b.fixed.size(), 4u);
  EXPECT_EQ(b.fixed[0].name, "fixed0");
  EXPECT_EQ(b.fixed[0].nodes.size(), 2u * 11u + 2u * 4u);  // the border of 11 × 6 nodes
  EXPECT_EQ(b.fixed[1].nodes, std::vector<mesh::Index>{0});
  EXPECT_EQ(b.fixed[2].nodes.size(), 6u);
  EXPECT_EQ(b.fixed[3].nodes.size(), 6u);  // the column at x = 0
  EXPECT_EQ(b.springs, (std::vector<SpringType>{SpringType::longitudinal, SpringType::diagonal}));
}

TEST(SceneLoad, HyperelasticConstants) {
  const Model m = parse_scene(R"(
[materials.mr]
model = "mooney_rivlin"
c10 = 1000
c01 = 500
kappa = 1e5
density = 1000
[materials.nh]
model = "neo_hookean"
mu = 3000
kappa = 1e5
density = 1000
[materials.sls]
young_modulus = 1e4
poisson_ratio = 0.3
density = 1000
damping = { nodal = 0.5 }
viscoelastic = { model = "standard_linear_solid", tau = 0.2, long_term_fraction = 0.4 }
)",
                              "mat.toml");
  const Material& mr = *m.find_material("mr");
  EXPECT_EQ(mr.c10, 1000.0);
  EXPECT_EQ(mr.c01, 500.0);
  EXPECT_DOUBLE_EQ(mr.shear_modulus, 3000.0);
  EXPECT_DOUBLE_EQ(mr.bulk_modulus, 1e5);
  // E and ν follow from μ and κ.
  EXPECT_NEAR(mr.young_modulus, 9 * 1e5 * 3000 / (3 * 1e5 + 3000), 1e-6);
  EXPECT_GT(mr.poisson_ratio, 0.48);
  EXPECT_LT(mr.poisson_ratio, 0.5);
  const Material& nh = *m.find_material("nh");
  EXPECT_NEAR(nh.young_modulus, mr.young_modulus, 1e-9);
  EXPECT_DOUBLE_EQ(nh.c10, 1500.0);
  const Material& sls = *m.find_material("sls");
  EXPECT_EQ(sls.viscoelastic.model, ViscoelasticModel::standard_linear_solid);
  EXPECT_EQ(sls.viscoelastic.long_term_fraction, 0.4);
  EXPECT_EQ(sls.damping.nodal, 0.5);
  EXPECT_NEAR(sls.lame_lambda, 1e4 * 0.3 / (1.3 * 0.4), 1e-9);
}

TEST(SceneLoad, ToolsDevicesAlgorithms) {
  const Model m = parse_scene(R"(
[materials.m]
young_modulus = 1e4
density = 1000
[bodies.artery]
kind = "rigid"
mesh = { generator = "cylinder", radius = 0.003, height = 0.05 }
[devices.a]
type = "simulated_operator"
trajectory = { type = "circle", center = [0, 0, 0.01], radius = 0.01, normal = [0, 0, 2] }
hand_mass = 0.3
[devices.b]
type = "scripted"
trajectory = { type = "raster", min = [-0.02, -0.02], max = [0.02, 0.02], z = 0.01 }
tremor = { amplitude = 1e-4 }
[devices.c]
type = "scripted"
trajectory = { type = "needle_line", entry = [0, 0, 0.02], target = [0, 0, -0.02] }
[tools.hand]
type = "two_fingers"
devices = ["a", "b"]
[tools.pin]
type = "needle"
device = "c"
[algorithms.pad]
type = "fingerpad"
tool = "hand"
[algorithms.beat]
type = "pulse"
tool = "hand"
body = "artery"
rate = 60
enabled = false
[algorithms.insert]
type = "needle"
tool = "pin"
[recording]
path = "out.tacrec"
include = ["forces", "events"]
)",
                              "tools.toml");
  const auto& op = std::get<SimulatedOperatorDevice>(m.find_device("a")->source);
  EXPECT_EQ(op.hand_mass, 0.3);
  EXPECT_EQ(std::get<CirclePath>(op.target).normal, Vec3(0, 0, 1));  // normalized
  EXPECT_EQ(std::get<ScriptedDevice>(m.find_device("b")->source).tremor.amplitude, 1e-4);
  EXPECT_EQ(m.find_tool("hand")->devices, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(std::get<FingerpadParams>(m.find_algorithm("pad")->params).m, 2100.0);
  const Algorithm& beat = *m.find_algorithm("beat");
  EXPECT_FALSE(beat.enabled);
  EXPECT_EQ(std::get<PulseParams>(beat.params).body, 0u);
  EXPECT_EQ(std::get<PulseParams>(beat.params).duty_cycle, 0.2);
  EXPECT_EQ(m.recording.path, "out.tacrec");
  EXPECT_TRUE(m.recording.forces);
  EXPECT_FALSE(m.recording.poses);
  EXPECT_NO_THROW(summarize(m));
}

TEST(SceneLoad, NeedleAlgorithmNeedsANeedle) {
  EXPECT_THROW(parse_scene(R"(
[devices.d]
type = "network"
[tools.t]
type = "sphere"
device = "d"
[algorithms.a]
type = "needle"
tool = "t"
)",
                           "n.toml"),
               InputError);
}

TEST(SceneLoad, SphereSetLayouts) {
  const Model m = parse_scene(R"(
[devices.d]
type = "network"
[devices.e]
type = "network"
port = 47601
[tools.eight]
type = "sphere_set"
device = "d"
radius = 0.004
[tools.one]
type = "sphere_set"
device = "e"
count = 1
)",
                              "s.toml");
  const auto& eight = std::get<SphereSetTool>(m.tools[0].shape);
  ASSERT_EQ(eight.spheres.size(), 8u);
  EXPECT_NEAR(eight.spheres[7].center.x(), 0.002, 1e-15);
  EXPECT_EQ(std::get<SphereSetTool>(m.tools[1].shape).spheres.size(), 1u);
}

}  // namespace
}  // namespace tactus::scene

namespace tactus::scene {
namespace {

TEST(SceneLoad, RealtimeSettingsAndWorkspaceRotation) {
  const Model m = parse_scene(std::string(kMinimal) + R"(
[realtime]
priority = 0
haptic_cpu = 1
spin = 0.0002
dedicated_core = true

[devices.left]
type = "dhd"
index = 2
scale = 2.0
offset = [0.1, 0, 0]
rotation = { axis = [0, 0, 2], degrees = 90 }
)", "scenes/rt.toml");
  EXPECT_EQ(m.realtime.priority, 0);
  EXPECT_EQ(m.realtime.haptic_cpu, 1);
  EXPECT_EQ(m.realtime.spin, 0.0002);
  EXPECT_TRUE(m.realtime.dedicated_core);
  const Device* d = m.find_device("left");
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(std::get<DhdDevice>(d->source).index, 2);
  // 90° about z takes the device's x axis to the scene's y axis.
  EXPECT_LT((d->rotation * Vec3::UnitX() - Vec3::UnitY()).norm(), 1e-15);
  EXPECT_EQ(parse_scene(kMinimal, "m.toml").realtime.priority, 80);  // the default
}

}  // namespace
}  // namespace tactus::scene
