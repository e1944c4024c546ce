#pragma once
// Shared helpers for the FEM tests: meshes, node selections and homogeneous deformations.
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "mesh/generators.hpp"
#include "physics/body.hpp"
#include "physics/fem/tet_fem.hpp"

namespace tactus::physics::fem_test {

inline FemMaterial material(FemLaw law, double E = 1e6, double nu = 0.3, double rho = 1000.0) {
  FemMaterial m;
  m.law = law;
  m.young_modulus = E;
  m.poisson_ratio = nu;
  m.density = rho;
  return m;
}

inline const std::vector<FemLaw>& all_laws() {
  static const std::vector<FemLaw> laws{FemLaw::linear, FemLaw::corotational, FemLaw::stvk, FemLaw::neo_hookean,
                                        FemLaw::mooney_rivlin};
  return laws;
}

/// One reference tetrahedron, deliberately not axis-aligned.
inline mesh::TetMesh single_tet() {
  mesh::TetMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(0.01, 0.001, 0.0), Vec3(0.002, 0.012, 0.001), Vec3(0.001, 0.002, 0.011)};
  m.tets = {{0, 1, 2, 3}};
  return m;
}

/// Nodes whose coordinate `axis` is within 1e-9 of `value`.
inline std::vector<std::int32_t> nodes_at(const mesh::TetMesh& m, int axis, double value) {
  std::vector<std::int32_t> out;
  for (std::size_t i = 0; i < m.vertices.size(); ++i)
    if (std::abs(m.vertices[i][axis] - value) < 1e-9) out.push_back(static_cast<std::int32_t>(i));
  return out;
}

/// x = F X + t applied to every rest position.
inline VecX deformed(const VecX& rest, const Mat3& F, const Vec3& t = Vec3::Zero()) {
  VecX x(rest.size());
  for (Eigen::Index i = 0; i < rest.size(); i += 3) x.segment<3>(i) = F * rest.segment<3>(i) + t;
  return x;
}

inline Mat3 rotation(double angle, const Vec3& axis) { return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix(); }

}  // namespace tactus::physics::fem_test
