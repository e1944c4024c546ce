// Adaptive refinement: cells split where the force bends, their new points solved by
// transitions, and the tricubic Hermite querying the finest cell.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <random>
#include <unistd.h>

#include "core/error.hpp"
#include "precompute/builder.hpp"
#include "precompute/configuration_solver.hpp"
#include "precompute/interpolator.hpp"
#include "precompute/model_identity.hpp"
#include "precompute/refinement.hpp"
#include "precompute/space_file.hpp"
#include "test_body.hpp"

namespace tactus::precompute {
namespace {

/// The block's space over 4 mm in +x, +y and down from the contact node at 2 mm (27 points),
/// pressed deep enough that the force bends.
struct Fixture {
  physics::Body body = testing::block_body();
  SpaceSettings settings;
  std::shared_ptr<Space> space;

  Fixture() {
    settings = testing::block_settings(body);
    settings.spacing = 0.002;
    settings.bounds_min = Vec3(-1e-7, -1e-7, 0.006 - 1e-7);
    settings.bounds_max = Vec3(0.004 + 1e-7, 0.004 + 1e-7, 0.01 + 1e-7);
    space = std::make_shared<Space>(make_space(body, settings, ""));
    build_local(*space, factory(), BuildOptions{});
  }
  [[nodiscard]] SolverFactory factory() const {
    return [this] { return std::make_unique<ConfigurationSolver>(body, settings); };
  }
  RefineStats refine(Space& s, std::size_t points, unsigned threads) const {
    RefineOptions o;
    o.points = points;
    o.threads = threads;
    return refine_local(s, factory(), o);
  }
};

TEST(Refinement, SplitsWithinTheBudgetAndSolvesEveryNewPointAsADirectSolveWould) {
  Fixture f;
  ASSERT_EQ(f.space->count(PointStatus::solved), 27u);
  const RefineStats stats = f.refine(*f.space, 50, 1);
  // 50 points: the 8 cells' centres probed, then splits of 18 points more each: two fit.
  EXPECT_GE(stats.cells, 2u);
  EXPECT_LE(stats.points, 50u);
  EXPECT_EQ(stats.failed, 0u);
  EXPECT_EQ(f.space->point_count(), 27u + stats.points);
  EXPECT_EQ(f.space->refined_cells.size(), stats.cells);
  ConfigurationSolver solver(f.body, f.settings);
  for (std::size_t p = f.space->grid.size(); p < f.space->point_count(); ++p) {
    ASSERT_TRUE(f.space->solved(p)) << f.space->reason[p];
    EXPECT_EQ(f.space->refined_points[p - f.space->grid.size()].level, 1);
    const PointResult direct = solver.solve_direct(f.space->position(p), 8);
    ASSERT_EQ(direct.status, PointStatus::solved);
    EXPECT_LT((direct.force - f.space->force[p]).norm(), 1e-5 * direct.force.norm() + 1e-9) << "point " << p;
    EXPECT_LT((direct.force_gradient - f.space->force_gradient[p]).norm(), 1e-4 * direct.force_gradient.norm());
  }
  // The query passes through the new points: at each, the stored force. A point on a face
  // shared with a cell not split is looked up in whichever cell holds it, and the unsplit
  // cell does not interpolate through it (docs/precompute.md: hanging points), so only the
  // points whose cell of the grid is split are checked.
  const Interpolator in(f.space, Interpolation::tricubic_hermite);
  int checked = 0;
  for (std::size_t p = f.space->grid.size(); p < f.space->point_count(); ++p) {
    const Grid& g = f.space->grid;
    const Vec3 u = (f.space->position(p) - g.origin) / g.spacing;
    LatticeIndex cell{0, {}};
    for (int a = 0; a < 3; ++a)
      cell.ijk[static_cast<std::size_t>(a)] =
          std::clamp(static_cast<int>(std::floor(u[a])), 0, g.counts[static_cast<std::size_t>(a)] - 2);
    if (!f.space->is_refined(cell)) continue;
    ++checked;
    EXPECT_LT((in.force(f.space->position(p)).force - f.space->force[p]).norm(), 1e-9 * f.space->force[p].norm());
  }
  EXPECT_GE(checked, 7);  // at least the first cell's own centre, face and edge points
  // Located once (as a two-point space's levels are), a query in a split cell or beside one
  // is the plain query, bit for bit.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  const Grid& g = f.space->grid;
  for (int i = 0; i < 500; ++i) {
    const Vec3 p = g.lower() + (g.upper() - g.lower()).cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    const Query plain = in.force(p), located = in.force(p, in.locate(p));
    EXPECT_EQ(plain.force, located.force) << p.transpose();
    EXPECT_EQ(plain.valid, located.valid);
    EXPECT_EQ(plain.outside, located.outside);
    EXPECT_EQ(plain.fallback, located.fallback);
  }
}

TEST(Refinement, ProbesRankTheCellsByTheSolvedCentresMiss) {
  // With a budget of one probe and one split, the probed cell is split; with 26 points (5
  // probes, one split), the split cell is the one whose solved centre the unrefined tricubic
  // Hermite misses most.
  Fixture f;
  const Space unrefined = *f.space;
  const RefineStats one = f.refine(*f.space, 19, 1);
  EXPECT_EQ(one.cells, 1u);
  EXPECT_EQ(one.points, 19u);
  Fixture g;
  g.refine(*g.space, 8 + 18, 2);
  ASSERT_EQ(g.space->refined_cells.size(), 1u);
  const Interpolator before(std::make_shared<const Space>(unrefined), Interpolation::tricubic_hermite);
  double worst = -1.0;
  LatticeIndex expected;
  for (std::size_t p = g.space->grid.size(); p < g.space->point_count(); ++p) {
    const LatticeIndex& at = g.space->refined_points[p - g.space->grid.size()];
    if (at.ijk[0] % 2 == 0 || at.ijk[1] % 2 == 0 || at.ijk[2] % 2 == 0) continue;  // not a centre
    const LatticeIndex cell{0, {at.ijk[0] / 2, at.ijk[1] / 2, at.ijk[2] / 2}};
    double scale = 0.0;
    for (int k = 0; k < 8; ++k)
      scale = std::max(scale, g.space->force[g.space->grid.index(cell.ijk[0] + (k & 1), cell.ijk[1] + ((k >> 1) & 1),
                                                                  cell.ijk[2] + ((k >> 2) & 1))]
                                  .norm());
    const double miss = (before.force(g.space->position(p)).force - g.space->force[p]).norm() / scale;
    if (miss > worst) {
      worst = miss;
      expected = cell;
    }
  }
  EXPECT_EQ(g.space->refined_cells[0], expected);
}

TEST(Refinement, RefinedCellsInterpolateCloserToDirectSolves) {
  // Random positions inside the first cell split, against direct solves: the refined space's
  // tricubic Hermite error is below the unrefined one's.
  Fixture f;
  Space unrefined = *f.space;
  f.refine(*f.space, 19, 1);
  ASSERT_EQ(f.space->refined_cells.size(), 1u);
  const LatticeIndex cell = f.space->refined_cells[0];
  const auto coarse = std::make_shared<const Space>(unrefined);
  const Interpolator before(coarse, Interpolation::tricubic_hermite), after(f.space, Interpolation::tricubic_hermite);
  ConfigurationSolver solver(f.body, f.settings);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  double error_before = 0.0, error_after = 0.0;
  for (int i = 0; i < 8; ++i) {
    const Vec3 p = f.space->grid.point(cell.ijk[0], cell.ijk[1], cell.ijk[2]) +
                   f.space->grid.spacing * Vec3(u(rng), u(rng), u(rng));
    const PointResult direct = solver.solve_direct(p, 8);
    ASSERT_EQ(direct.status, PointStatus::solved);
    error_before += (before.force(p).force - direct.force).norm() / direct.force.norm();
    error_after += (after.force(p).force - direct.force).norm() / direct.force.norm();
  }
  EXPECT_LT(error_after, 0.5 * error_before) << "mean relative error " << error_before / 8 << " -> "
                                              << error_after / 8;
}

TEST(Refinement, ThreadCountDoesNotChangeTheResultAndTheFileKeepsIt) {
  Fixture f;
  Space two = *f.space;
  f.refine(*f.space, 40, 1);
  f.refine(two, 40, 2);
  EXPECT_EQ(f.space->refined_points, two.refined_points);
  EXPECT_EQ(f.space->refined_cells, two.refined_cells);
  EXPECT_EQ(f.space->force, two.force);
  EXPECT_TRUE(f.space->displacement_gradient == two.displacement_gradient);

  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("tactus_refinement_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  write_space(dir / "refined.h5", *f.space);
  const auto back = std::make_shared<const Space>(load_space(dir / "refined.h5", f.space->identity));
  fs::remove_all(dir);
  EXPECT_EQ(back->refined_points, f.space->refined_points);
  EXPECT_EQ(back->refined_cells, f.space->refined_cells);
  EXPECT_EQ(back->force, f.space->force);
  EXPECT_TRUE(back->displacement == f.space->displacement);
  const Interpolator a(f.space, Interpolation::tricubic_hermite), b(back, Interpolation::tricubic_hermite);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  VecX shape_a, shape_b;
  for (int i = 0; i < 50; ++i) {
    const Vec3 p = f.space->grid.lower() + (f.space->grid.upper() - f.space->grid.lower()).cwiseProduct(
                                               Vec3(u(rng), u(rng), u(rng)));
    EXPECT_EQ(a.force(p).force, b.force(p).force);
    // The shape path (weights) and the force path agree.
    EXPECT_LT((a.shape(p, shape_a).force - a.force(p).force).norm(), 1e-12 * (1.0 + a.force(p).force.norm()));
    b.shape(p, shape_b);
    EXPECT_TRUE(shape_a == shape_b);
  }
}

TEST(Refinement, ABudgetTooSmallForASplitAddsNothing) {
  Fixture f;
  const RefineStats stats = f.refine(*f.space, 18, 2);
  EXPECT_EQ(stats.cells, 0u);
  EXPECT_EQ(f.space->point_count(), 27u);
}

TEST(Refinement, PlacesBeyondTheKeysRangeAreRefusedNotAliased) {
  // Places are keyed by 21 bits an axis on the finest lattice: a grid of more than 8,192
  // points along an axis cannot be refined, and says so, rather than two places sharing a key.
  Space space;
  space.grid.counts = {10000, 2, 2};
  space.allocate(1);
  EXPECT_THROW(space.add_point({1, {2 * 9000 + 1, 1, 1}}), InputError);
  EXPECT_THROW(space.refine_cell({0, {9000, 0, 0}}), InputError);
  EXPECT_NO_THROW(space.add_point({1, {2 * 8000 + 1, 1, 1}}));
  // 2^14 on level 1 is 2^21 on the finest lattice: the same key, masked, as the point above.
  EXPECT_FALSE(space.find({1, {2 * 8000 + 1 + (1 << 14), 1, 1}}).has_value());
  EXPECT_TRUE(space.find({1, {2 * 8000 + 1, 1, 1}}).has_value());
}

}  // namespace
}  // namespace tactus::precompute
