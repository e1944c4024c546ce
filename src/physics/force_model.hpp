#pragma once
// The contract between a deformable model and the integrators: internal forces, their
// derivatives and the masses. A ForceModel is immutable; everything that changes during a
// simulation (positions, velocities, internal variables, linearization caches) lives in
// BodyState and the model's Scratch.
#include <Eigen/SparseCore>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/math.hpp"

namespace tactus::physics {

using Triplet = Eigen::Triplet<double>;
using SparseMatrix = Eigen::SparseMatrix<double>;

/// Per-state buffers a model needs (element rotations, cached stiffness blocks...).
struct Scratch {
  virtual ~Scratch() = default;
};

/// A symmetric matrix of 3x3 node blocks: the diagonal blocks and, row by row, the nonzero
/// blocks above the diagonal (block compressed sparse rows). Models that assemble their system
/// matrix fill one (ForceModel::assemble_system) and the integrator solves with it.
struct BlockMatrix {
  std::vector<Mat3> diagonal;           ///< one per node
  std::vector<std::int32_t> row_start;  ///< row i's upper blocks: [row_start[i], row_start[i + 1])
  std::vector<std::int32_t> column;     ///< each upper block's column (above its row)
  std::vector<Mat3> upper;              ///< the upper blocks
  /// Node ranges the block CG sweeps in (physics/block_cg.hpp), where the model knows better
  /// than the size rule; 0: block_cg_ranges(nodes). A property of the system, never of the
  /// threads, so the answer is the same bits on any number of them.
  std::size_t sweep_ranges = 0;
};

class ForceModel {
 public:
  virtual ~ForceModel() = default;

  [[nodiscard]] virtual std::size_t node_count() const = 0;
  /// Rest positions, 3N (x0 y0 z0 x1 ...).
  [[nodiscard]] virtual const VecX& rest_positions() const = 0;
  /// Lumped mass per degree of freedom, 3N. Its row sums equal those of the mass matrix M
  /// below, so weight (M·g) and the total mass are the same with either.
  [[nodiscard]] virtual const VecX& lumped_mass() const = 0;
  /// Whether M is the lumped (diagonal) one. Explicit integrators need M^-1 f and run only
  /// with a diagonal M.
  [[nodiscard]] virtual bool mass_is_diagonal() const { return true; }
  /// out += scale·M·in with the model's mass matrix M (default: the lumped one).
  virtual void add_mass_product(double scale, const VecX& in, VecX& out) const;
  /// Appends scale·M as triplets (default: the lumped diagonal), for direct solvers.
  virtual void add_mass_triplets(double scale, std::vector<Triplet>& out) const;
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
  /// Like linearize, but with the exact tangent where linearize would make it positive
  /// semi-definite (hyperelastic laws). Returns false, having done nothing, where the two do
  /// not differ. The exact K may be indefinite: only for solvers that detect it (Cholesky).
  virtual bool linearize_exact(const VecX& x, const VecX& v, const VecX& q, Scratch& s) const;
  /// out += K dx (after linearize).
  virtual void add_stiffness_product(const VecX& dx, VecX& out, const Scratch& s) const = 0;
  /// out += D dv (after linearize). Default: no velocity dependence.
  virtual void add_damping_product(const VecX& dv, VecX& out, const Scratch& s) const;
  /// out += (a·M + b·D + c·K) in (after linearize), M the mass matrix: the system product of
  /// implicit steps and static solves, once per CG iteration. Default: the mass term plus
  /// the two products above; models override it to make one pass over their elements.
  virtual void add_system_product(double a_mass, double b_damping, double c_stiffness, const VecX& in, VecX& out,
                                  const Scratch& s) const;
  /// out += diag(K) and diag(D) scaled: out += a·diag(K) + b·diag(D); for preconditioning.
  virtual void add_diagonal(double a, double b, VecX& out, const Scratch& s) const = 0;
  /// Assembles a·M + b·D + c·K (after linearize) into a block matrix kept in s until the next
  /// call, and returns it. Returns nullptr where the model does not assemble (the default): the
  /// integrator then solves with add_system_product and add_diagonal.
  virtual const BlockMatrix* assemble_system(double a, double b, double c, Scratch& s) const;
  /// f = forces(x, v, q) + K dx with K linearized at (x, v, q): linearize() and the force and
  /// product of a linearized implicit step in one call. f has size 3N on entry. Default: the
  /// three calls; models override it to make one pass over their elements.
  virtual void linearized_forces(const VecX& x, const VecX& v, const VecX& q, const VecX& dx, VecX& f,
                                 Scratch& s) const;
  /// Appends a·K + b·D as triplets (after linearize), for direct solvers.
  virtual void add_triplets(double a, double b, std::vector<Triplet>& out, const Scratch& s) const = 0;
  /// For models whose triplets keep their number, order and places from call to call (a
  /// pattern fixed at construction): adds the values that add_triplets(a, b) and then, where
  /// mass != 0, add_mass_triplets(mass) would append, the k-th into values[slots[k]] (none
  /// where slots[k] < 0). Direct solvers reassemble a matrix of known pattern this way
  /// without building triplets. Returns false, having done nothing, where the model does not
  /// offer it (the default) or slots has not one entry per triplet.
  virtual bool add_matrix_values(double a, double b, double mass, std::span<const std::int32_t> slots, double* values,
                                 const Scratch& s) const;

  /// Advances internal variables over a step of length dt that ended at x (for instance the
  /// dashpot elongations of standard-linear-solid springs). Default: none.
  virtual void update_internal(const VecX& x, double dt, VecX& q, Scratch& s) const;

  /// Stored elastic energy at x (with internal variables q).
  [[nodiscard]] virtual double elastic_energy(const VecX& x, const VecX& q) const = 0;

  /// The smallest volume ratio J = det F over the model's elements at x, where a step that
  /// turns an element inside out (J ≤ 0) cannot be trusted: hyperelastic tetrahedra. Default:
  /// +infinity (no such elements, or laws that take inversion in their stride).
  [[nodiscard]] virtual double min_volume_ratio(const VecX& x) const;
};

}  // namespace tactus::physics
