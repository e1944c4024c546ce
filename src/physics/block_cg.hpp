#pragma once
// Conjugate gradients on an assembled block system (ForceModel::assemble_system), with a
// symmetric block Gauss-Seidel preconditioner whose sweeps run in node ranges side by side.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/math.hpp"
#include "physics/force_model.hpp"

namespace tactus::physics {

/// What solve_block_cg keeps between calls: sized on the first call for a system (or when
/// its pattern changes), so the calls after it allocate nothing.
struct BlockCgScratch {
  std::size_t ranges = 0;  ///< node ranges to sweep in; 0: block_cg_ranges(nodes)
  VecX residual, rhat, z, p, t, u, lower;
  std::vector<Mat3> diagonal, inverse;  ///< node blocks (fixed dofs decoupled) and their inverses
  /// The node ranges: range r is [bound[r], bound[r + 1]).
  std::vector<Eigen::Index> bound;
  /// Upper blocks into a node from rows of earlier ranges: node j's from cross_start[j] to
  /// cross_start[j + 1], each its block index and its row.
  std::vector<std::int32_t> cross_start, cross_block, cross_row;
  /// The separator (nodes with a block to a later range; none with one range) and each range's
  /// interior (its other nodes: range r's from interior_start[r] to interior_start[r + 1]),
  /// in node order. The interiors of two ranges share no block.
  std::vector<char> in_separator;
  std::vector<std::int32_t> separator, interior, interior_start;
  /// Upper blocks into a node from rows on the other side of the separator (as cross_*).
  std::vector<std::int32_t> across_start, across_block, across_row;
  std::vector<double> partial_rr, partial_rz, partial_pbp;  ///< per range: the dot products' partial sums
  std::vector<char> range_ok;                ///< per range: its node blocks were invertible
  const void* pattern = nullptr;             ///< the row_start array these were built for
  std::size_t pattern_blocks = 0;
};

/// How many node ranges a system of `nodes` nodes is swept in: 1 below 2,048 nodes, 2 below
/// 32,768, 4 below 131,072, then 8. It depends on the system alone, not on the threads, so the
/// result is the same bits on any number of threads.
[[nodiscard]] std::size_t block_cg_ranges(std::size_t nodes);

/// Solves A x = rhs on the dofs where free_mask is 1 (x is 0 on the others) to
/// ‖rhs − A x‖ ≤ tolerance ‖rhs‖, warm started from x. Returns the iterations, or -1 where a
/// node block is not positive definite (x then holds the masked start).
///
/// Preconditioner: symmetric block Gauss-Seidel, M = W D⁻¹ Wᵀ with W = D + L, D the node blocks
/// and L the blocks below them in the sweeps' order: the separator first (the nodes with a
/// block into a later range, in node order), then each range's interior (in node order). Two
/// interiors share no block, so after the separator (one thread) each interior is swept by
/// its own thread; with one range this is the natural order. Eisenstat's trick (1981) saves
/// the product with A: CG on W⁻¹ A W⁻ᵀ preconditioned by D⁻¹ has the same iterates, at the
/// cost of one backward and one forward sweep. The residual of A that decides convergence is
/// kept alongside. The dot products are summed range by range in order.
int solve_block_cg(const BlockMatrix& A, const VecX& free_mask, double tolerance, int max_iterations, const VecX& rhs,
                   VecX& x, BlockCgScratch& w);

}  // namespace tactus::physics
