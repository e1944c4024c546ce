#pragma once
// The scene of the cloth step benchmarks (issue 25): a 20 × 20 cm denim sheet hanging from a
// bar clamp along its top edge, released from a tilt out of its plane, under gravity.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "physics/body.hpp"
#include "physics/cloth/kes.hpp"
#include "physics/cloth/sheet.hpp"

namespace tactus::bench_cloth {

inline constexpr double kSide = 0.20;      ///< [m]
inline constexpr double kGravity = 9.81;   ///< [m/s²]
inline constexpr double kTilt = 0.3;       ///< [rad] out of plane about the clamp's lower edge
inline constexpr double kDamping = 0.002;  ///< [s] time constant of stretch, shear and bending

/// Denim as data/fabrics.toml [denim] gives it (Kumari & Khurana, Journal of Textiles 2016,
/// Article ID 4614168, Table 5, sample B): one value per property, used for warp and weft.
/// EMT 5.735 %, LT 0.655, WT 9.400 gf·cm/cm², B 0.144 gf·cm²/cm, G 1.538 gf/(cm·°),
/// W 37.1 mg/cm² (the table marks W illustrative), tensile test to 500 gf/cm.
inline physics::KesFabric denim() {
  physics::KesFabric f;
  f.warp = {5.735, 0.655, 9.400, 0.144, 1.538};
  f.weft = f.warp;
  f.w = 37.1;
  f.tensile_max_load = 500.0;
  return f;
}

inline physics::ClothMaterial denim_material() {
  physics::ClothMaterial m = physics::kes_material(denim(), "denim");
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
  std::uint64_t h = 1469598103934665603ull;
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v[i], sizeof bits);
    for (int b = 0; b < 8; ++b) {
      h ^= (bits >> (8 * b)) & 0xffu;
      h *= 1099511628211ull;
    }
  }
  return h;
}

}  // namespace tactus::bench_cloth
