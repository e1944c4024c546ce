#include "physics/mass_spring/surface_builder.hpp"

#include <algorithm>
#include <cstdint>
#include <map>
#include <set>
#include <span>
#include <utility>

#include "core/error.hpp"

namespace tactus::physics {
namespace {

using Edge = std::pair<std::int32_t, std::int32_t>;
Edge key(std::int32_t a, std::int32_t b) { return a < b ? Edge{a, b} : Edge{b, a}; }

/// Faces as vertex loops (3 or 4 vertices, counter-clockwise).
template <std::size_t K>
std::shared_ptr<SpringNetwork> build(const std::vector<Vec3>& vertices, const std::vector<std::array<mesh::Index, K>>& faces,
                                     const SurfaceSpringParams& p) {
  p.viscoelastic.validate();
  const auto n = static_cast<Eigen::Index>(vertices.size());
  for (const auto& f : faces)
    for (auto v : f)
      if (v < 0 || v >= n) throw InputError("surface mass-spring: face refers to a missing vertex");
  VecX rest(3 * n), mass = VecX::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) rest.segment<3>(3 * i) = vertices[static_cast<std::size_t>(i)];
  if (p.node_mass > 0.0) {
    mass.setConstant(p.node_mass);
  } else {
    if (!(p.areal_density > 0.0)) throw InputError("surface mass-spring: need node_mass or areal_density > 0");
    for (const auto& f : faces) {
      // Area of a planar polygon from its fan (exact for triangles and planar quads).
      double area = 0.0;
      for (std::size_t k = 1; k + 1 < K; ++k)
        area += 0.5 * (vertices[f[k]] - vertices[f[0]]).cross(vertices[f[k + 1]] - vertices[f[0]]).norm();
      for (auto v : f) mass[v] += p.areal_density * area / static_cast<double>(K);
    }
    for (Eigen::Index i = 0; i < n; ++i)
      if (!(mass[i] > 0.0)) throw InputError("surface mass-spring: vertex " + std::to_string(i) + " is in no face");
  }
  auto net = std::make_shared<SpringNetwork>(std::move(rest), mass, p.options);
  for (Eigen::Index i = 0; i < n; ++i) net->set_nodal_damping(static_cast<std::int32_t>(i), p.nodal_damping);

  const auto add = [&](std::int32_t a, std::int32_t b, double k) {
    std::vector<SpringArm> arms;
    for (const auto& arm : p.viscoelastic.arms) arms.push_back({arm.ratio * k, arm.ratio * k * arm.tau});
    net->add_spring(a, b, k, p.viscoelastic.kelvin_voigt_tau * k, arms);
  };

  // Edges, in first-seen order, with the faces on each side (for bending).
  std::map<Edge, std::vector<std::pair<std::size_t, std::size_t>>> edge_faces;  // (face, local edge)
  std::vector<Edge> edges;
  for (std::size_t fi = 0; fi < faces.size(); ++fi)
    for (std::size_t k = 0; k < K; ++k) {
      const Edge e = key(faces[fi][k], faces[fi][(k + 1) % K]);
      auto& list = edge_faces[e];
      if (list.empty()) edges.push_back(e);
      list.emplace_back(fi, k);
    }
  if (p.longitudinal)
    for (const auto& e : edges) add(e.first, e.second, p.longitudinal_stiffness);
  if constexpr (K == 4) {
    if (p.diagonal)
      for (const auto& f : faces) {
        add(f[0], f[2], p.diagonal_stiffness);
        add(f[1], f[3], p.diagonal_stiffness);
      }
  }
  if (p.torsional)
    for (const auto& f : faces)
      for (std::size_t k = 0; k < K; ++k) net->add_angle(f[(k + K - 1) % K], f[k], f[(k + 1) % K], p.torsional_stiffness);
  if (p.bending) {
    std::set<Edge> added;
    const auto add_once = [&](std::int32_t a, std::int32_t b) {
      if (a != b && added.insert(key(a, b)).second) add(a, b, p.bending_stiffness);
    };
    for (const auto& [e, list] : edge_faces) {
      if (list.size() != 2) continue;  // boundary or non-manifold edge
      const auto& [f0, k0] = list[0];
      const auto& [f1, k1] = list[1];
      const auto& a = faces[f0];
      const auto& b = faces[f1];
      if constexpr (K == 3) {
        add_once(a[(k0 + 2) % 3], b[(k1 + 2) % 3]);  // the two vertices opposite the edge
      } else {
        // Shared edge (s0, s1) = (a[k0], a[k0+1]); in face a the neighbour of s0 off the edge is
        // a[k0−1], of s1 is a[k0+2]. The skip-one spring runs across the edge through s0.
        for (int side = 0; side < 2; ++side) {
          const std::int32_t s = a[(k0 + static_cast<std::size_t>(side)) % 4];
          const std::int32_t in_a = side == 0 ? a[(k0 + 3) % 4] : a[(k0 + 2) % 4];
          std::int32_t in_b = -1;
          for (std::size_t m = 0; m < 4; ++m)
            if (b[m] == s) in_b = b[(m + 1) % 4] == (side == 0 ? a[(k0 + 1) % 4] : a[k0]) ? b[(m + 3) % 4] : b[(m + 1) % 4];
          if (in_b >= 0) add_once(in_a, in_b);
        }
      }
    }
  }
  return net;
}

}  // namespace

SurfaceSpringParams skin_seed004(double stiffness, double damping, double node_mass) {
  SurfaceSpringParams p;
  p.longitudinal = true;
  p.longitudinal_stiffness = stiffness;
  p.diagonal = p.torsional = p.bending = false;
  p.node_mass = node_mass;
  p.nodal_damping = damping;
  return p;
}

std::shared_ptr<SpringNetwork> surface_mass_spring(const mesh::QuadMesh& m, const SurfaceSpringParams& p) {
  return build<4>(m.vertices, m.quads, p);
}

std::shared_ptr<SpringNetwork> surface_mass_spring(const mesh::TriMesh& m, const SurfaceSpringParams& p) {
  return build<3>(m.vertices, m.triangles, p);
}

}  // namespace tactus::physics
