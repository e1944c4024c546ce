#pragma once
// Adaptive refinement of a built configuration space: where the force–position map bends
// most, a cell is split into 8 of half the spacing and the new points are solved, within a
// budget of points. The tricubic Hermite interpolator then queries the finest cell holding
// the interaction point (docs/precompute.md, "Refinement").
#include <cstddef>
#include <functional>

#include "precompute/builder.hpp"

namespace tactus::precompute {

struct RefineOptions {
  std::size_t points = 0;  ///< budget: at most this many new points
  unsigned threads = 1;
  /// Every new outcome, in the order solved.
  std::function<void(const PointResult&)> on_result;
};

struct RefineStats {
  std::size_t cells = 0;   ///< cells split
  std::size_t points = 0;  ///< points added (solved or not)
  std::size_t failed = 0;  ///< of those, not solved
  double wall_seconds = 0.0;
};

/// Splits cells of `space` (built, with derivatives), largest error first, until the next
/// split would exceed the budget or no cell with solved corners is left. The error: an
/// estimate (Interpolator::cell_disagreement, the tricubic Hermite force at the centre against
/// the corners' mean) ranks the cells; the first budget/5 of them (fewer where a split could
/// not follow) have their centre solved and are ranked first, by how far the tricubic
/// Hermite misses it. Each new point is reached by a transition from a solved neighbour half a
/// parent spacing away (a probed centre from the cell's lowest corner). Deterministic: the
/// same space and budget give the same points on any number of threads.
RefineStats refine_local(Space& space, const SolverFactory& make_solver, const RefineOptions& options);

}  // namespace tactus::precompute
