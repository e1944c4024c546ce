#pragma once
// A configuration space in memory: per grid point its status, the reaction force and torque
// at the interaction point and the nodal displacements, plus what identifies the model it was
// built from.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "core/math.hpp"
#include "precompute/grid.hpp"
#include "precompute/settings.hpp"

namespace tactus::precompute {

enum class PointStatus : std::uint8_t {
  pending = 0,      ///< not computed (yet)
  solved = 1,       ///< converged static equilibrium
  failed = 2,       ///< the transition's solve did not converge (reason recorded)
  unreachable = 3,  ///< every neighbour it could be reached from failed
};
const char* to_string(PointStatus s);

/// The outcome of one configuration (one grid point).
struct PointResult {
  std::size_t point = 0;
  PointStatus status = PointStatus::pending;
  std::int64_t source = -1;  ///< the point it was reached from; -1 for the start point
  int iterations = 0;        ///< Newton iterations over all load steps
  int refinements = 0;       ///< load-step halvings the solve needed (not stored in the file)
  double residual = 0.0;     ///< worst final relative residual of the load steps
  double seconds = 0.0;      ///< wall time of the solve on its worker
  double derivative_seconds = 0.0;  ///< of which the derivatives (not stored in the file)
  Vec3 force = Vec3::Zero(); ///< force the body exerts on the tool [N]
  /// Torque the body exerts on the tool about the interaction point [N·m]: the moment of the
  /// contact patch's reactions (a probe space's probe feels it; a one-node patch has none).
  Vec3 torque = Vec3::Zero();
  std::string reason;        ///< why it failed (empty when solved)
  VecX displacement;         ///< 3N, x − rest (solved points only)
  /// Derivatives with respect to the interaction point's position (solved points only):
  /// column k of each is along axis k. ∂force/∂x is the stiffness the tool feels [N/m].
  Mat3 force_gradient = Mat3::Zero();
  Mat3 torque_gradient = Mat3::Zero();  ///< ∂torque/∂x [N]
  MatX displacement_gradient;  ///< 3N × 3, ∂displacement/∂x
};

/// Identifies the model a space belongs to (docs/precompute.md, "Model identity").
struct ModelIdentity {
  std::uint64_t mesh_hash = 0;   ///< rest positions and elements
  std::uint64_t model_hash = 0;  ///< mesh + material + fixed dofs + contact patch + settings
  std::size_t node_count = 0;
  std::size_t element_count = 0;
};

/// A point or cell of a refinement level: level L's lattice has spacing grid.spacing / 2^L and
/// the grid's origin, so level L's (i, j, k) is level L+1's (2i, 2j, 2k).
struct LatticeIndex {
  std::int32_t level = 0;
  std::array<std::int32_t, 3> ijk{};
  bool operator==(const LatticeIndex&) const = default;
};

struct Space {
  /// Refinement levels below the grid (a cell of level L splits into 8 of level L + 1).
  static constexpr int kMaxLevel = 8;

  Grid grid;
  SpaceSettings settings;
  ModelIdentity identity;
  std::size_t start = 0;  ///< the grid point of the undeformed contact point
  std::string scene_text;  ///< the scene file it was built from (informative)
  VecX rest_positions;     ///< 3N, the mesh it was built on
  std::vector<std::array<std::int32_t, 4>> elements;

  std::vector<PointStatus> status;
  std::vector<Vec3> force;
  std::vector<std::int64_t> source;
  std::vector<std::int32_t> iterations;
  std::vector<double> residual, seconds;
  std::vector<std::string> reason;
  /// Column p: point p's displacement (3N); zero for points not solved.
  Eigen::MatrixXd displacement;
  /// Derivatives with respect to the interaction point (PointResult): per point ∂force/∂x,
  /// and columns 3p..3p+2 of displacement_gradient ∂displacement/∂x. A space read from a file
  /// of version 1 has none (has_gradients false): the Hermite methods then refuse it.
  std::vector<Mat3> force_gradient;
  Eigen::MatrixXd displacement_gradient;
  bool has_gradients = true;
  /// Per point the torque about the interaction point and ∂torque/∂x. A space read from a file
  /// of version 1 or 2 has none (has_torques false).
  std::vector<Vec3> torque;
  std::vector<Mat3> torque_gradient;
  bool has_torques = true;

  /// Adaptive refinement (docs/precompute.md, "Refinement"): points beyond the grid's, at
  /// index grid.size() + r of every per-point array, with refined_points[r] their place; and
  /// the cells split, each into 8 of the next level.
  std::vector<LatticeIndex> refined_points;
  std::vector<LatticeIndex> refined_cells;

  /// Sizes every per-point array for grid.size() points of 3 · node_count dofs, all pending,
  /// with no refinement.
  void allocate(std::size_t node_count);
  void store(const PointResult& r);
  [[nodiscard]] std::size_t count(PointStatus s) const;
  [[nodiscard]] bool solved(std::size_t p) const { return status[p] == PointStatus::solved; }
  /// Points in every per-point array: the grid's and the refinement's.
  [[nodiscard]] std::size_t point_count() const { return status.size(); }

  /// The point at a lattice place (the grid's own where it coincides with a grid point), or
  /// nothing where no point lies there.
  [[nodiscard]] std::optional<std::size_t> find(const LatticeIndex& at) const;
  /// Where point p lies [m] (grid or refinement).
  [[nodiscard]] Vec3 position(std::size_t p) const;
  /// Whether the cell is split into 8 of the next level.
  [[nodiscard]] bool is_refined(const LatticeIndex& cell) const;
  /// Appends a pending point at `at` (which must hold none) and returns its index.
  std::size_t add_point(const LatticeIndex& at);
  /// Marks a cell split (its points are added separately).
  void refine_cell(const LatticeIndex& cell);
  /// Whether a refined point or cell can lie at `at`: not negative, and below 2^21 on the
  /// finest lattice (grids of up to 8,192 points along an axis).
  [[nodiscard]] static bool fits(const LatticeIndex& at);

 private:
  /// Keys of places on the finest lattice (level kMaxLevel): 21 bits per axis.
  [[nodiscard]] static std::uint64_t key(const LatticeIndex& at);
  std::unordered_map<std::uint64_t, std::size_t> refined_lookup_;
  std::array<std::unordered_set<std::uint64_t>, kMaxLevel> cell_lookup_;
};

}  // namespace tactus::precompute
