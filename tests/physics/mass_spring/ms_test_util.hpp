#pragma once
// Shared fixtures of the mass-spring tests.
#include <cstdint>
#include <random>
#include <vector>

#include "core/error.hpp"
#include "mesh/generators.hpp"
#include "physics/body.hpp"
#include "physics/mass_spring/spring_network.hpp"

namespace tactus::physics::test {

/// Nodes whose coordinate `axis` equals `value` (to 1e-12).
inline std::vector<std::int32_t> nodes_at(const VecX& rest, int axis, double value) {
  std::vector<std::int32_t> out;
  for (Eigen::Index n = 0; 3 * n < rest.size(); ++n)
    if (std::abs(rest[3 * n + axis] - value) < 1e-12) out.push_back(static_cast<std::int32_t>(n));
  return out;
}

inline VecX random_vector(Eigen::Index n, unsigned seed, double scale = 1.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-scale, scale);
  VecX v(n);
  for (auto& x : v) x = u(rng);
  return v;
}

/// Σ over nodes of the internal force component `axis`: minus the reaction those nodes need.
inline double force_sum(const ForceModel& m, const BodyState& s, const std::vector<std::int32_t>& nodes, int axis) {
  VecX f;
  m.forces(s.x, s.v, s.q, f, *s.model_scratch);
  double sum = 0.0;
  for (auto n : nodes) sum += f[3 * n + axis];
  return sum;
}

}  // namespace tactus::physics::test
