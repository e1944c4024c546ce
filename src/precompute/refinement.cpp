#include "precompute/refinement.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <memory>
#include <thread>
#include <vector>

#include "precompute/interpolator.hpp"

namespace tactus::precompute {

namespace {

struct Candidate {
  double indicator = 0.0;
  LatticeIndex cell;
  bool probed = false;  ///< the indicator is the miss at the solved centre, not the estimate
};

/// Probed cells first, then greatest indicator; ties by level, then lattice place, so the
/// order never depends on anything but the space.
bool before(const Candidate& a, const Candidate& b) {
  if (a.probed != b.probed) return a.probed;
  if (a.indicator != b.indicator) return a.indicator > b.indicator;
  if (a.cell.level != b.cell.level) return a.cell.level < b.cell.level;
  return a.cell.ijk < b.cell.ijk;
}

/// Solves each (point, source) transition, spread over the solvers, and stores the results.
void solve_transitions(Space& space, const std::vector<std::pair<std::size_t, std::size_t>>& tasks,
                       std::vector<std::unique_ptr<ConfigurationSolver>>& solvers, const RefineOptions& options,
                       RefineStats& stats) {
  std::vector<PointResult> results(tasks.size());
  std::vector<std::exception_ptr> errors(solvers.size());
  auto work = [&](std::size_t worker) {
    try {
      for (std::size_t i = worker; i < tasks.size(); i += solvers.size()) {
        const auto [p, s] = tasks[i];
        results[i] = solvers[worker]->transition(p, static_cast<std::int64_t>(s),
                                                 space.displacement.col(static_cast<Eigen::Index>(s)),
                                                 space.position(s), space.position(p));
      }
    } catch (...) {
      errors[worker] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t w = 1; w < std::min(solvers.size(), tasks.size()); ++w) pool.emplace_back(work, w);
  work(0);
  for (auto& t : pool) t.join();
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
  for (const PointResult& r : results) {
    space.store(r);
    if (r.status != PointStatus::solved) ++stats.failed;
    if (options.on_result) options.on_result(r);
  }
}

/// Solves `points` (pending, on the level `level` lattice) ring by ring: each round takes the
/// points with a solved neighbour along an axis and reaches each from the first such neighbour
/// (x−, x+, y−, y+, z−, z+), in parallel; points no round can reach are marked unreachable.
void solve_new_points(Space& space, std::vector<std::size_t> points, int level,
                      std::vector<std::unique_ptr<ConfigurationSolver>>& solvers, const RefineOptions& options,
                      RefineStats& stats) {
  while (!points.empty()) {
    std::vector<std::pair<std::size_t, std::size_t>> ready;  // point, source
    std::vector<std::size_t> waiting;
    for (std::size_t p : points) {
      const LatticeIndex& at = space.refined_points[p - space.grid.size()];
      std::optional<std::size_t> source;
      for (int a = 0; a < 3 && !source; ++a)
        for (int side : {-1, 1}) {
          LatticeIndex n{level, at.ijk};
          n.ijk[static_cast<std::size_t>(a)] += side;
          const auto q = space.find(n);
          if (q && space.solved(*q)) {
            source = q;
            break;
          }
        }
      if (source)
        ready.emplace_back(p, *source);
      else
        waiting.push_back(p);
    }
    if (ready.empty()) {
      for (std::size_t p : waiting) {
        PointResult u = unreachable_result(p);
        space.store(u);
        ++stats.failed;
        if (options.on_result) options.on_result(u);
      }
      return;
    }
    solve_transitions(space, ready, solvers, options, stats);
    points = std::move(waiting);
  }
}

/// The centre of a cell: a point of the next level.
LatticeIndex centre_of(const LatticeIndex& cell) {
  return {cell.level + 1, {2 * cell.ijk[0] + 1, 2 * cell.ijk[1] + 1, 2 * cell.ijk[2] + 1}};
}

/// The estimate ranks the cells; the first few have their centre solved (reached from the
/// cell's lowest corner) and are ranked instead by how far the tricubic Hermite misses the
/// solved force there, relative to the cell's largest corner force. The probes count against
/// the budget and are made only where a split (at most 18 points beside the centre) can
/// still follow; a split cell keeps its probe as its centre.
void probe(Space& space, const Interpolator& interpolator, std::vector<Candidate>& leaves,
           std::vector<std::unique_ptr<ConfigurationSolver>>& solvers, const RefineOptions& options,
           RefineStats& stats) {
  constexpr std::size_t kSplit = 18;
  std::size_t wanted = std::min(leaves.size(), std::max<std::size_t>(1, options.points / 5));
  if (wanted + kSplit > options.points) wanted = options.points > kSplit ? options.points - kSplit : 0;
  std::sort(leaves.begin(), leaves.end(), before);
  std::vector<std::pair<std::size_t, std::size_t>> tasks;  // centre, the cell's lowest corner
  std::vector<std::pair<std::size_t, Vec3>> predicted;     // leaf, the tricubic Hermite there
  for (std::size_t i = 0; i < leaves.size() && tasks.size() < wanted; ++i) {
    const LatticeIndex centre = centre_of(leaves[i].cell);
    const auto corner = space.find(leaves[i].cell);
    if (!(leaves[i].indicator > 0.0) || space.find(centre) || !corner) continue;
    const std::size_t p = space.add_point(centre);
    predicted.emplace_back(i, interpolator.force(space.position(p)).force);
    tasks.emplace_back(p, *corner);
  }
  solve_transitions(space, tasks, solvers, options, stats);
  stats.points += tasks.size();
  for (std::size_t t = 0; t < tasks.size(); ++t) {
    Candidate& c = leaves[predicted[t].first];
    const std::size_t p = tasks[t].first;
    double scale = 0.0;
    for (int k = 0; k < 8; ++k) {
      const auto q = space.find({c.cell.level, {c.cell.ijk[0] + (k & 1), c.cell.ijk[1] + ((k >> 1) & 1),
                                                c.cell.ijk[2] + ((k >> 2) & 1)}});
      if (q) scale = std::max(scale, space.force[*q].norm());
    }
    c.probed = space.solved(p);
    c.indicator = c.probed ? (predicted[t].second - space.force[p]).norm() / std::max(scale, 1e-12) : -1.0;
  }
}

}  // namespace

RefineStats refine_local(Space& space, const SolverFactory& make_solver, const RefineOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  RefineStats stats;
  if (options.points == 0) return stats;
  std::vector<std::unique_ptr<ConfigurationSolver>> solvers;
  for (unsigned t = 0; t < std::max(1u, options.threads); ++t) solvers.push_back(make_solver());
  // The interpolator reads the space in place (not owned) and is built again after each split.
  const std::shared_ptr<const Space> view(std::shared_ptr<const Space>{}, &space);
  auto interpolator = std::make_unique<Interpolator>(view, Interpolation::tricubic_hermite);

  std::vector<Candidate> leaves;
  const Grid& g = space.grid;
  for (int k = 0; k + 1 < g.counts[2]; ++k)
    for (int j = 0; j + 1 < g.counts[1]; ++j)
      for (int i = 0; i + 1 < g.counts[0]; ++i) {
        const LatticeIndex cell{0, {i, j, k}};
        if (space.is_refined(cell)) continue;
        leaves.push_back({interpolator->cell_disagreement(cell), cell});
      }
  probe(space, *interpolator, leaves, solvers, options, stats);
  while (!leaves.empty()) {
    const auto worst = std::min_element(leaves.begin(), leaves.end(), before);
    const Candidate c = *worst;
    leaves.erase(worst);
    if (!(c.indicator > 0.0) || c.cell.level + 1 > Space::kMaxLevel) continue;
    const int level = c.cell.level + 1;
    std::vector<LatticeIndex> fresh;
    for (int k = 0; k <= 2; ++k)
      for (int j = 0; j <= 2; ++j)
        for (int i = 0; i <= 2; ++i) {
          const LatticeIndex at{level, {2 * c.cell.ijk[0] + i, 2 * c.cell.ijk[1] + j, 2 * c.cell.ijk[2] + k}};
          if (!space.find(at)) fresh.push_back(at);
        }
    if (stats.points + fresh.size() > options.points) continue;  // a cheaper split may still fit
    space.refine_cell(c.cell);
    ++stats.cells;
    std::vector<std::size_t> added;
    for (const LatticeIndex& at : fresh) added.push_back(space.add_point(at));
    stats.points += added.size();
    solve_new_points(space, added, level, solvers, options, stats);
    interpolator = std::make_unique<Interpolator>(view, Interpolation::tricubic_hermite);
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
          const LatticeIndex child{level, {2 * c.cell.ijk[0] + i, 2 * c.cell.ijk[1] + j, 2 * c.cell.ijk[2] + k}};
          leaves.push_back({interpolator->cell_disagreement(child), child});
        }
  }
  stats.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

}  // namespace tactus::precompute
