#pragma once
// The scene of the cloth step benchmarks (issue 25): a 20 × 20 cm denim sheet hanging from a
// bar clamp along its top edge, released from a tilt out of its plane, under gravity.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/hash.hpp"
#include "physics/body.hpp"
#include "physics/cloth/sheet.hpp"
#include "scene/scene.hpp"

namespace tactus::bench_cloth {

inline constexpr double kSide = 0.20;      ///< [m]
inline constexpr double kGravity = 9.81;   ///< [m/s²]
inline constexpr double kTilt = 0.3;       ///< [rad] out of plane about the clamp's lower edge
inline constexpr double kDamping = 0.002;  ///< [s] time constant of stretch, shear and bending

/// Denim as the fabric database gives it (data/fabrics.toml [denim]: Kumari & Khurana,
/// Journal of Textiles 2016, Table 5, sample B), read the way a scene reads it.
inline physics::ClothMaterial denim_material() {
  const std::string scene = "[bodies.f]\nkind = \"cloth\"\nfabric = \"denim\"\nsize = [0.1, 0.1]\nspacing = 0.05\n";
  physics::ClothMaterial m =
      scene::parse_scene(scene, std::string(TACTUS_SOURCE_DIR) + "/scenes/bench.toml").bodies.at(0).cloth->model->material();
  m.stretch_damping = m.shear_damping = m.bend_damping = kDamping;
  return m;
}

struct HangingSheet {
  physics::SheetGrid grid;
  physics::Body body;
  std::vector<std::int32_t> clamp;  ///< the held nodes (the two top rows)
  VecX start;                       ///< positions at release (tilted)
  std::int32_t tip = 0;             ///< the middle node of the bottom edge
};

/// The sheet at `spacing` [m]: warp hanging down (−z), weft along x, the first two warp rows
/// held by the clamp (clamp_warp_start), the rest turned by kTilt about the clamp's lower
/// edge towards +y: released there it swings about the clamp like a pendulum and flexes.
inline HangingSheet hanging_sheet(double spacing, physics::LinearSolver solver) {
  HangingSheet s{physics::rectangular_sheet(kSide, kSide, spacing, Vec3::Zero(), -Vec3::UnitZ(), Vec3::UnitX()),
                 {}, {}, {}, 0};
  s.clamp = physics::clamp_warp_start(s.grid);
  s.body.model = std::make_shared<physics::ClothModel>(s.grid.cloth, denim_material());
  s.body.gravity = Vec3(0.0, 0.0, -kGravity);
  s.body.settings.integrator = physics::Integrator::implicit_euler;
  s.body.settings.solver = solver;  // CG at the default tolerance 1e-4, or CHOLMOD
  s.body.fix_nodes(s.clamp);
  s.start = s.body.model->rest_positions();
  const double edge = -s.grid.cloth.uv[static_cast<std::size_t>(s.grid.at(1, 0))].x();  // the clamp's lower edge, z
  for (Eigen::Index n = 0; n < s.start.size() / 3; ++n) {
    const double depth = edge - s.start[3 * n + 2];
    if (depth <= 0.0) continue;
    s.start[3 * n + 1] = depth * std::sin(kTilt);
    s.start[3 * n + 2] = edge - depth * std::cos(kTilt);
  }
  s.tip = s.grid.at(s.grid.nodes_u - 1, s.grid.nodes_v / 2);
  return s;
}

/// FNV-1a of the bytes of v: equal states, equal hashes (for bit-for-bit checks).
inline std::uint64_t state_hash(const VecX& v) {
  Fnv1a h;
  h.add(v.data(), sizeof(double) * static_cast<std::size_t>(v.size()));
  return h.value();
}

}  // namespace tactus::bench_cloth
