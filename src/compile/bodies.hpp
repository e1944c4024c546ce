#pragma once
// Simulation bodies built from a scene's Model: the bridge from scene keys to physics models.
#include <algorithm>
#include <memory>
#include <vector>

#include "physics/body.hpp"
#include "scene/model.hpp"

namespace tactus::compile {

/// The physics body of scene body `index`: its force model (FEM, tetrahedral or surface
/// mass-spring, per the body's kind and material), fixed and prescribed nodes as fixed
/// dofs, gravity and step settings. Throws InputError for a rigid body or a combination the
/// physics cannot run (named in the message).
physics::Body make_physics_body(const scene::Model& model, std::size_t index);

/// Deformed positions of the body's mapped surfaces (scene::Body::mapped, in that order) for
/// node positions x (3N, a BodyState's x): out[i] receives the vertices of mapped surface i,
/// with the triangles of b.mapped[i].mesh. Allocates nothing once out is sized.
void mapped_surface_positions(const scene::Body& b, const VecX& x, std::vector<std::vector<Vec3>>& out);

/// node_forces (3N) += the forces on mapped surface `index`'s vertices carried to the body's
/// nodes by the transpose of its mapping (the same virtual work). Throws std::out_of_range
/// for a bad index.
void add_mapped_surface_forces(const scene::Body& b, std::size_t index, const std::vector<Vec3>& vertex_forces,
                               VecX& node_forces);

/// Linear ramp from 0 at t = 0 to 1 at ramp_time (a step when ramp_time is 0).
inline double ramp(double t, double ramp_time) { return ramp_time > 0.0 ? std::min(1.0, t / ramp_time) : 1.0; }

/// External forces of the body's loads into f (3N, zeroed first); `fraction(ramp_time)` is
/// how much of each load applies (a ramp in time, or a load step of a static solve).
template <class Fraction>
void assemble_loads(const scene::Body& b, Fraction fraction, VecX& f) {
  f.setZero();
  for (const auto& load : b.loads) {
    const Vec3 per_node = fraction(load.ramp_time) * load.force / static_cast<double>(load.nodes.size());
    for (auto n : load.nodes) f.segment<3>(3 * n) += per_node;
  }
}

/// Places the prescribed nodes at rest + fraction · displacement.
template <class Fraction>
void place_prescribed(const scene::Body& b, const VecX& rest, Fraction fraction, VecX& x) {
  for (const auto& p : b.prescribed) {
    const Vec3 d = fraction(p.ramp_time) * p.displacement;
    for (auto n : p.nodes) x.segment<3>(3 * n) = rest.segment<3>(3 * n) + d;
  }
}

}  // namespace tactus::compile
