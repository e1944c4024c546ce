// A contact load in parts (a sphere-set finger on a patch, runtime/exchange.hpp): the
// simulation spreads each part over its own contact, weighted by its share, so the tissue
// dents under every sphere in proportion to that sphere's force.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "runtime/exchange.hpp"
#include "runtime/haptic_loop.hpp"
#include "runtime/simulation_loop.hpp"
#include "scene/scene.hpp"

namespace tactus::runtime {
namespace {

scene::Model soft_block() {
  return scene::load_scene(std::filesystem::path(TACTUS_SOURCE_DIR) / "tests/fixtures/scenes/soft_block.toml");
}

/// The top-surface triangle whose centroid is nearest (x, 0, 0).
std::int32_t top_triangle(const scene::Body& b, double x) {
  std::int32_t best = -1;
  double best_d = 1e9;
  for (std::size_t t = 0; t < b.surface.triangles.size(); ++t) {
    Vec3 c = Vec3::Zero();
    for (auto v : b.surface.triangles[t]) c += b.surface.vertices[v] / 3.0;
    const double d = (c - Vec3(x, 0.0, 0.0)).norm();
    if (d < best_d) best_d = d, best = static_cast<std::int32_t>(t);
  }
  return best;
}

/// The block after 1 s under a push of `force` newtons split into `parts` (x, share), or
/// (split false) all of it on the first part's triangle: how far its top sinks near
/// x = −20 mm and x = +20 mm.
std::pair<double, double> drops(double force, const std::vector<std::pair<double, double>>& parts, bool split) {
  const scene::Model m = soft_block();
  const scene::Body& b = m.bodies.front();
  DeviceChannels channels(16);
  SimulationLoop sim(m, {&channels});
  ContactLoad& load = channels.load.write_buffer();
  load.active = true;
  load.body = 0;
  load.triangle = top_triangle(b, parts.front().first);
  load.barycentric = Vec3::Constant(1.0 / 3.0);
  load.force = Vec3(0, 0, -force);
  load.contact_radius = -1.0;
  if (split)
    for (const auto& [x, share] : parts)
      load.parts[static_cast<std::size_t>(load.part_count++)] = {top_triangle(b, x), Vec3::Constant(1.0 / 3.0), share,
                                                                 -1.0};
  channels.load.publish();
  for (int k = 0; k < 100; ++k) sim.step(k * 0.01, 0, 0, false);
  const VecX& x = *sim.positions(0);
  auto drop_near = [&](double at) {
    double drop = 0.0;
    for (std::size_t v = 0; v < b.surface.vertices.size(); ++v) {
      const Vec3& rest = b.surface.vertices[v];
      if (std::abs(rest.z()) > 1e-9 || std::abs(rest.x() - at) > 0.0101) continue;  // top, within a cell
      const auto node = 3 * static_cast<Eigen::Index>(b.surface_to_volume[v]);
      drop = std::max(drop, rest.z() - x(node + 2));
    }
    return drop;
  };
  return {drop_near(-0.02), drop_near(0.02)};
}

TEST(ContactLoadParts, EachPartDentsTheTissueUnderItAsItsShareAloneWould) {
  // 0.4 N in parts of 0.1 N (left) and 0.3 N (right), against each part's force alone on its
  // own triangle: small strains (the block is 20 mm thick, the dents a few tenths of a mm),
  // so the responses add, and 40 mm apart the two dents barely overlap.
  const auto [left, right] = drops(0.4, {{-0.02, 0.25}, {0.02, 0.75}}, true);
  const auto [left_only, left_only_far] = drops(0.1, {{-0.02, 1.0}}, false);
  const auto [right_only_far, right_only] = drops(0.3, {{0.02, 1.0}}, false);
  std::printf("drops [mm]: parts 0.1 N / 0.3 N: %.4f / %.4f; 0.1 N alone on the left: %.4f (right %.4f); 0.3 N alone "
              "on the right: %.4f (left %.4f)\n",
              1e3 * left, 1e3 * right, 1e3 * left_only, 1e3 * left_only_far, 1e3 * right_only, 1e3 * right_only_far);
  // Each side sinks as its part alone sinks it, to within the little (under 5 % here) the
  // other part adds there. The whole 0.4 N on the left triangle would sink the left about
  // 4 times as far as its 0.1 N part (linear at these depths), far outside the tolerance.
  EXPECT_NEAR(left, left_only, 0.1 * left_only);
  EXPECT_NEAR(right, right_only, 0.1 * right_only);
  EXPECT_LT(right_only_far, 0.2 * right_only);
  EXPECT_LT(left_only_far, 0.2 * left_only);
}

}  // namespace
}  // namespace tactus::runtime
