// Embedded bodies (scene kind "embedded"): a surface carried by another body's tetrahedra
// follows them, a load on it reaches them by the mapping's transpose (the same virtual
// work), and the loader refuses what cannot be carried.
#include <gtest/gtest.h>

#include <string>

#include "core/error.hpp"
#include "runtime/exchange.hpp"
#include "runtime/haptic_loop.hpp"
#include "runtime/simulation_loop.hpp"
#include "scene/scene.hpp"

namespace tactus::runtime {
namespace {

const std::string kBlock = R"(
[scene]
gravity = [0, 0, 0]

[rates]
simulation = 100

[materials.soft]
model = "corotational"
young_modulus = 2e4
poisson_ratio = 0.4
density = 1000
damping = { rayleigh_alpha = 2.0 }

[bodies.tissue]
kind = "fem"
material = "soft"
mesh = { generator = "box", size = [0.04, 0.04, 0.02], cells = [4, 4, 2], translate = [0, 0, -0.01] }
time_step = 0.01
[[bodies.tissue.fixed]]
side = "z_min"
)";

const std::string kLayers = R"(
[bodies.skin]
kind = "embedded"
host = "tissue"
mesh = { generator = "grid_plate", size = [0.038, 0.038], cells = [12, 12] }

[bodies.fascia]
kind = "embedded"
host = "tissue"
mesh = { generator = "grid_plate", size = [0.03, 0.03], cells = [6, 6], translate = [0, 0, -0.006] }
)";

TEST(EmbeddedBody, LoadsAfterItsHostWhateverTheOrderAndSaysWhatCarriesIt) {
  // "fascia" and "skin" sort before "tissue": the loader reads them after it.
  const scene::Model m = scene::parse_scene(kBlock + kLayers, "embedded.toml");
  ASSERT_EQ(m.bodies.size(), 3u);
  const scene::Body* skin = m.find_body("skin");
  ASSERT_NE(skin, nullptr);
  EXPECT_EQ(skin->kind, scene::BodyKind::embedded);
  ASSERT_TRUE(skin->host.has_value());
  EXPECT_EQ(m.bodies[*skin->host].name, "tissue");
  EXPECT_EQ(skin->host_mapping->point_count(), skin->surface.vertices.size());
  EXPECT_NE(scene::summarize(m).find("carried by tissue"), std::string::npos);
}

TEST(EmbeddedBody, RefusesAMissingHostARigidHostAndAVertexOutside) {
  auto message = [](const std::string& text) {
    try {
      (void)scene::parse_scene(text, "bad.toml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(kBlock + "[bodies.skin]\nkind = \"embedded\"\nhost = \"tisue\"\nmesh = { generator = \"grid_plate\", size = [0.01, 0.01] }\n")
                .find("undefined body 'tisue'"),
            std::string::npos);
  EXPECT_NE(message(kBlock + "[bodies.bone]\nkind = \"rigid\"\nmesh = { generator = \"sphere\", radius = 0.01 }\n"
                             "[bodies.skin]\nkind = \"embedded\"\nhost = \"bone\"\nmesh = { generator = \"grid_plate\", size = [0.01, 0.01] }\n")
                .find("rides on the tetrahedra"),
            std::string::npos);
  const std::string outside = message(kBlock + "[bodies.skin]\nkind = \"embedded\"\nhost = \"tissue\"\n"
                                               "mesh = { generator = \"grid_plate\", size = [0.01, 0.01], translate = [0, 0, 0.01] }\n");
  EXPECT_NE(outside.find("outside body 'tissue'"), std::string::npos) << outside;
  EXPECT_NE(outside.find("bad.toml:"), std::string::npos) << outside;  // located in the scene
}

TEST(EmbeddedBody, APushOnTheSkinDentsTheTissueAndTheFasciaUnderItFollows) {
  const scene::Model m = scene::parse_scene(kBlock + kLayers, "embedded.toml");
  auto index = [&](const char* name) { return static_cast<std::size_t>(m.find_body(name) - m.bodies.data()); };
  const std::size_t tissue = index("tissue"), skin = index("skin"), fascia = index("fascia");
  DeviceChannels channels(16);
  SimulationLoop sim(m, {&channels});
  // A 2 N push down on the skin triangle nearest the centre, spread over that triangle.
  const scene::Body& s = m.bodies[skin];
  std::int32_t centre = 0;
  double best = 1e9;
  for (std::size_t t = 0; t < s.surface.triangles.size(); ++t) {
    Vec3 c = Vec3::Zero();
    for (auto v : s.surface.triangles[t]) c += s.surface.vertices[v] / 3.0;
    if (c.norm() < best) best = c.norm(), centre = static_cast<std::int32_t>(t);
  }
  ContactLoad& load = channels.load.write_buffer();
  load.active = true;
  load.body = static_cast<std::int32_t>(skin);
  load.triangle = centre;
  load.barycentric = Vec3::Constant(1.0 / 3.0);
  load.force = Vec3(0, 0, -2.0);
  channels.load.publish();
  for (int k = 0; k < 200; ++k) sim.step(k * 0.01, 0, 0, false);

  const VecX& host = *sim.positions(tissue);
  const VecX& skin_x = *sim.positions(skin);
  const VecX& fascia_x = *sim.positions(fascia);
  // Embedded vertices sit where the host's tetrahedra put them.
  std::vector<Vec3> expected;
  s.host_mapping->apply(host, expected);
  for (std::size_t v = 0; v < expected.size(); ++v)
    EXPECT_LT((skin_x.segment<3>(3 * static_cast<Eigen::Index>(v)) - expected[v]).norm(), 1e-12) << v;
  // The skin dents under the push; the fascia below moves down with the tissue, less.
  auto lowest_drop = [&](const scene::Body& b, const VecX& x) {
    double drop = 0.0;
    for (std::size_t v = 0; v < b.surface.vertices.size(); ++v)
      drop = std::max(drop, b.surface.vertices[v].z() - x(3 * static_cast<Eigen::Index>(v) + 2));
    return drop;
  };
  const double skin_drop = lowest_drop(s, skin_x), fascia_drop = lowest_drop(m.bodies[fascia], fascia_x);
  EXPECT_GT(skin_drop, 5e-4);
  EXPECT_GT(fascia_drop, 0.1 * skin_drop);
  EXPECT_LT(fascia_drop, skin_drop);
  // Without gravity nothing else moves the tissue: the dent is the load's, carried to the
  // host's nodes by the mapping's transpose.
  double host_drop = 0.0;
  for (Eigen::Index i = 2; i < host.size(); i += 3)
    host_drop = std::max(host_drop, m.bodies[tissue].volume->vertices[static_cast<std::size_t>(i / 3)].z() - host(i));
  EXPECT_GT(host_drop, 0.5 * skin_drop);
}

TEST(NeedleShaft, ItsPushIsSharedByTheTissueNodesAlongItAndTheTissueFollows) {
  // A shaft 8 mm into the block through the skin, pushing the tissue along +x with 0.5 N
  // (the reaction of a lateral pull on the hand): the tissue at the shaft moves along +x and
  // not sideways; with the shaft flag off the same load record moves nothing.
  const scene::Model m = scene::parse_scene(kBlock + kLayers, "embedded.toml");
  const std::size_t tissue = static_cast<std::size_t>(m.find_body("tissue") - m.bodies.data());
  const std::size_t skin = static_cast<std::size_t>(m.find_body("skin") - m.bodies.data());
  auto run = [&](bool shaft) {
    DeviceChannels channels(16);
    SimulationLoop sim(m, {&channels});
    ContactLoad& load = channels.load.write_buffer();
    load.body = static_cast<std::int32_t>(skin);  // a layer of the host: the host takes it
    load.shaft = shaft;
    load.shaft_from = Vec3(0, 0, 0);
    load.shaft_to = Vec3(0, 0, -0.008);
    load.shaft_force = Vec3(0.5, 0, 0);
    channels.load.publish();
    for (int k = 0; k < 200; ++k) sim.step(k * 0.01, 0, 0, false);
    if (shaft) {
      const auto& search = sim.parts()[5];
      EXPECT_EQ(search.name, "shaft node search");
      EXPECT_GT(search.time.count(), 0u);
    }
    return VecX(*sim.positions(tissue));
  };
  const VecX pushed = run(true), idle = run(false);
  const auto& rest = m.bodies[tissue].volume->vertices;
  for (std::size_t n = 0; n < rest.size(); ++n) {
    const Vec3 moved = pushed.segment<3>(3 * static_cast<Eigen::Index>(n)) - rest[n];
    EXPECT_LT((idle.segment<3>(3 * static_cast<Eigen::Index>(n)) - rest[n]).norm(), 1e-12) << n;  // round-off
    if (rest[n].norm() < 1e-9) {  // the node where the shaft enters
      EXPECT_GT(moved.x(), 1e-4);
      EXPECT_LT(std::abs(moved.y()), 0.1 * moved.x());
    }
  }
}

TEST(EmbeddedBody, WithoutALoadTheLayersStayAtRest) {
  const scene::Model m = scene::parse_scene(kBlock + kLayers, "embedded.toml");
  const std::size_t skin = static_cast<std::size_t>(m.find_body("skin") - m.bodies.data());
  SimulationLoop sim(m, {});
  for (int k = 0; k < 20; ++k) sim.step(k * 0.01, 0, 0, false);
  const VecX& x = *sim.positions(skin);
  for (std::size_t v = 0; v < m.bodies[skin].surface.vertices.size(); ++v)
    EXPECT_LT((x.segment<3>(3 * static_cast<Eigen::Index>(v)) - m.bodies[skin].surface.vertices[v]).norm(), 1e-12);
}

}  // namespace
}  // namespace tactus::runtime
