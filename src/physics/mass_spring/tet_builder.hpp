#pragma once
// Volumetric tetrahedral mass-spring (seed 000 §3.3, eq. 9–10): springs along the unique
// tetrahedron edges, masses lumped from density, nodal damping d_i u̇_i, and optional
// viscoelastic dashpots and Maxwell arms on every spring.
#include <memory>

#include "mesh/tet_mesh.hpp"
#include "physics/mass_spring/spring_network.hpp"
#include "physics/mass_spring/viscoelastic.hpp"

namespace tactus::physics {

struct TetSpringParams {
  /// Long-term Young's modulus E∞ [Pa]. Each edge gets k = E Σ V_t / l² over the tets t
  /// that share it (Van Gelder 1998). A spring network has Poisson ratio 1/4 at best
  /// (Cauchy's relation), so no Poisson ratio is taken.
  double youngs_modulus = 10e3;
  double density = 1000.0;  ///< [kg/m³]; node mass = Σ ρ V_t / 4 over its tets
  /// Mass-proportional nodal damping α [1/s]: d_i = α m_i, so every node's velocity decays
  /// with the same time 1/α whatever the mesh size.
  double damping_per_mass = 0.0;
  ViscoelasticParams viscoelastic;  ///< times relative to each spring's own stiffness
  SpringNetworkOptions options;
};

std::shared_ptr<SpringNetwork> tet_mass_spring(const mesh::TetMesh& mesh, const TetSpringParams& params);

}  // namespace tactus::physics
