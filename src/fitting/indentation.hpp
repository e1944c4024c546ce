#pragma once
// The forward model of an indentation experiment, simulated with the engine itself: the
// specimen as a TetFem body, its bottom held, the indenter pressed as prescribed
// displacements of the nodes it touches, load stepping through the depths with
// physics::predict_static and physics::solve_static, and the force read as the reaction on
// those nodes.
//  - flat punch of radius a: the top nodes within a of the axis move with the punch
//    (bonded: no slip under the punch);
//  - sphere of radius R, a fingertip's too: frictionless contact by an active set: the top
//    nodes the sphere reaches are projected onto it (z held, x and y free); nodes the body
//    pulls into the sphere (a tensile reaction) are released and nodes that end inside it
//    are added, until the set stops changing. A finger's own elasticity or its pad then
//    shares the depth (IndentationModel::curve).
// A relaxation curve is the hereditary integral of the elastic force along the ramp; a creep
// curve inverts that integral for the held force (docs/fitting.md, "Relaxation and creep").
#include <memory>
#include <span>
#include <vector>

#include "fitting/experiment.hpp"
#include "mesh/tet_mesh.hpp"
#include "physics/fem/material.hpp"

namespace tactus::fitting {

class IndentationModel {
 public:
  /// Builds or reads the specimen mesh. InputError for a mesh file that cannot be read or
  /// whose top face the indenter does not reach.
  explicit IndentationModel(const Experiment& experiment);

  /// The force [N] on the indenter at each depth [m] (increasing, > 0), pressed in that
  /// order from rest. Throws std::runtime_error when a static solve fails.
  [[nodiscard]] std::vector<double> forces(const physics::FemMaterial& material, std::span<const double> depths) const;

  /// The curve the experiment measured, at its abscissae: force at each depth (depth,force),
  /// force at each time (time,force) or depth at each time (time,depth) for the material's
  /// Prony series.
  [[nodiscard]] std::vector<double> curve(const physics::FemMaterial& material) const;

  [[nodiscard]] const mesh::TetMesh& mesh() const { return mesh_; }
  /// The depth the indenter is pressed to at time t of a relaxation's ramp and hold.
  [[nodiscard]] double hold_depth(double t) const;

 private:
  /// Creep: the elastic force history hereditary_creep gives, turned into depths through the
  /// elastic curve pressed up to the force the creep tends to.
  [[nodiscard]] std::vector<double> creep(const physics::FemMaterial& material) const;
  /// A loading curve under a finger (Hertz's two bodies) or a fingerpad (in series).
  [[nodiscard]] std::vector<double> finger_forces(const physics::FemMaterial& material) const;
  [[nodiscard]] std::vector<double> fingerpad_forces(const physics::FemMaterial& material) const;

  const Experiment* experiment_;
  mesh::TetMesh mesh_;
  Vec3 top_centre_ = Vec3::Zero();  ///< the point of the top face on the indenter's axis
  std::vector<std::int32_t> top_nodes_, bottom_nodes_;
};

/// Ramp-and-hold relaxation by Boltzmann's hereditary integral: the force F_e(d) of an
/// elastic material with the instantaneous modulus, relaxed by the normalized Prony modulus
/// g(s) = g_inf + Σ g_i exp(−s/τ_i): F(t) = Σ_k g(t − t_k) ΔF_e,k over the ramp's steps
/// (their midpoints t_k). `ramp_forces` are F_e at the depths of `ramp_times` (the ramp's
/// step ends, from t = 0 at depth 0 excluded).
std::vector<double> hereditary_relaxation(const std::vector<physics::PronyTerm>& prony, std::span<const double> ramp_times,
                                          std::span<const double> ramp_forces, std::span<const double> times);

/// Ramp-and-hold creep, the same integral solved for the elastic force: under a force ramped
/// linearly to `force` over `ramp_time` (0: a step) and held, the elastic force history
/// φ(t) = F_e(d(t)) with F(t) = Σ_k g(t − m_k) Δφ_k (steps' midpoints m_k, steps of at most a
/// fiftieth of the shortest τ), at `times`. For a linear elastic curve F_e = k d this is
/// k d(t) = F J(t), J the normalized creep compliance.
std::vector<double> hereditary_creep(const std::vector<physics::PronyTerm>& prony, double force, double ramp_time,
                                     std::span<const double> times);

}  // namespace tactus::fitting
