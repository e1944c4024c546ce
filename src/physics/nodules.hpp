#pragma once
// Spheres under a sheet that its nodes may touch only from outside (seed 004 §5.2 and §5.4):
// a rigid nodule projects a node that entered it back onto its surface; a soft nodule pushes
// it back with the Hertz pressure of its own indentation. Both act after each step, on the
// step's end positions, so they add no term to the body's force model.
#include <cstdint>
#include <vector>

#include "core/math.hpp"

namespace tactus::physics {

/// The point where the ray from `center` through `p` meets the sphere of `radius` about
/// `center`: C + (P − C)·r/‖P − C‖ (seed 004 eq. 8–10 for any centre and radius; r = r_n
/// is its t1, r = r_n + r_p its t2 for the centre of a spherical proxy). A point at the
/// centre itself goes up (+z).
[[nodiscard]] Vec3 project_onto_sphere(const Vec3& p, const Vec3& center, double radius);

/// A local pressure law for a sheet pressed onto an elastic sphere: where the undeformed
/// sheet and sphere overlap by δ the pressure is p = β·√δ with β = E*/(π·√R),
/// E* = E/(1 − ν²). Summed over the overlap of a flat sheet lowered by d it gives exactly
/// Hertz's F = (4/3)·E*·√R·d^(3/2) (docs/scenes.md derives it).
[[nodiscard]] double hertz_pressure_coefficient(double young_modulus, double poisson_ratio, double radius);

struct Nodule {
  Vec3 center = Vec3::Zero();  ///< [m]
  double radius = 0.0;         ///< [m], > 0
  bool rigid = true;
  /// Soft nodules: β of hertz_pressure_coefficient [Pa/√m]; unused when rigid.
  double pressure_coefficient = 0.0;
};

/// The nodules one body rests on, with the area each node stands for (soft nodules turn
/// pressure into a node force with it).
struct NoduleSet {
  std::vector<Nodule> nodules;
  /// Per node [m²]: a third of the area of the triangles around it. Needed only by soft
  /// nodules; may be empty when every nodule is rigid.
  std::vector<double> node_area;

  [[nodiscard]] bool empty() const { return nodules.empty(); }
};

/// Moves every free node that ended a step of length dt inside a nodule back out (a node
/// whose path x − dt·v → x crossed a nodule within the step counts as having stopped at the
/// point of that path deepest in it: a fast node does not tunnel through):
///  - rigid: onto the surface, P' = C + (P − C)·r_n/‖P − C‖, and its inward velocity removed
///    (the nodule takes the impact; nothing bounces);
///  - soft: by the backward-Euler step of the Hertz pressure alone along the outward normal,
///    m Δv = dt·A·β·√δ⁺ with δ⁺ = δ − dt·Δv (solved in closed form; it stays stable however
///    stiff the nodule and tends to the rigid projection as E grows).
/// Fixed dofs (flag per dof, 3N, may be empty) never move. `mass` is the lumped mass (3N).
void enforce_nodules(const NoduleSet& set, const std::vector<std::uint8_t>& fixed_dofs, const VecX& mass, double dt,
                     VecX& x, VecX& v);

/// A moving rigid sphere that pushes nodes but never pulls or drags them (a fingertip on
/// skin, seed 004 §5.1): a node inside it goes to its surface and keeps its tangential
/// velocity; its normal velocity becomes at least the sphere's. Returns the number of nodes
/// moved. For a simulation loop that renders the fingertip geometrically: after each body
/// step, call it with the finger's centre, radius and velocity.
int push_out_of_sphere(const Vec3& center, double radius, const Vec3& velocity,
                       const std::vector<std::uint8_t>& fixed_dofs, VecX& x, VecX& v);

}  // namespace tactus::physics
