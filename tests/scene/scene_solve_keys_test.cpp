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

std::string solve_error(const std::string& extra) {
  try {
    parse_scene(kBlock + extra, "solve.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(SceneSolveKeys, Errors) {
  EXPECT_NE(solve_error("[[bodies.pad.loads]]\nside = \"x_max\"\n").find("bodies.pad.loads[0]"), std::string::npos);
  EXPECT_NE(solve_error("[[bodies.pad.loads]]\nside = \"x_max\"\n").find("force"), std::string::npos);
  EXPECT_NE(solve_error("[[bodies.pad.loads]]\nforce = [0, 0, 1]\n").find("missing a node selector"),
            std::string::npos);
  EXPECT_NE(solve_error("[[bodies.pad.loads]]\nname = \"wall\"\nside = \"x_max\"\nforce = [0, 0, 1]\n")
                .find("duplicate region name 'wall'"),
            std::string::npos);
  EXPECT_NE(solve_error("[[bodies.pad.prescribed]]\nside = \"x_min\"\ndisplacement = [0, 0, 1e-3]\n")
                .find("which fixed region 'wall' holds"),
            std::string::npos);
  EXPECT_NE(solve_error("[[bodies.pad.loads]]\nbox = { min = [1, 1, 1], max = [2, 2, 2] }\nforce = [0, 0, 1]\n")
                .find("selects no node"),
            std::string::npos);
  EXPECT_NE(solve_error("[[bodies.pad.probes]]\nposition = [0, 0, 0]\n[[bodies.pad.probes]]\nname = \"probe0\"\n"
                     "position = [0, 0, 0]\n")
                .find("duplicate probe name"),
            std::string::npos);
  const std::string ramp = solve_error("[[bodies.pad.loads]]\nside = \"x_max\"\nforce = [0, 0, 1]\nramp_time = -1\n");
  EXPECT_NE(ramp.find("solve.toml:"), std::string::npos) << ramp;
  EXPECT_NE(ramp.find("ramp_time"), std::string::npos) << ramp;
}

TEST(SceneSolveKeys, StaticSolveSettingsAreReadAndChecked) {
  const Model defaults = parse_scene(kBlock, "solve.toml");
  EXPECT_EQ(defaults.static_solve.newton.max_iterations, 100);
  EXPECT_EQ(defaults.static_solve.newton.tolerance, 1e-8);
  EXPECT_EQ(defaults.static_solve.newton.force_tolerance, 1e-10);
  EXPECT_EQ(defaults.static_solve.max_step_halvings, 8);
  const Model m = parse_scene(kBlock + "[solve]\ntolerance = 1e-10\nforce_tolerance = 1e-12\n"
                                      "max_iterations = 30\nmax_step_halvings = 3\n",
                              "solve.toml");
  EXPECT_EQ(m.static_solve.newton.tolerance, 1e-10);
  EXPECT_EQ(m.static_solve.newton.force_tolerance, 1e-12);
  EXPECT_EQ(m.static_solve.newton.max_iterations, 30);
  EXPECT_EQ(m.static_solve.max_step_halvings, 3);
  EXPECT_NE(solve_error("[solve]\ntolerance = 0\n").find("solve.tolerance"), std::string::npos);
  EXPECT_NE(solve_error("[solve]\nmax_iterations = 0\n").find("solve.max_iterations"), std::string::npos);
  EXPECT_NE(solve_error("[solve]\nforce_tolerance = -1\n").find("solve.force_tolerance"), std::string::npos);
  EXPECT_NE(solve_error("[solve]\nmax_halvings = 2\n").find("max_halvings"), std::string::npos);
}

/// kBlock with `keys` added to the body's table.
std::string pad_with(const std::string& keys) {
  std::string scene = kBlock;
  const std::string anchor = "load_steps = 4\n";
  return scene.insert(scene.find(anchor) + anchor.size(), keys);
}

std::string body_error(const std::string& keys) {
  try {
    parse_scene(pad_with(keys), "body.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(SceneBodyKeys, NewtonIterationsAndConsistentMassAreRead) {
  const Body plain = parse_scene(pad_with(""), "body.toml").bodies.at(0);
  EXPECT_EQ(plain.stepping.newton_iterations, 1);
  EXPECT_EQ(plain.mass_matrix, MassMatrix::lumped);
  const Model m = parse_scene(pad_with("newton_iterations = 3\nmass_matrix = \"consistent\"\n"), "body.toml");
  EXPECT_EQ(m.bodies.at(0).stepping.newton_iterations, 3);
  EXPECT_EQ(m.bodies.at(0).mass_matrix, MassMatrix::consistent);
  const std::string summary = summarize(m);
  EXPECT_NE(summary.find("consistent mass, 3 Newton iterations"), std::string::npos) << summary;
}

TEST(SceneBodyKeys, NewtonIterationsAndConsistentMassErrors) {
  for (const char* bad : {"newton_iterations = 0\n", "newton_iterations = 101\n", "newton_iterations = 2.5\n"}) {
    const std::string e = body_error(bad);
    EXPECT_NE(e.find("body.toml:"), std::string::npos) << e;
    EXPECT_NE(e.find("newton_iterations"), std::string::npos) << e;
  }
  EXPECT_NE(body_error("integrator = \"symplectic_euler\"\nnewton_iterations = 3\n").find("only implicit_euler"),
            std::string::npos);
  // "static" once parsed and stepped as implicit_euler: equilibrium is tactus solve --static's.
  const std::string static_integrator = body_error("integrator = \"static\"\n");
  EXPECT_NE(static_integrator.find("not a time integrator"), std::string::npos) << static_integrator;
  EXPECT_NE(static_integrator.find("tactus solve --static"), std::string::npos) << static_integrator;
  const std::string explicit_mass = body_error("integrator = \"rk4\"\nmass_matrix = \"consistent\"\n");
  EXPECT_NE(explicit_mass.find("mass_matrix"), std::string::npos) << explicit_mass;
  EXPECT_NE(explicit_mass.find("explicit integrators divide by a lumped mass"), std::string::npos) << explicit_mass;
  std::string springs = kBlock;
  springs.replace(springs.find("kind = \"fem\""), 12, "kind = \"tet_mass_spring\"\nmass_matrix = \"consistent\"");
  try {
    parse_scene(springs, "body.toml");
    ADD_FAILURE() << "a spring body took a consistent mass";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("for 'fem' bodies"), std::string::npos) << e.what();
  }
}

TEST(SceneBodyKeys, FactorReuseIsReadForLinearizedCholeskySteps) {
  EXPECT_EQ(parse_scene(pad_with(""), "body.toml").bodies.at(0).stepping.factor_reuse_steps, 1);
  const Model m = parse_scene(pad_with("solver = \"cholesky\"\nfactor_reuse_steps = 4\n"), "body.toml");
  EXPECT_EQ(m.bodies.at(0).stepping.factor_reuse_steps, 4);
  const std::string summary = summarize(m);
  EXPECT_NE(summary.find("one factorization per 4 steps"), std::string::npos) << summary;
  for (const char* bad : {"solver = \"cholesky\"\nfactor_reuse_steps = 0\n", "factor_reuse_steps = 2\n",
                          "solver = \"cholesky\"\nnewton_iterations = 2\nfactor_reuse_steps = 2\n",
                          "integrator = \"rk4\"\nsolver = \"cholesky\"\nfactor_reuse_steps = 2\n"}) {
    const std::string e = body_error(bad);
    EXPECT_NE(e.find("body.toml:"), std::string::npos) << e;
    EXPECT_NE(e.find("factor_reuse_steps"), std::string::npos) << e;
  }
  EXPECT_NE(body_error("factor_reuse_steps = 2\n").find("solved by cholesky"), std::string::npos);
}

TEST(SceneBodyKeys, MappedSurfacesAreReadAndMappedIntoTheTetrahedra) {
  // The pad spans [-0.05, 0.05] x [-0.01, 0.01]^2: a finer box skin on its boundary, a vessel
  // through it along z and a fascia sheet across it.
  const Model m = parse_scene(pad_with(R"(
[[bodies.pad.mapped]]
name = "skin"
role = "visual"
mesh = { generator = "box", size = [0.1, 0.02, 0.02], cells = 3 }

[[bodies.pad.mapped]]
name = "vessel"
role = "embedded"
mesh = { generator = "cylinder", radius = 0.003, height = 0.016, segments = 8, rings = 4, translate = [0.02, 0, -0.008] }

[[bodies.pad.mapped]]
role = "collision"
mesh = { generator = "grid_plate", size = [0.08, 0.015], cells = 4 }
)"),
                              "mapped.toml");
  const Body& b = m.bodies.at(0);
  ASSERT_EQ(b.mapped.size(), 3u);
  EXPECT_EQ(b.mapped[0].name, "skin");
  EXPECT_EQ(b.mapped[0].role, MappedRole::visual);
  EXPECT_EQ(b.mapped[1].role, MappedRole::embedded);
  EXPECT_EQ(b.mapped[2].name, "mapped2");
  EXPECT_EQ(b.mapped[2].role, MappedRole::collision);
  VecX rest(3 * static_cast<Eigen::Index>(b.volume->vertices.size()));
  for (std::size_t i = 0; i < b.volume->vertices.size(); ++i) rest.segment<3>(3 * static_cast<Eigen::Index>(i)) = b.volume->vertices[i];
  for (const MappedSurface& s : b.mapped) {
    ASSERT_TRUE(s.mapping);
    ASSERT_EQ(s.mapping->point_count(), s.mesh.vertices.size());
    EXPECT_FALSE(s.mesh.triangles.empty());
    // At rest the mapping reproduces every vertex (barycentric weights sum to one).
    std::vector<Vec3> at_rest;
    s.mapping->apply(rest, at_rest);
    for (std::size_t v = 0; v < at_rest.size(); ++v)
      ASSERT_LT((at_rest[v] - s.mesh.vertices[v]).norm(), 1e-12) << s.name << " vertex " << v;
  }
  const std::string summary = summarize(m);
  EXPECT_NE(summary.find("mapped embedded surface 'vessel'"), std::string::npos) << summary;
}

TEST(SceneBodyKeys, MappedSurfaceErrors) {
  // A sphere of radius 0.02 reaches 0.01 m beyond the pad's faces.
  const std::string outside = body_error(R"(
[[bodies.pad.mapped]]
name = "ball"
role = "visual"
mesh = { generator = "sphere", radius = 0.02, subdivisions = 1 }
)");
  EXPECT_NE(outside.find("body.toml:"), std::string::npos) << outside;
  EXPECT_NE(outside.find("mapped surface 'ball'"), std::string::npos) << outside;
  EXPECT_NE(outside.find("outside body 'pad''s tetrahedra"), std::string::npos) << outside;
  // A generous tolerance accepts it.
  EXPECT_NO_THROW(parse_scene(pad_with("[[bodies.pad.mapped]]\nrole = \"visual\"\ntolerance = 0.02\n"
                                       "mesh = { generator = \"sphere\", radius = 0.02, subdivisions = 1 }\n"),
                              "body.toml"));
  EXPECT_NE(body_error("[[bodies.pad.mapped]]\nrole = \"skin\"\nmesh = { generator = \"sphere\", radius = 0.005 }\n")
                .find("role"),
            std::string::npos);
  EXPECT_NE(body_error("[[bodies.pad.mapped]]\nmesh = { generator = \"sphere\", radius = 0.005 }\n").find("role"),
            std::string::npos);
  EXPECT_NE(body_error("[[bodies.pad.mapped]]\nrole = \"visual\"\n").find("mesh"), std::string::npos);
  EXPECT_NE(body_error("[[bodies.pad.mapped]]\nname = \"a\"\nrole = \"visual\"\nmesh = { generator = \"sphere\", "
                       "radius = 0.005 }\n[[bodies.pad.mapped]]\nname = \"a\"\nrole = \"embedded\"\n"
                       "mesh = { generator = \"sphere\", radius = 0.004 }\n")
                .find("duplicate mapped surface name 'a'"),
            std::string::npos);
}

}  // namespace
}  // namespace tactus::scene
