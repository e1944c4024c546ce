#pragma once
// Surface mass-spring sheets (seed 004 §4.2): longitudinal springs on the mesh edges,
// diagonal springs across quads (transversal resistance), "torsional" angle terms that hold
// the corner angles between longitudinal springs, optional skip-one bending springs, and
// velocity damping (the paper's "dumping").
#include <memory>

#include "mesh/generators.hpp"
#include "physics/mass_spring/spring_network.hpp"
#include "physics/mass_spring/viscoelastic.hpp"

namespace tactus::physics {

struct SurfaceSpringParams {
  bool longitudinal = true;
  double longitudinal_stiffness = 50.0;  ///< K_m of seed 004 eq. 3 [N/m]
  bool diagonal = false;                 ///< quads only: both diagonals of each quad
  double diagonal_stiffness = 25.0;      ///< [N/m]
  bool torsional = false;                ///< corner angle terms of every face
  double torsional_stiffness = 0.01;     ///< [N·m/rad²]
  /// Skip-one bending springs: across each interior edge, between the two vertices that sit
  /// opposite it (triangles) or between the grid neighbours on either side of it (quads).
  bool bending = false;
  double bending_stiffness = 5.0;  ///< [N/m]
  /// Node mass [kg]; when 0, masses are lumped from areal_density (face area shared equally
  /// among its corners).
  double node_mass = 0.0;
  double areal_density = 1.0;  ///< [kg/m²]
  double nodal_damping = 0.0;  ///< k_d of seed 004 eq. 3: f = −k_d v_i [N·s/m]
  /// Kelvin–Voigt dashpots and Maxwell arms on every spring (times relative to each
  /// spring's own stiffness).
  ViscoelasticParams viscoelastic;
  SpringNetworkOptions options;
};

/// The skin model built in seed 004 §4.2.1: longitudinal springs on the quad edges and
/// velocity damping, nothing else. The paper gives no numbers; these defaults are a
/// 1 mm-scale sheet that settles without oscillation (damping ratio above 1 per node).
SurfaceSpringParams skin_seed004(double stiffness = 50.0, double damping = 0.5, double node_mass = 1e-3);

std::shared_ptr<SpringNetwork> surface_mass_spring(const mesh::QuadMesh& mesh, const SurfaceSpringParams& params);
/// Triangle sheets: diagonal springs do not apply (the edges already triangulate).
std::shared_ptr<SpringNetwork> surface_mass_spring(const mesh::TriMesh& mesh, const SurfaceSpringParams& params);

}  // namespace tactus::physics
