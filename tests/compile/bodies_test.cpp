// The bridge from scene bodies to physics bodies: step settings, mass matrix, viscoelastic
// hyperelastic materials, and mapped surfaces driven by a body state.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "core/error.hpp"
#include "physics/fem/nodal_pressure.hpp"
#include "physics/fem/tet_fem.hpp"
#include "compile/bodies.hpp"
#include "scene/scene.hpp"

namespace tactus::runtime {
namespace {

const std::string kScene = R"(
[materials.liver]
model = "neo_hookean"
young_modulus = 5e3
poisson_ratio = 0.45
density = 1060
viscoelastic = { model = "standard_linear_solid", tau = 0.4, long_term_fraction = 0.5 }

[bodies.organ]
kind = "fem"
material = "liver"
mesh = { generator = "box", size = [0.04, 0.03, 0.02], cells = [4, 3, 2] }
newton_iterations = 3
mass_matrix = "consistent"

[[bodies.organ.mapped]]
name = "skin"
role = "visual"
mesh = { generator = "sphere", radius = 0.009, subdivisions = 2 }

[[bodies.organ.mapped]]
name = "fascia"
role = "embedded"
mesh = { generator = "grid_plate", size = [0.03, 0.02], cells = 6, translate = [0, 0, 0.004] }
)";

VecX random_vector(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  VecX v(n);
  for (auto& c : v) c = u(rng);
  return v;
}

TEST(RuntimeBodies, SceneSettingsReachThePhysicsBody) {
  const scene::Model model = scene::parse_scene(kScene, "bodies.toml");
  const physics::Body body = compile::make_physics_body(model, 0);
  EXPECT_EQ(body.settings.newton_iterations, 3);
  const auto* fem = dynamic_cast<const physics::TetFem*>(body.model.get());
  ASSERT_NE(fem, nullptr);
  EXPECT_EQ(fem->mass_kind(), physics::FemMass::consistent);
  EXPECT_FALSE(fem->mass_is_diagonal());
  // The neo-Hookean law carries the standard linear solid's branch (6 + 6 values per tet).
  EXPECT_EQ(fem->internal_size(), 12 * fem->elements().size());
  physics::BodyState s = physics::make_state(body);
  for (int i = 0; i < 3; ++i) physics::step(body, s, 0.01);
  EXPECT_TRUE(s.x.allFinite());
}

TEST(RuntimeBodies, MappedSurfacesFollowAffineMotionAndCarryForcesBack) {
  // P1 interpolation reproduces affine motion exactly, so every mapped vertex p must move to
  // F p + t (round-off: 1e-12 m). The transpose must do the same virtual work as the forces
  // on the vertices for any node motion (1e-12 relative) and so conserve the total force.
  const scene::Model model = scene::parse_scene(kScene, "bodies.toml");
  const scene::Body& b = model.bodies.at(0);
  ASSERT_EQ(b.mapped.size(), 2u);
  const auto nodes = static_cast<Eigen::Index>(b.volume->vertices.size());
  Mat3 F;
  F << 1.1, 0.2, 0.0, -0.1, 0.9, 0.05, 0.03, 0.0, 1.2;
  const Vec3 t(0.01, -0.02, 0.005);
  VecX x(3 * nodes);
  for (Eigen::Index i = 0; i < nodes; ++i) x.segment<3>(3 * i) = F * b.volume->vertices[static_cast<std::size_t>(i)] + t;
  std::vector<std::vector<Vec3>> surfaces;
  compile::mapped_surface_positions(b, x, surfaces);
  ASSERT_EQ(surfaces.size(), 2u);
  for (std::size_t k = 0; k < surfaces.size(); ++k) {
    ASSERT_EQ(surfaces[k].size(), b.mapped[k].mesh.vertices.size());
    for (std::size_t v = 0; v < surfaces[k].size(); ++v)
      ASSERT_LT((surfaces[k][v] - (F * b.mapped[k].mesh.vertices[v] + t)).norm(), 1e-12) << b.mapped[k].name << " " << v;

    std::vector<Vec3> forces(surfaces[k].size());
    const VecX random = random_vector(3 * static_cast<Eigen::Index>(forces.size()), 5 + static_cast<unsigned>(k));
    Vec3 total = Vec3::Zero();
    for (std::size_t v = 0; v < forces.size(); ++v) total += forces[v] = random.segment<3>(3 * static_cast<Eigen::Index>(v));
    VecX node_forces = VecX::Zero(3 * nodes);
    compile::add_mapped_surface_forces(b, k, forces, node_forces);
    Vec3 node_total = Vec3::Zero();
    for (Eigen::Index i = 0; i < nodes; ++i) node_total += node_forces.segment<3>(3 * i);
    EXPECT_LT((node_total - total).norm(), 1e-12 * random.norm());
    const VecX dx = random_vector(3 * nodes, 17);
    std::vector<std::vector<Vec3>> moved;
    compile::mapped_surface_positions(b, x + dx, moved);
    double work = 0.0;
    for (std::size_t v = 0; v < forces.size(); ++v) work += forces[v].dot(moved[k][v] - surfaces[k][v]);
    EXPECT_NEAR(node_forces.dot(dx), work, 1e-12 * node_forces.norm() * dx.norm());
  }
  EXPECT_THROW(compile::add_mapped_surface_forces(b, 2, {}, x), std::out_of_range);
}

TEST(RuntimeBodies, NodalVolumetricMaterialsAverageTheVolumeChangeAtTheNodes) {
  const std::string scene = R"(
[materials.tissue]
model = "mooney_rivlin"
c10 = 700
c01 = 300
poisson_ratio = 0.49
density = 1000
volumetric = "nodal"
[bodies.block]
kind = "fem"
material = "tissue"
mesh = { generator = "box", size = [0.02, 0.02, 0.02], cells = 2 }
solver = "cholesky"
)";
  const scene::Model model = scene::parse_scene(scene, "nodal.toml");
  EXPECT_TRUE(model.materials.at(0).nodal_pressure);
  EXPECT_NE(scene::summarize(model).find("pressure at the nodes"), std::string::npos) << scene::summarize(model);
  const physics::Body body = compile::make_physics_body(model, 0);
  const auto* nodal = dynamic_cast<const physics::NodalPressureFem*>(body.model.get());
  ASSERT_NE(nodal, nullptr);
  EXPECT_EQ(physics::tet_fem_of(body.model.get()), &nodal->isochoric());
  EXPECT_TRUE(nodal->isochoric().material().nodal_pressure);
  // Squeezed to 90 % of its volume, every node's pressure is κ (0.9 − 1).
  const VecX x = [&] {
    VecX y = body.model->rest_positions();
    for (Eigen::Index i = 2; i < y.size(); i += 3) y[i] *= 0.9;
    return y;
  }();
  const double kappa = model.materials.at(0).bulk_modulus;
  EXPECT_LT((nodal->nodal_pressures(x).array() + 0.1 * kappa).abs().maxCoeff(), 1e-9 * kappa);

  for (const auto& [keys, why] :
       {std::pair{std::string("model = \"neo_hookean\"\nyoung_modulus = 3000\n"), "use model = \"mooney_rivlin\""},
        std::pair{std::string("model = \"mooney_rivlin\"\nc10 = 700\nviscoelastic = { model = \"prony\", "
                              "terms = [{ g = 0.3, tau = 0.1 }] }\n"),
                  "keeps the bulk response elastic"}}) {
    try {
      scene::parse_scene("[materials.m]\n" + keys + "density = 1000\nvolumetric = \"nodal\"\n", "bad.toml");
      ADD_FAILURE() << keys;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("bad.toml:"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("volumetric"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace tactus::runtime
