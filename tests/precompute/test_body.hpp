#pragma once
// A small StVK block held at its base, its top centre node the contact node: spaces of a few
// dozen points solve in well under a second.
#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "mesh/generators.hpp"
#include "physics/body.hpp"
#include "physics/fem/tet_fem.hpp"
#include "precompute/configuration_solver.hpp"
#include "precompute/settings.hpp"

namespace tactus::precompute::testing {

/// The mean and largest error of the forces `guess` against `truth`, each relative to the
/// largest force of `truth` (the accuracy study's measure, docs/validation.md).
inline std::pair<double, double> relative_errors(const std::vector<Vec3>& truth, const std::vector<Vec3>& guess) {
  double scale = 0.0, sum = 0.0, worst = 0.0;
  for (const Vec3& f : truth) scale = std::max(scale, f.norm());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const double e = (guess[i] - truth[i]).norm() / scale;
    sum += e;
    worst = std::max(worst, e);
  }
  return {sum / static_cast<double>(truth.size()), worst};
}

/// Configurations solved `step` either side of `at` along each axis by transitions from the
/// solved `centre`: [k][0] at at + step·e_k, [k][1] at at − step·e_k (for central differences
/// of what they store; the caller checks that each solved).
inline std::array<std::array<PointResult, 2>, 3> solved_either_side(ConfigurationSolver& solver,
                                                                     const PointResult& centre, const Vec3& at,
                                                                     double step) {
  std::array<std::array<PointResult, 2>, 3> out;
  for (int k = 0; k < 3; ++k) {
    const Vec3 d = step * Vec3::Unit(k);
    out[static_cast<std::size_t>(k)] = {solver.transition(1, 0, centre.displacement, at, at + d),
                                        solver.transition(2, 0, centre.displacement, at, at - d)};
  }
  return out;
}

inline physics::Body block_body(double young = 5.0e3, double poisson = 0.3) {
  const mesh::TetMesh mesh = mesh::box_volume(Vec3(0.04, 0.04, 0.02), 4, 4, 2);
  physics::FemMaterial material;
  material.law = physics::FemLaw::stvk;
  material.young_modulus = young;
  material.poisson_ratio = poisson;
  physics::Body body;
  body.model = std::make_shared<physics::TetFem>(mesh, material);
  std::vector<std::int32_t> base;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if (mesh.vertices[v].z() < -0.0099) base.push_back(static_cast<std::int32_t>(v));
  body.fix_nodes(base);
  return body;
}

/// Settings for block_body(): the top centre node, a 3 x 3 x 4 grid of 3 mm.
inline SpaceSettings block_settings(const physics::Body& body) {
  SpaceSettings s;
  s.body = "block";
  const VecX& rest = body.model->rest_positions();
  for (Eigen::Index n = 0; n < rest.size() / 3; ++n)
    if (rest.segment<3>(3 * n).isApprox(Vec3(0, 0, 0.01), 1e-9)) s.contact_node = static_cast<std::int32_t>(n);
  s.patch_nodes = {s.contact_node};
  s.spacing = 0.003;
  s.bounds_min = Vec3(-0.003, -0.003, 0.004);
  s.bounds_max = Vec3(0.003, 0.003, 0.013);
  return s;
}

/// The same block as a scene file, followed by `precompute_table` (the keys of its
/// [precompute] table).
inline std::string block_scene(const std::string& precompute_table) {
  return R"(
[materials.tissue]
model = "stvk"
young_modulus = 5.0e3
poisson_ratio = 0.3
density = 1000.0

[bodies.block]
kind = "fem"
material = "tissue"
solver = "cholesky"

[bodies.block.mesh]
generator = "box"
size = [0.04, 0.04, 0.02]
cells = [4, 4, 2]

[[bodies.block.fixed]]
side = "z_min"

[precompute]
)" + precompute_table;
}

/// The block's scene with a probe leaning 12 degrees either way, its end the contact node and
/// its neighbours 1 cm away: a space of 9 levels of 27 points, pressed at most 3 mm (deeper,
/// the leaning probe turns the block's coarse elements inside out).
inline std::string probe_block_scene() {
  return block_scene(R"(contact_point = [0.0, 0.0, 0.01]
spacing = 0.003
min = [-0.003, -0.003, 0.007]
max = [0.003, 0.003, 0.013]
patch_radius = 0.0105
probe_axis = [0.0, 0.0, -1.0]
probe_tilt = 12.0
)");
}

/// The block's scene with two points on its top 20 mm apart (at x = −10 and +10 mm), each
/// with a 3 mm grid over 3 mm either way and 6 mm down: 27 points each, 2 + 27 + 27 levels.
inline std::string pair_block_scene() {
  return block_scene(R"(contact_point = [-0.01, 0.0, 0.01]
spacing = 0.003
min = [-0.013, -0.003, 0.004]
max = [-0.007, 0.003, 0.0101]
second_point = [0.01, 0.0, 0.01]
second_min = [0.007, -0.003, 0.004]
second_max = [0.013, 0.003, 0.0101]
)");
}

}  // namespace tactus::precompute::testing
