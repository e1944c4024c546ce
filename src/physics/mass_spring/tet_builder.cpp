#include "physics/mass_spring/tet_builder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include "core/error.hpp"

namespace tactus::physics {

std::shared_ptr<SpringNetwork> tet_mass_spring(const mesh::TetMesh& m, const TetSpringParams& p) {
  if (!(p.youngs_modulus > 0.0 && std::isfinite(p.youngs_modulus)))
    throw InputError("tet mass-spring: Young's modulus must be positive");
  if (!(p.density > 0.0 && std::isfinite(p.density))) throw InputError("tet mass-spring: density must be positive");
  if (!(p.damping_per_mass >= 0.0 && std::isfinite(p.damping_per_mass)))
    throw InputError("tet mass-spring: damping must be >= 0");
  p.viscoelastic.validate();
  const auto n = static_cast<std::int64_t>(m.vertices.size());
  VecX rest(3 * n), mass = VecX::Zero(n);
  for (std::int64_t i = 0; i < n; ++i) rest.segment<3>(3 * i) = m.vertices[static_cast<std::size_t>(i)];

  // (edge key, volume of one tet holding it); sorted and merged below.
  std::vector<std::pair<std::uint64_t, double>> edge_volume;
  edge_volume.reserve(6 * m.tets.size());
  constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const auto& tet = m.tets[t];
    for (auto v : tet)
      if (v < 0 || v >= n) throw InputError("tet mass-spring: tet " + std::to_string(t) + " refers to a missing vertex");
    const double vol = m.tet_volume(t);
    if (!(vol > 0.0)) throw InputError("tet mass-spring: tet " + std::to_string(t) + " is inverted or flat");
    for (auto v : tet) mass[v] += p.density * vol / 4.0;
    for (const auto& e : kEdges) {
      const auto a = static_cast<std::uint64_t>(std::min(tet[e[0]], tet[e[1]]));
      const auto b = static_cast<std::uint64_t>(std::max(tet[e[0]], tet[e[1]]));
      edge_volume.emplace_back((a << 32) | b, vol);
    }
  }
  for (std::int64_t i = 0; i < n; ++i)
    if (!(mass[i] > 0.0)) throw InputError("tet mass-spring: vertex " + std::to_string(i) + " is in no tet");
  std::sort(edge_volume.begin(), edge_volume.end());

  auto net = std::make_shared<SpringNetwork>(std::move(rest), mass, p.options);
  for (std::int64_t i = 0; i < n; ++i) net->set_nodal_damping(static_cast<std::int32_t>(i), p.damping_per_mass * mass[i]);
  std::vector<SpringArm> arms;
  for (std::size_t k = 0; k < edge_volume.size();) {
    const std::uint64_t edge = edge_volume[k].first;
    double volume = 0.0;
    for (; k < edge_volume.size() && edge_volume[k].first == edge; ++k) volume += edge_volume[k].second;
    const auto a = static_cast<std::int32_t>(edge >> 32), b = static_cast<std::int32_t>(edge & 0xffffffffu);
    const double l = (m.vertices[static_cast<std::size_t>(b)] - m.vertices[static_cast<std::size_t>(a)]).norm();
    const double stiffness = p.youngs_modulus * volume / (l * l);  // Van Gelder 1998
    arms.clear();
    for (const auto& arm : p.viscoelastic.arms) arms.push_back({arm.ratio * stiffness, arm.ratio * stiffness * arm.tau});
    net->add_spring(a, b, stiffness, p.viscoelastic.kelvin_voigt_tau * stiffness, arms);
  }
  return net;
}

}  // namespace tactus::physics
