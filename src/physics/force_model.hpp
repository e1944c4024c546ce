#pragma once
// The contract between a deformable model and the integrators: internal forces, their
// derivatives and the masses. A ForceModel is immutable; everything that changes during a
// simulation (positions, velocities, internal variables, linearization caches) lives in
// BodyState and the model's Scratch.
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "core/math.hpp"

namespace tactus::physics {

using Triplet = Eigen::Triplet<double>;
using SparseMatrix = Eigen::SparseMatrix<double>;

/// Per-state buffers a model needs (element rotations, cached stiffness blocks...).
struct Scratch {
  virtual ~Scratch() = default;
};

class ForceModel {
 public:
  virtual ~ForceModel() = default;

  [[nodiscard]] virtual std::size_t node_count() const = 0;
  /// Rest positions, 3N (x0 y0 z0 x1 ...).
  [[nodiscard]] virtual const VecX& rest_positions() const = 0;
  /// Lumped mass per degree of freedom, 3N.
  [[nodiscard]] virtual const VecX& lumped_mass() const = 0;
  /// Number of internal variables (viscoelastic history); they start at zero.
  [[nodiscard]] virtual std::size_t internal_size() const { return 0; }
  [[nodiscard]] virtual std::unique_ptr<Scratch> make_scratch() const {
    return std::make_unique<Scratch>();
  }

  /// Internal force f(x, v, q): elastic and viscous, without gravity or external loads.
  /// f has size 3N on entry; the model overwrites it.
  virtual void forces(const VecX& x, const VecX& v, const VecX& q, VecX& f, Scratch& s) const = 0;

  /// Prepares K = -df/dx and D = -df/dv at (x, v, q) for the products below.
  virtual void linearize(const VecX& x, const VecX& v, const VecX& q, Scratch& s) const = 0;
  /// out += K dx (after linearize).
  virtual void add_stiffness_product(const VecX& dx, VecX& out, const Scratch& s) const = 0;
  /// out += D dv (after linearize). Default: no velocity dependence.
  virtual void add_damping_product(const VecX& dv, VecX& out, const Scratch& s) const;
  /// out += (a·M + b·D + c·K) in (after linearize), M the lumped mass: the system product of
  /// implicit steps and static solves, once per CG iteration. Default: the mass term plus
  /// the two products above; models override it to make one pass over their elements.
  virtual void add_system_product(double a_mass, double b_damping, double c_stiffness, const VecX& in, VecX& out,
                                  const Scratch& s) const;
  /// out += diag(K) and diag(D) scaled: out += a·diag(K) + b·diag(D); for preconditioning.
  virtual void add_diagonal(double a, double b, VecX& out, const Scratch& s) const = 0;
  /// Appends a·K + b·D as triplets (after linearize), for direct solvers.
  virtual void add_triplets(double a, double b, std::vector<Triplet>& out, const Scratch& s) const = 0;

  /// Advances internal variables over a step of length dt that ended at x (for instance the
  /// dashpot elongations of standard-linear-solid springs). Default: none.
  virtual void update_internal(const VecX& x, double dt, VecX& q, Scratch& s) const;

  /// Stored elastic energy at x (with internal variables q).
  [[nodiscard]] virtual double elastic_energy(const VecX& x, const VecX& q) const = 0;
};

}  // namespace tactus::physics
