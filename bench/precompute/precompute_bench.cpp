// Cost, scaling, query latency and accuracy of configuration spaces (docs/precompute.md) on
// the generated organ (about 22 cm long, target node count, fixed along its underside, the
// contact patch on the top centre). Subcommands (results in docs/BENCHMARKS.md and
// docs/validation.md):
//
//   cost     --nodes N --law L --spacing S --points K
//            CPU-seconds per point: the first K points of the wavefront (the points nearest
//            the start, in the order the builder hands them out) of the grid of spacing S
//            over the organ's bounding box plus 10 mm, built on one thread.
//   scaling  --nodes N --spacing S --seconds T
//            the wavefront width of that full grid over time, and the build time and
//            parallel efficiency on 64 and 1024 solver ranks for T seconds per point,
//            simulated event by event with the builder's own Wavefront.
//   query    [--space FILE]
//            force query latency per interpolation method (p50, p99, max), on a space
//            file or a synthetic 10 x 10 x 10 space.
//   accuracy --nodes N --law L --positions M [--box MM] [--spacings 20,6.667] [--refine K]
//            interpolated force and displacement against configurations solved directly
//            at M random positions, for grid spacings 20, 13.33, 10 and 6.667 mm (a half, a
//            third, a quarter and a sixth of the box; or those listed, in mm) and each
//            method, in the accuracy box (40 mm along +x and +y and 40 mm down by default);
//            with --refine, each grid also refined by up to K points, tricubic Hermite; with
//            --worst W, the W worst tricubic Hermite positions per grid and how far their
//            cell's corners lie from direct solves (path dependence against interpolation).
//            With --cells 1, a row per grid cell: its edges' jump (Interpolator::cell_jump),
//            the refinement's estimate and the errors at the positions inside it.
//   line     --nodes N --law L --from X,Y,Z --to X,Y,Z [--samples K]
//            the force at K points of the segment (in mm from the contact node) solved
//            directly from rest (as accuracy's references with --spacings 20), and walked
//            along it from each end by transitions: where the walks disagree, the tissue has
//            two equilibria there and the path decides (a snap with hysteresis).
//   probe    --nodes N --law L --spacing S --tilt DEG --levels n --positions M [--box MM]
//            [--patch MM]
//            a probe space (precompute/probe.hpp) on the accuracy box's grid of spacing S,
//            n × n leans up to DEG degrees about each tangent axis of the probe pointing
//            down, against direct solves at M random positions (where every level's cell is
//            solved) and leans: the force error
//            per method, at the same positions with the nearest level's lean (the position's
//            interpolation alone), and with the lean ignored (the upright level alone); the
//            cost per point and the force query's latency.
//   twopoint --nodes N --law L --spacing S --separation MM --positions M [--box MM] [--patch MM]
//            two interaction points (two fingers): the top centre's node and the surface
//            node MM further along +x, each with its own point space (a box of MM along +x
//            and +y and MM down from it), against direct solves with both held at M random
//            pairs of positions: the forces from each space alone, and corrected by the
//            coupling of the two points (the rest stiffness condensed onto them); and from
//            the two-point space `tactus precompute` builds (precompute/pair.hpp): per point
//            of the other's grid a level, the point's own space with the other held there.
//            With --patch, each point moves the nodes within MM of it (then the couplings,
//            the two nodes', are not printed). With --space FILE the levels are written
//            there, or read from there where an earlier run of the same command wrote them.
//   online   --nodes N --law L --spacing S --threads W [--first V]
//            on-line construction: the largest tool speed at which at least 99 % of the
//            1 kHz force queries find their cell complete, with W solver threads, on the
//            accuracy box's grid of spacing S, driven in real time along the scripted path
//            (speeds from V mm/s, default 1, doubled or halved, then 2 bisections);
//            then the same speed search simulated with the measured solve times for 1 to
//            64 workers (the scheduler's own code, in simulated time).
//   compare  A.h5 B.h5
//            whether two space files hold the same outcomes, forces and displacements, bit
//            for bit (solve times aside): a resumed build against an uninterrupted one.
//
// The accuracy box: from the contact node's rest position 40 mm along +x and +y and 40 mm down
// (pressing in). The grids run through the contact node and 40 mm is a multiple of every
// spacing, so each grid covers exactly this box.
#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <queue>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "core/histogram.hpp"
#include "core/parallel.hpp"
#include "precompute/builder.hpp"
#include "precompute/probe.hpp"
#include "precompute/configuration_solver.hpp"
#include "precompute/interpolator.hpp"
#include "precompute/online.hpp"
#include "precompute/pair.hpp"
#include "precompute/refinement.hpp"
#include "precompute/space_file.hpp"
#include "precompute/wavefront.hpp"
#include "compile/bodies.hpp"
#include "scene/scene.hpp"

namespace {

using namespace tactus;
namespace pc = tactus::precompute;

struct Options {
  std::string command;
  int nodes = 501;
  std::string law = "stvk";
  double spacing = 0.02;
  std::size_t points = 20;
  double seconds = 1.0;
  int positions = 40;
  unsigned threads = 1;
  unsigned seed = 1;
  std::string space;  ///< query: a space file (default: a synthetic one)
  double first = 1.0;  ///< online: first speed tried [mm/s]
  /// accuracy: the box's edge [m] (--box, in mm) and the grid spacings [m]: the box's half,
  /// third, quarter and sixth (20, 13.33, 10 and 6.667 mm for the 40 mm box) unless
  /// --spacings lists others (in mm, divisors of the box; the reference positions are drawn
  /// where every listed grid is solved).
  double box = 0.04;
  std::size_t refine = 0;  ///< accuracy: each grid also refined by at most this many points
  std::size_t worst = 0;   ///< accuracy: list this many worst tricubic Hermite positions per grid
  bool cells = false;      ///< accuracy: a row per grid cell (--cells 1)
  Vec3 from = Vec3::Zero(), to = Vec3::Zero();  ///< line: the segment's ends from the contact node [m] (mm)
  int samples = 11;                             ///< line: solves along it, ends included
  std::vector<double> spacings;
  double tilt = 15.0;  ///< probe: largest lean [degrees]
  double patch = 0.016;  ///< probe: the patch's radius [m] (--patch, in mm): the probe's end
  double separation = 0.03;  ///< twopoint: from the first point to the second along +x [m] (mm)
  double pair_patch = 0.0;   ///< twopoint: each point's patch radius [m] (--patch, in mm; 0: the node alone)
  int levels = 3;      ///< probe: leans per tangent axis
};

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/// The organ scene: soft tissue (E = 6 kPa, nu = 0.45, as scenes/liver.toml's parenchyma)
/// in `law`, about `nodes` nodes, held along the bottom 10 mm, touched on the top centre by a
/// patch of radius 8 mm (a fingertip). Newton stops at 1e-6 relative residual per load step:
/// at the default 1e-8 the projected tangent stalled (2e-7 to 2e-5) on 9 of the 27 points of
/// the 20 mm accuracy grid, at 1e-6 on 3; 1e-6 of the step's force is far below the
/// interpolation errors measured here.
///
/// `mooney_rivlin_049` and `mooney_rivlin_nodal`: the Mooney–Rivlin tissue nearly
/// incompressible (nu = 0.49), its volume change taken per element or at the nodes.
std::string organ_scene(int nodes, const std::string& law) {
  const std::string mooney_rivlin = "model = \"mooney_rivlin\"\nc10 = 700.0\nc01 = 300.0\n";
  const std::string material =
      law == "mooney_rivlin"         ? mooney_rivlin + "poisson_ratio = 0.45\n"
      : law == "mooney_rivlin_049"   ? mooney_rivlin + "poisson_ratio = 0.49\n"
      : law == "mooney_rivlin_nodal" ? mooney_rivlin + "poisson_ratio = 0.49\nvolumetric = \"nodal\"\n"
                                     : "model = \"" + law + "\"\nyoung_modulus = 6.0e3\npoisson_ratio = 0.45\n";
  return fmt::format(R"(
[materials.tissue]
{}density = 1060.0

[bodies.organ]
kind = "fem"
material = "tissue"
solver = "cholesky"

[bodies.organ.mesh]
generator = "organ"
length = 0.22
resolution = 8
target_nodes = {}

[[bodies.organ.fixed]]
side = "z_min"
tolerance = 0.01

[precompute]
contact_point = [0.0, 0.0, 0.05]
patch_radius = 0.008
spacing = 0.02
min = [-0.12, -0.08, -0.05]
max = [0.12, 0.08, 0.06]
tolerance = 1e-6
)",
                     material, nodes);
}

struct Model {
  physics::Body body;
  pc::SpaceSettings settings;
  Vec3 contact = Vec3::Zero();  ///< rest position of the contact node
  Vec3 lower = Vec3::Zero(), upper = Vec3::Zero();  ///< the organ's bounding box
};

/// The organ; `contact` moves the [precompute] table's contact point (the contact node is the
/// surface node nearest to it).
Model load_model(int nodes, const std::string& law, const Vec3& contact = Vec3(0.0, 0.0, 0.05)) {
  std::string text = organ_scene(nodes, law);
  const std::string key = "contact_point = [0.0, 0.0, 0.05]";
  text.replace(text.find(key), key.size(),
               fmt::format("contact_point = [{}, {}, {}]", contact.x(), contact.y(), contact.z()));
  const scene::Model scene = scene::parse_scene(text, "organ-bench");
  Model m{compile::make_physics_body(scene, 0), *scene.precompute, {}, {}, {}};
  const VecX& rest = m.body.model->rest_positions();
  m.contact = rest.segment<3>(3 * m.settings.contact_node);
  const auto points = rest.reshaped(3, rest.size() / 3);
  m.lower = points.rowwise().minCoeff();
  m.upper = points.rowwise().maxCoeff();
  return m;
}

/// Settings for a grid of `spacing` over [lower, upper] (a little slack so that box faces
/// on lattice planes are kept).
pc::SpaceSettings with_grid(const Model& m, double spacing, const Vec3& lower, const Vec3& upper) {
  pc::SpaceSettings s = m.settings;
  s.spacing = spacing;
  s.bounds_min = lower - Vec3::Constant(1e-6);
  s.bounds_max = upper + Vec3::Constant(1e-6);
  return s;
}

pc::SpaceSettings full_grid(const Model& m, double spacing) {
  return with_grid(m, spacing, m.lower - Vec3::Constant(0.01), m.upper + Vec3::Constant(0.01));
}

pc::SpaceSettings accuracy_grid(const Model& m, double spacing, double box = 0.04) {
  return with_grid(m, spacing, m.contact + Vec3(0.0, 0.0, -box), m.contact + Vec3(box, box, 0.0));
}

pc::SolverFactory factory(const Model& m, const pc::SpaceSettings& s) {
  return [&m, s] { return std::make_unique<pc::ConfigurationSolver>(m.body, s); };
}

int cost(const Options& o) {
  const Model m = load_model(o.nodes, o.law);
  const pc::SpaceSettings s = full_grid(m, o.spacing);
  pc::Space space = pc::make_space(m.body, s, "");
  pc::BuildOptions b;
  b.threads = 1;
  b.stop_after = o.points;
  long long iterations = 0;
  std::size_t failed = 0;
  double derivative_seconds = 0.0;
  b.on_result = [&](const pc::PointResult& r) {
    iterations += r.iterations;
    derivative_seconds += r.derivative_seconds;
    failed += r.status == pc::PointStatus::failed;
  };
  const double cpu0 = cpu_seconds();
  const pc::BuildStats stats = pc::build_local(space, factory(m, s), b);
  const double cpu = cpu_seconds() - cpu0;
  const auto n = static_cast<double>(std::max<std::size_t>(stats.computed, 1));
  std::printf("cost: %s, %zu nodes, %zu tets, spacing %.4g m, full grid %d x %d x %d = %zu points\n", o.law.c_str(),
              m.body.model->node_count(), space.elements.size(), s.spacing, space.grid.counts[0],
              space.grid.counts[1], space.grid.counts[2], space.grid.size());
  std::printf("  first %zu points of the wavefront (%zu failed): %.3f CPU-s/point, %.3f solver-s/point (wall), "
              "%.1f Newton iterations/point\n",
              stats.computed, failed, cpu / n, stats.solve_seconds / n, static_cast<double>(iterations) / n);
  std::printf("  of which the derivatives (one factorization, three solves): %.3f s/point, %.1f%%\n",
              derivative_seconds / n, 100.0 * derivative_seconds / std::max(stats.solve_seconds, 1e-12));
  return 0;
}

/// Event simulation of the scheduler on `ranks` solver ranks, every solve taking `seconds`
/// plus the scheduler's per-task overhead `overhead` (serialized on rank 0). Returns the
/// makespan; `width` gets the number of ready-or-running points at each completion.
double simulate(const pc::Grid& grid, std::size_t start, int ranks, double seconds, double overhead,
                std::vector<std::pair<double, std::size_t>>* width) {
  pc::Wavefront wave(grid, start, std::vector<pc::PointStatus>(grid.size(), pc::PointStatus::pending));
  using Event = std::pair<double, std::size_t>;  // finish time, point
  std::priority_queue<Event, std::vector<Event>, std::greater<>> running;
  double now = 0.0, scheduler_free = 0.0;
  int idle = ranks;
  while (!wave.finished()) {
    while (idle > 0) {
      const auto task = wave.next();
      if (!task) break;
      scheduler_free = std::max(scheduler_free, now) + overhead;
      running.emplace(scheduler_free + seconds, task->point);
      --idle;
    }
    if (running.empty()) break;
    const auto [t, p] = running.top();
    running.pop();
    now = t;
    wave.complete(p, pc::PointStatus::solved);
    ++idle;
    if (width) width->emplace_back(now, running.size() + 1);
  }
  return now;
}

int scaling(const Options& o) {
  const Model m = load_model(o.nodes, "stvk");
  const pc::SpaceSettings s = full_grid(m, o.spacing);
  const pc::Space space = pc::make_space(m.body, s, "");
  const std::size_t dofs = 3 * m.body.model->node_count();
  // Rank 0's work per task: send the source's displacements and receive the result (8 * 3N
  // bytes each way) at 1 GB/s with 5 us latency, and append 8 * 3N bytes to the journal.
  const double bytes = 8.0 * static_cast<double>(dofs);
  const double overhead = 2.0 * (5e-6 + bytes / 1e9) + bytes / 1e9;
  std::printf("scaling: grid %d x %d x %d = %zu points at %.4g m, %zu nodes, %.3g s per point, message %.0f bytes, "
              "scheduler %.3g ms per task\n",
              space.grid.counts[0], space.grid.counts[1], space.grid.counts[2], space.grid.size(), s.spacing,
              m.body.model->node_count(), o.seconds, bytes, 1e3 * overhead);
  // Wavefront width: with unlimited ranks, how many points are ready at once.
  std::vector<std::pair<double, std::size_t>> width;
  const double depth = simulate(space.grid, space.start, 1 << 30, o.seconds, 0.0, &width);
  std::map<long, std::size_t> by_level;
  for (const auto& [t, w] : width) by_level[std::lround(t / o.seconds)] = std::max(by_level[std::lround(t / o.seconds)], w);
  std::size_t widest = 0;
  std::printf("  unlimited ranks: %.0f levels (critical path %.4g s); ready points per level:", depth / o.seconds,
              depth);
  for (const auto& [level, w] : by_level) {
    widest = std::max(widest, w);
    if (level % 5 == 1) std::printf(" %ld:%zu", level, w);
  }
  std::printf("\n  widest level %zu points\n", widest);
  const double serial = static_cast<double>(space.grid.size()) * o.seconds;
  for (const int ranks : {1, 2, 4, 64, 1024}) {
    const double t = simulate(space.grid, space.start, ranks, o.seconds, overhead, nullptr);
    std::printf("  %5d solver ranks: %.4g s (%.2f h), efficiency %.0f%%\n", ranks, t, t / 3600.0,
                100.0 * serial / (ranks * t));
  }
  return 0;
}

/// A 10 x 10 x 10 space of 1 cm whose every point is solved, forces from a smooth field (the
/// query cost does not depend on the values): interior cells use the full 32-point stencils.
std::shared_ptr<pc::Space> synthetic_space() {
  auto s = std::make_shared<pc::Space>();
  s->grid.spacing = 0.01;
  s->grid.counts = {10, 10, 10};
  s->allocate(2);
  for (std::size_t p = 0; p < s->grid.size(); ++p) {
    const Vec3 x = s->grid.point(p);
    s->status[p] = pc::PointStatus::solved;
    s->force[p] = Vec3(std::sin(20 * x.x()) + x.y(), std::exp(5 * x.y()) * x.z(), 10 * x.x() * x.z());
    s->force_gradient[p] << 20 * std::cos(20 * x.x()), 1, 0, 0, 5 * std::exp(5 * x.y()) * x.z(), std::exp(5 * x.y()),
        10 * x.z(), 0, 10 * x.x();
  }
  return s;
}

int query(const Options& o) {
  const auto space = o.space.empty() ? synthetic_space() : std::make_shared<pc::Space>(pc::read_space(o.space));
  std::printf("query: %s, grid %d x %d x %d at %.4g m, %zu solved; queries uniform over the grid's box\n",
              o.space.empty() ? "synthetic space" : o.space.c_str(), space->grid.counts[0], space->grid.counts[1],
              space->grid.counts[2], space->grid.spacing, space->count(pc::PointStatus::solved));
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  constexpr int kQueries = 200000;
  std::vector<Vec3> points(kQueries);
  const Vec3 lo = space->grid.lower(), size = space->grid.upper() - lo;
  for (auto& p : points) p = lo + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(size);
  for (const auto method : {pc::Interpolation::trilinear, pc::Interpolation::rbf_cubic,
                            pc::Interpolation::rbf_thin_plate, pc::Interpolation::polynomial,
                            pc::Interpolation::tricubic_hermite, pc::Interpolation::rbf_hermite}) {
    if (!space->has_gradients && (method == pc::Interpolation::tricubic_hermite ||
                                  method == pc::Interpolation::rbf_hermite))
      continue;
    const pc::Interpolator in(space, method);
    LatencyHistogram h;
    double sink = 0.0;
    int fallbacks = 0;
    for (int i = 0; i < 1000; ++i) sink += in.force(points[static_cast<std::size_t>(i)]).force.x();  // warm-up
    for (const Vec3& p : points) {
      const auto t0 = std::chrono::steady_clock::now();
      const pc::Query q = in.force(p);
      const auto t1 = std::chrono::steady_clock::now();
      sink += q.force.x();
      fallbacks += q.fallback;
      h.record(std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count());
    }
    const LatencySummary l = summarize(h);
    std::printf("  %-15s p50 %6.3f us  p99 %6.3f us  max %7.3f us  (%llu queries, %d fell back to trilinear, "
                "checksum %.3g)\n",
                std::string(pc::to_string(method)).c_str(), 1e-3 * static_cast<double>(l.p50),
                1e-3 * static_cast<double>(l.p99), 1e-3 * static_cast<double>(l.max),
                static_cast<unsigned long long>(l.count), fallbacks, sink);
  }
  return 0;
}

/// The grid point of corner `corner` (bits x, y, z) of the grid cell holding p, or nothing
/// when p lies outside the grid.
std::optional<std::size_t> cell_corner(const pc::Space& space, const Vec3& p, int corner) {
  const Vec3 t = (p - space.grid.origin) / space.grid.spacing;
  std::array<int, 3> c{};
  for (int a = 0; a < 3; ++a) {
    if (t[a] < 0.0 || t[a] > space.grid.counts[a] - 1) return std::nullopt;
    c[a] = std::clamp(static_cast<int>(std::floor(t[a])), 0, space.grid.counts[a] - 2);
  }
  return space.grid.index(c[0] + (corner & 1), c[1] + ((corner >> 1) & 1), c[2] + ((corner >> 2) & 1));
}

/// The corners of the finest cell that holds p (p in the grid): its grid cell, and down
/// through the refined cells; `level` is that cell's level.
std::array<std::optional<std::size_t>, 8> finest_corners(const pc::Space& space, const Vec3& p, int& level) {
  const Vec3 from_origin = p - space.grid.origin;
  pc::LatticeIndex cell{};
  for (std::size_t a = 0; a < 3; ++a) {
    const double t = from_origin[static_cast<Eigen::Index>(a)] / space.grid.spacing;
    cell.ijk[a] = std::clamp(static_cast<int>(std::floor(t)), 0, space.grid.counts[a] - 2);
  }
  while (cell.level < pc::Space::kMaxLevel && space.is_refined(cell)) {
    pc::LatticeIndex child{cell.level + 1, {}};
    const double h = space.grid.spacing / (1 << child.level);
    for (std::size_t a = 0; a < 3; ++a) {
      const double t = from_origin[static_cast<Eigen::Index>(a)] / h;
      child.ijk[a] = std::clamp(static_cast<int>(std::floor(t)), 2 * cell.ijk[a], 2 * cell.ijk[a] + 1);
    }
    cell = child;
  }
  level = cell.level;
  std::array<std::optional<std::size_t>, 8> corners;
  for (int c = 0; c < 8; ++c)
    corners[static_cast<std::size_t>(c)] =
        space.find({cell.level, {cell.ijk[0] + (c & 1), cell.ijk[1] + ((c >> 1) & 1), cell.ijk[2] + ((c >> 2) & 1)}});
  return corners;
}

/// Whether p lies in the grid and every corner of its cell is solved.
bool cell_solved(const pc::Space& space, const Vec3& p) {
  for (int corner = 0; corner < 8; ++corner) {
    const auto q = cell_corner(space, p, corner);
    if (!q || !space.solved(*q)) return false;
  }
  return true;
}

int accuracy(const Options& o) {
  const Model m = load_model(o.nodes, o.law);
  const std::vector<double>& spacings = o.spacings;
  std::vector<std::shared_ptr<pc::Space>> spaces, refined_spaces;
  for (const double d : spacings) {
    const pc::SpaceSettings s = accuracy_grid(m, d, o.box);
    auto space = std::make_shared<pc::Space>(pc::make_space(m.body, s, ""));
    pc::BuildOptions b;
    b.threads = o.threads;
    const pc::BuildStats st = pc::build_local(*space, factory(m, s), b);
    std::printf("accuracy: %s, %zu nodes, spacing %.4g mm: %zu points, %zu solved, %zu failed, %zu unreachable, "
                "%zu failed transitions tried again, %.1f s wall\n",
                o.law.c_str(), m.body.model->node_count(), 1e3 * d, space->grid.size(),
                space->count(pc::PointStatus::solved), space->count(pc::PointStatus::failed),
                space->count(pc::PointStatus::unreachable), st.retried, st.wall_seconds);
    for (std::size_t p = 0; p < space->grid.size(); ++p)
      if (space->status[p] == pc::PointStatus::failed) {
        const Vec3 at = space->grid.point(p) - m.contact;
        std::printf("    failed at (%+.1f, %+.1f, %+.1f) mm from the contact node: %s\n", 1e3 * at.x(), 1e3 * at.y(),
                    1e3 * at.z(), space->reason[p].c_str());
      }
    std::fflush(stdout);
    if (o.refine > 0) {
      // The refined space is a copy: the methods without refinement are measured on the grid.
      auto refined = std::make_shared<pc::Space>(*space);
      pc::RefineOptions r;
      r.points = o.refine;
      r.threads = o.threads;
      const pc::RefineStats rs = pc::refine_local(*refined, factory(m, s), r);
      std::printf("    refined %zu cells: %zu points more (%zu not solved), %.1f s wall\n", rs.cells, rs.points,
                  rs.failed, rs.wall_seconds);
      refined_spaces.push_back(std::move(refined));
    }
    spaces.push_back(std::move(space));
  }
  // Reference solutions: straight from rest to the position, in load steps of at most a
  // third of the finest spacing's load step, so their discretization of the path is finer
  // than any grid's.
  // The positions are drawn in one sequence and solved a batch (one per thread) at a time;
  // the first M that solve are kept in the order drawn, whatever the thread count.
  const double finest = *std::min_element(spacings.begin(), spacings.end());
  std::vector<std::unique_ptr<pc::ConfigurationSolver>> solvers;
  for (unsigned t = 0; t < std::max(1u, o.threads); ++t)
    solvers.push_back(std::make_unique<pc::ConfigurationSolver>(m.body, m.settings));
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3 lo = m.contact + Vec3(0.0, 0.0, -o.box);
  const Vec3 size = Vec3::Constant(o.box);
  std::vector<pc::PointResult> refs;
  std::vector<Vec3> where;
  int tries = 0;
  while (static_cast<int>(refs.size()) < o.positions && tries < 20 * o.positions) {
    std::vector<Vec3> batch;
    while (batch.size() < solvers.size() && tries++ < 20 * o.positions) {
      const Vec3 p = lo + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(size);
      if (std::all_of(spaces.begin(), spaces.end(), [&](const auto& s) { return cell_solved(*s, p); }))
        batch.push_back(p);
    }
    std::vector<pc::PointResult> solved(batch.size());
    std::vector<std::thread> threads;
    for (std::size_t b = 0; b < batch.size(); ++b)
      threads.emplace_back([&, b] {
        const Vec3& p = batch[b];
        const double step = m.settings.load_steps > 0 ? finest / m.settings.load_steps / 3.0 : 1e-3;
        const int steps = std::max(2, static_cast<int>(std::ceil((p - m.contact).norm() / step)));
        solved[b] = solvers[b]->solve_direct(p, steps);
      });
    for (auto& t : threads) t.join();
    for (std::size_t b = 0; b < batch.size() && static_cast<int>(refs.size()) < o.positions; ++b) {
      const Vec3& p = batch[b];
      if (solved[b].status != pc::PointStatus::solved) {
        std::printf("  reference at (%.4f, %.4f, %.4f) failed: %s\n", p.x(), p.y(), p.z(), solved[b].reason.c_str());
        continue;
      }
      refs.push_back(std::move(solved[b]));
      where.push_back(p);
    }
  }
  double mean_force = 0.0;
  for (const auto& r : refs) mean_force += r.force.norm() / static_cast<double>(refs.size());
  std::printf("  %zu reference positions (mean |force| %.4g N)\n", refs.size(), mean_force);
  std::printf("| spacing [mm] | method | force error mean | force error max | displacement error mean | "
              "displacement error max |\n|---|---|---|---|---|---|\n");
  std::vector<std::pair<std::size_t, pc::Interpolation>> rows;
  for (std::size_t k = 0; k < spaces.size(); ++k) {
    for (const auto method : {pc::Interpolation::trilinear, pc::Interpolation::rbf_cubic,
                              pc::Interpolation::rbf_thin_plate, pc::Interpolation::polynomial,
                              pc::Interpolation::tricubic_hermite, pc::Interpolation::rbf_hermite})
      rows.emplace_back(k, method);
    if (o.refine > 0) rows.emplace_back(spaces.size() + k, pc::Interpolation::tricubic_hermite);
  }
  for (const auto& [index, method] : rows) {
    const bool refined = index >= spaces.size();
    const std::size_t k = refined ? index - spaces.size() : index;
    const auto& space = refined ? refined_spaces[k] : spaces[k];
    const pc::Interpolator in(space, method);
    double fmean = 0.0, fmax = 0.0, umean = 0.0, umax = 0.0;
    VecX u_interp;
    for (std::size_t i = 0; i < refs.size(); ++i) {
      const pc::Query q = in.shape(where[i], u_interp);
      // Relative errors: of the force vector against the reference force's magnitude, of
      // the displacement field (all nodes, 2-norm) against the reference field's norm.
      const double fe = (q.force - refs[i].force).norm() / refs[i].force.norm();
      const double ue = (u_interp - refs[i].displacement).norm() / refs[i].displacement.norm();
      fmean += fe / static_cast<double>(refs.size());
      umean += ue / static_cast<double>(refs.size());
      fmax = std::max(fmax, fe);
      umax = std::max(umax, ue);
    }
    const std::string name =
        std::string(pc::to_string(method)) +
        (refined ? fmt::format(", refined (+{} points)", space->point_count() - space->grid.size()) : "");
    std::printf("| %.4g | %s | %.2f%% | %.2f%% | %.2f%% | %.2f%% |\n", 1e3 * spacings[k], name.c_str(), 100 * fmean,
                100 * fmax, 100 * umean, 100 * umax);
  }
  if (o.cells) {
    // Per grid cell: what its corners' derivatives cannot explain of the force's change along
    // its edges (Interpolator::cell_jump), the refinement's estimate, and the tricubic
    // Hermite errors at the positions inside it.
    std::printf("| spacing [mm] | cell | jump [N] | centre disagreement | positions | force error mean | max |\n"
                "|---|---|---|---|---|---|---|\n");
    for (std::size_t k = 0; k < spaces.size(); ++k) {
      const pc::Interpolator in(spaces[k], pc::Interpolation::tricubic_hermite);
      const pc::Grid& g = spaces[k]->grid;
      for (int kk = 0; kk + 1 < g.counts[2]; ++kk)
        for (int j = 0; j + 1 < g.counts[1]; ++j)
          for (int i = 0; i + 1 < g.counts[0]; ++i) {
            const pc::LatticeIndex cell{0, {i, j, kk}};
            double emax = 0.0, emean = 0.0;
            int n = 0;
            for (std::size_t q = 0; q < refs.size(); ++q) {
              int level = 0;
              if (finest_corners(*spaces[k], where[q], level)[0] != g.index(i, j, kk)) continue;
              const double e = (in.force(where[q]).force - refs[q].force).norm() / refs[q].force.norm();
              emax = std::max(emax, e);
              emean += e;
              ++n;
            }
            std::printf("| %.4g | %d %d %d | %.3f | %.4f | %d | %.2f%% | %.2f%% |\n", 1e3 * spacings[k], i, j, kk,
                        in.cell_jump(cell), in.cell_disagreement(cell), n, n ? 100 * emean / n : 0.0, 100 * emax);
          }
    }
  }
  if (o.worst > 0) {
    // Where tricubic Hermite errs most on each grid, and whether the grid points around are
    // the configurations a direct solve from rest reaches there: if not, the error is the
    // path's (another equilibrium), not the interpolation's.
    for (std::size_t index = 0; index < spaces.size() + refined_spaces.size(); ++index) {
      const bool refined = index >= spaces.size();
      const std::size_t k = refined ? index - spaces.size() : index;
      const auto& shared = refined ? refined_spaces[k] : spaces[k];
      const pc::Space& space = *shared;
      const pc::Interpolator in(shared, pc::Interpolation::tricubic_hermite);
      std::vector<std::pair<double, std::size_t>> errors;
      for (std::size_t i = 0; i < refs.size(); ++i)
        errors.emplace_back((in.force(where[i]).force - refs[i].force).norm() / refs[i].force.norm(), i);
      std::sort(errors.rbegin(), errors.rend());
      std::printf("worst tricubic_hermite positions on the %.4g mm grid%s:\n", 1e3 * spacings[k],
                  refined ? ", refined" : "");
      for (std::size_t w = 0; w < std::min<std::size_t>(o.worst, errors.size()); ++w) {
        const auto [error, i] = errors[w];
        const Vec3 at = where[i] - m.contact;
        double corner_gap = 0.0;
        int level = 0;
        const auto corners = finest_corners(space, where[i], level);  // the positions lie in every grid
        for (const auto& corner : corners) {
          if (!corner) continue;
          const std::size_t p = *corner;
          const Vec3 x = space.position(p);
          const double step = finest / std::max(1, m.settings.load_steps) / 3.0;
          const int steps = std::max(2, static_cast<int>(std::ceil((x - m.contact).norm() / step)));
          const pc::PointResult direct = solvers[0]->solve_direct(x, steps);
          if (direct.status == pc::PointStatus::solved)
            corner_gap =
                std::max(corner_gap, (direct.force - space.force[p]).norm() / std::max(direct.force.norm(), 1e-9));
        }
        std::printf("  (%+.1f, %+.1f, %+.1f) mm: force error %.2f%% (|f| %.3g N); the corners of its cell (level %d) "
                    "solved directly from rest differ from the grid's by up to %.2g%%\n",
                    1e3 * at.x(), 1e3 * at.y(), 1e3 * at.z(), 100 * error, refs[i].force.norm(), level,
                    100 * corner_gap);
      }
    }
  }
  return 0;
}

int line(const Options& o) {
  // Each position three ways: straight from rest (as the accuracy study's references), and
  // walked along the segment from each end, each sample reached from the one before by a
  // transition (the tool sliding along it). Where the force jumps between two close samples
  // the equilibrium changes branch (the tissue snaps); where the two walks disagree, both
  // branches exist at one position and which one the tissue is on depends on the path.
  const Model m = load_model(o.nodes, o.law);
  pc::ConfigurationSolver solver(m.body, m.settings);
  const int samples = std::max(2, o.samples);
  std::vector<Vec3> at(static_cast<std::size_t>(samples));
  for (int k = 0; k < samples; ++k) at[static_cast<std::size_t>(k)] = o.from + (o.to - o.from) * (k / (samples - 1.0));
  auto from_rest = [&](const Vec3& x) {
    const double step = o.box / 2.0 / std::max(1, m.settings.load_steps) / 3.0;  // as the 20 mm grid's references
    return solver.solve_direct(m.contact + x, std::max(2, static_cast<int>(std::ceil(x.norm() / step))));
  };
  auto walk = [&](bool forward) {
    std::vector<pc::PointResult> out(at.size());
    for (std::size_t n = 0; n < at.size(); ++n) {
      const std::size_t k = forward ? n : at.size() - 1 - n;
      if (n == 0) {
        out[k] = from_rest(at[k]);
        continue;
      }
      const std::size_t before = forward ? k - 1 : k + 1;
      if (out[before].status != pc::PointStatus::solved) {  // the walk ends where a step fails
        out[k].reason = "the walk stopped before";
        continue;
      }
      out[k] = solver.transition(k, static_cast<std::int64_t>(before), out[before].displacement,
                                 m.contact + at[before], m.contact + at[k]);
    }
    return out;
  };
  const std::vector<pc::PointResult> up = walk(true), down = walk(false);
  auto cell = [](const pc::PointResult& r) {
    return r.status == pc::PointStatus::solved ? fmt::format("({:.3f}, {:.3f}, {:.3f})", r.force.x(), r.force.y(),
                                                             r.force.z())
                                               : std::string("not solved");
  };
  std::printf("| x [mm] | y [mm] | z [mm] | force from rest [N] | walked from the first end | from the last end |\n"
              "|---|---|---|---|---|---|\n");
  for (std::size_t k = 0; k < at.size(); ++k) {
    // Each walk starts from rest at its own end: those two are solved already.
    const pc::PointResult direct = k == 0 ? up[k] : k + 1 == at.size() ? down[k] : from_rest(at[k]);
    std::printf("| %.2f | %.2f | %.2f | %s | %s | %s |\n", 1e3 * at[k].x(), 1e3 * at[k].y(), 1e3 * at[k].z(),
                cell(direct).c_str(), cell(up[k]).c_str(), cell(down[k]).c_str());
    if (direct.status != pc::PointStatus::solved) std::printf("  from rest: %s\n", direct.reason.c_str());
  }
  return 0;
}

int probe(const Options& o) {
  const Model m = load_model(o.nodes, o.law);
  pc::SpaceSettings s = accuracy_grid(m, o.spacing, o.box);
  // The probe's end: every node within the patch radius of the contact node (as the scene's
  // patch_radius takes them).
  const VecX& rest = m.body.model->rest_positions();
  s.patch_radius = o.patch;
  s.patch_nodes.clear();
  for (Eigen::Index n = 0; n < rest.size() / 3; ++n)
    if ((rest.segment<3>(3 * n) - m.contact).norm() <= o.patch) s.patch_nodes.push_back(static_cast<std::int32_t>(n));
  s.probe.axis = Vec3(0.0, 0.0, -1.0);
  s.probe.max_tilt = o.tilt * std::numbers::pi / 180.0;
  s.probe.tilt_levels = o.levels;
  std::vector<std::shared_ptr<const pc::Space>> levels;
  double wall = 0.0, cpu = 0.0;
  std::size_t points = 0, failed = 0;
  for (std::size_t k = 0; k < s.probe.level_count(); ++k) {
    const pc::SpaceSettings level = pc::level_settings(s, k);
    auto space = std::make_shared<pc::Space>(pc::make_space(m.body, level, ""));
    pc::BuildOptions b;
    b.threads = o.threads;
    const double cpu0 = cpu_seconds();
    const pc::BuildStats st = pc::build_local(*space, factory(m, level), b);
    cpu += cpu_seconds() - cpu0;
    wall += st.wall_seconds;
    points += space->grid.size();
    failed += space->grid.size() - space->count(pc::PointStatus::solved);
    for (std::size_t p = 0; p < space->grid.size(); ++p)
      if (space->status[p] == pc::PointStatus::failed) {
        const Vec3 at = space->grid.point(p) - m.contact;
        std::printf("    lean (%+.1f, %+.1f) degrees: failed at (%+.1f, %+.1f, %+.1f) mm from the contact node: %s\n",
                    level.tilt.x() * 180.0 / std::numbers::pi, level.tilt.y() * 180.0 / std::numbers::pi,
                    1e3 * at.x(), 1e3 * at.y(), 1e3 * at.z(), space->reason[p].c_str());
      }
    levels.push_back(std::move(space));
  }
  std::printf("probe: %s, %zu nodes, %zu patch nodes, spacing %.4g mm, %d x %d leans up to %.1f degrees: %zu points "
              "(%zu per level), %zu not solved, %.1f s wall, %.3f CPU-seconds per point\n",
              o.law.c_str(), m.body.model->node_count(), s.patch_nodes.size(), 1e3 * o.spacing, o.levels, o.levels,
              o.tilt, points, levels.front()->grid.size(), failed, wall, cpu / static_cast<double>(points));
  std::fflush(stdout);

  // References: straight from rest to the position and lean, in load steps of at most a
  // third of a transition's.
  pc::ConfigurationSolver solver(m.body, pc::level_settings(s, 0));
  const pc::ProbeFrame frame(s.probe.axis);
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3 lo = m.contact + Vec3(0.0, 0.0, -o.box);
  std::vector<pc::PointResult> refs;
  std::vector<std::pair<Vec3, Vec3>> where;  // position, direction
  std::vector<pc::PointResult> level_refs;   // at the same positions, the nearest level's lean
  std::vector<Vec3> level_where;
  for (int tries = 0; static_cast<int>(refs.size()) < o.positions && tries < 20 * o.positions; ++tries) {
    const Vec3 p = lo + Vec3(u(rng), u(rng), u(rng)) * o.box;
    const Vec2 t = s.probe.max_tilt * Vec2(2.0 * u(rng) - 1.0, 2.0 * u(rng) - 1.0);
    // As the accuracy study: where every level's cell is solved (the interpolation's error,
    // not that of points missing).
    if (!std::all_of(levels.begin(), levels.end(), [&](const auto& l) { return cell_solved(*l, p); })) continue;
    const double step = o.spacing / std::max(1, s.load_steps) / 3.0;
    const int steps = std::max(2, static_cast<int>(std::ceil((p - m.contact).norm() / step)));
    pc::PointResult r = solver.solve_direct(p, frame.rotation(t), steps);
    if (r.status != pc::PointStatus::solved) {
      std::printf("  reference at (%.4f, %.4f, %.4f), lean (%.1f, %.1f) degrees failed: %s\n", p.x(), p.y(), p.z(),
                  t.x() * 180.0 / std::numbers::pi, t.y() * 180.0 / std::numbers::pi, r.reason.c_str());
      continue;
    }
    // The same position at the nearest level's lean: the error there is the position's
    // interpolation alone.
    const double step_lean = 2.0 * s.probe.max_tilt / (s.probe.tilt_levels - 1);
    const Vec2 snapped = (t / step_lean).array().round() * step_lean;
    pc::PointResult at_level = solver.solve_direct(p, frame.rotation(snapped), steps);
    if (at_level.status != pc::PointStatus::solved) continue;
    refs.push_back(std::move(r));
    where.emplace_back(p, frame.direction(t));
    level_refs.push_back(std::move(at_level));
    level_where.push_back(frame.direction(snapped));
  }
  double mean_force = 0.0;
  for (const auto& r : refs) mean_force += r.force.norm() / static_cast<double>(refs.size());
  std::printf("  %zu reference positions and leans (mean |force| %.4g N)\n", refs.size(), mean_force);
  double largest_torque = 0.0;
  for (const auto& r : refs) largest_torque = std::max(largest_torque, r.torque.norm());
  std::printf("| method | force error mean | force error max | at the levels' leans: mean | max | lean ignored: mean | "
              "max | query p50 | query p99 |\n|---|---|---|---|---|---|---|---|---|\n");
  std::vector<std::string> torque_rows;
  for (const auto method : {pc::Interpolation::trilinear, pc::Interpolation::tricubic_hermite}) {
    const pc::ProbeInterpolator in(levels, method);
    const std::size_t upright = s.probe.level_count() / 2;
    double mean = 0.0, worst = 0.0, mean_upright = 0.0, worst_upright = 0.0, mean_level = 0.0, worst_level = 0.0;
    for (std::size_t i = 0; i < refs.size(); ++i) {
      const double el = (in.force(where[i].first, level_where[i]).force - level_refs[i].force).norm() /
                        level_refs[i].force.norm();
      mean_level += el / static_cast<double>(refs.size());
      worst_level = std::max(worst_level, el);
      const double e = (in.force(where[i].first, where[i].second).force - refs[i].force).norm() /
                       refs[i].force.norm();
      const double e0 = (in.level(upright).force(where[i].first).force - refs[i].force).norm() / refs[i].force.norm();
      mean += e / static_cast<double>(refs.size());
      mean_upright += e0 / static_cast<double>(refs.size());
      worst = std::max(worst, e);
      worst_upright = std::max(worst_upright, e0);
    }
    // Query latency: 100,000 queries along a path through the box, leaning as it goes (sorted
    // nanoseconds of `query(p, d)`, which returns what it looked up).
    Vec3 sink = Vec3::Zero();
    auto latencies = [&](auto query) {
      std::vector<double> ns;
      ns.reserve(100'000);
      for (int i = 0; i < 100'000; ++i) {
        const double a = 1e-4 * i;
        const Vec3 p =
            lo + o.box * Vec3(0.5 + 0.4 * std::sin(a), 0.5 + 0.4 * std::cos(1.3 * a), 0.5 + 0.4 * std::sin(0.7 * a));
        const Vec3 d = frame.direction(s.probe.max_tilt * Vec2(std::sin(2.1 * a), std::cos(1.7 * a)));
        const auto t0 = std::chrono::steady_clock::now();
        sink += query(p, d);
        ns.push_back(std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count());
      }
      std::sort(ns.begin(), ns.end());
      return ns;
    };
    std::vector<double> ns = latencies([&](const Vec3& p, const Vec3& d) { return in.force(p, d).force; });
    std::printf("| %s | %.2f%% | %.2f%% | %.2f%% | %.2f%% | %.2f%% | %.2f%% | %.2f µs | %.2f µs |\n",
                std::string(pc::to_string(method)).c_str(), 100 * mean, 100 * worst, 100 * mean_level,
                100 * worst_level, 100 * mean_upright, 100 * worst_upright, 1e-3 * ns[ns.size() / 2],
                1e-3 * ns[ns.size() * 99 / 100]);

    // The torque about the probe's end, its errors relative to the sample's largest torque
    // (it passes through zero where the probe presses straight), and the force-and-torque
    // query's latency along the same path.
    double torque_mean = 0.0, torque_worst = 0.0;
    for (std::size_t i = 0; i < refs.size(); ++i) {
      const double e = (in.force_and_torque(where[i].first, where[i].second).torque - refs[i].torque).norm() /
                       largest_torque;
      torque_mean += e / static_cast<double>(refs.size());
      torque_worst = std::max(torque_worst, e);
    }
    ns = latencies([&](const Vec3& p, const Vec3& d) {
      const pc::Query q = in.force_and_torque(p, d);
      return Vec3(q.force + q.torque);
    });
    torque_rows.push_back(fmt::format("| {} | {:.2f}% | {:.2f}% | {:.2f} µs | {:.2f} µs |", pc::to_string(method),
                                      100 * torque_mean, 100 * torque_worst, 1e-3 * ns[ns.size() / 2],
                                      1e-3 * ns[ns.size() * 99 / 100]));
    if (!sink.allFinite()) std::printf("  (a query was not finite)\n");
  }
  if (largest_torque == 0.0) {
    std::printf("\n  no torque about the probe's end: an end of one node has no lever\n");
    return 0;
  }
  std::printf("\n  torque about the probe's end (largest in the sample %.4g N·m), errors relative to it:\n"
              "| method | torque error mean | torque error max | force and torque query p50 | p99 |\n"
              "|---|---|---|---|---|\n",
              largest_torque);
  for (const auto& row : torque_rows) std::printf("%s\n", row.c_str());
  return 0;
}

/// The rest stiffness condensed onto two nodes a and b: ∂(forces on a, b)/∂(positions of a,
/// b), 6 × 6 (exact for a linear body: F = K d).
Eigen::Matrix<double, 6, 6> rest_coupling(const physics::Body& original, std::int32_t a, std::int32_t b) {
  physics::Body body = original;
  body.fixed_dofs.resize(3 * body.model->node_count(), 0);
  body.fix_nodes({a, b});
  body.settings.solver = physics::LinearSolver::cholesky;
  body.gravity = Vec3::Zero();
  physics::BodyState state = physics::make_state(body);
  MatX held = MatX::Zero(state.x.size(), 6), motion, force_change;
  held.block<3, 3>(3 * a, 0).setIdentity();
  held.block<3, 3>(3 * b, 3).setIdentity();
  if (!physics::static_response(body, state, held, motion, force_change))
    throw std::runtime_error("the rest stiffness did not solve");
  Eigen::Matrix<double, 6, 6> k;
  k.topRows<3>() = force_change.middleRows<3>(3 * a);
  k.bottomRows<3>() = force_change.middleRows<3>(3 * b);
  return k;
}

/// A two-point space as `tactus precompute` builds it (precompute/pair.hpp): each point's space
/// with the other free, then each point's with the other held at each of its grid points.
int twopoint(const Options& o) {
  const Model ma = load_model(o.nodes, o.law);
  const Model mb = load_model(o.nodes, o.law, Vec3(o.separation, 0.0, 0.05));
  const std::int32_t a = ma.settings.contact_node, b = mb.settings.contact_node;
  const Vec3 rest_a = ma.contact, rest_b = mb.contact;
  // Each point a single node, or with --patch the nodes within that radius of it, with its
  // own grid (a box of --box along +x and +y and down).
  const VecX& rest = ma.body.model->rest_positions();
  auto patch_of = [&](std::int32_t node) {
    std::vector<std::int32_t> patch;
    for (Eigen::Index n = 0; n < rest.size() / 3; ++n)
      if (n == node || (rest.segment<3>(3 * n) - rest.segment<3>(3 * node)).norm() <= o.pair_patch)
        patch.push_back(static_cast<std::int32_t>(n));
    return patch;
  };
  pc::SpaceSettings s = accuracy_grid(ma, o.spacing, o.box);
  s.patch_nodes = patch_of(a);
  s.patch_radius = o.pair_patch;
  const pc::SpaceSettings sb = accuracy_grid(mb, o.spacing, o.box);
  s.pair.node = b;
  s.pair.patch_nodes = patch_of(b);
  std::printf("twopoint: patches of %zu and %zu nodes (--patch %.1f mm)\n", s.patch_nodes.size(),
              s.pair.patch_nodes.size(), 1e3 * o.pair_patch);
  s.pair.bounds_min = sb.bounds_min;
  s.pair.bounds_max = sb.bounds_max;
  const std::vector<pc::SpaceSettings> settings = pc::space_levels(s, ma.body.model->rest_positions());
  std::vector<std::shared_ptr<const pc::Space>> levels;
  std::size_t points = 0, solved = 0;
  double wall = 0.0;
  // --space FILE: the levels built by an earlier run of the same command, where its levels
  // are this space's (the same models, grids and held places); else built and written there.
  std::vector<pc::Space> saved;
  if (!o.space.empty() && std::filesystem::exists(o.space)) {
    saved = pc::read_space_levels(o.space);
    bool same = saved.size() == settings.size();
    for (std::size_t k = 0; same && k < settings.size(); ++k)
      same = saved[k].identity.model_hash == pc::make_space(ma.body, settings[k], "").identity.model_hash;
    if (!same) {
      std::fprintf(stderr, "twopoint: %s holds other levels than this command's\n", o.space.c_str());
      return 2;
    }
    std::printf("twopoint: %zu levels read from %s (their build times are those of the run that wrote them)\n",
                saved.size(), o.space.c_str());
  }
  for (std::size_t k = 0; k < settings.size(); ++k) {
    const pc::SpaceSettings& level = settings[k];
    pc::Space space = saved.empty() ? pc::make_space(ma.body, level, "") : std::move(saved[k]);
    pc::BuildOptions bo;
    bo.threads = o.threads;
    double w = 0.0;
    if (saved.empty()) w = pc::build_local(space, factory(ma, level), bo).wall_seconds;
    if (levels.size() < 2)
      std::printf("twopoint: point %c (node %d at (%.1f, %.1f, %.1f) mm) alone: %zu points, %zu not solved, %.1f s "
                  "wall\n",
                  levels.empty() ? 'A' : 'B', level.contact_node, 1e3 * (levels.empty() ? rest_a : rest_b).x(),
                  1e3 * (levels.empty() ? rest_a : rest_b).y(), 1e3 * (levels.empty() ? rest_a : rest_b).z(),
                  space.grid.size(), space.grid.size() - space.count(pc::PointStatus::solved), w);
    else {
      points += space.grid.size();
      solved += space.count(pc::PointStatus::solved);
      wall += w;
    }
    levels.push_back(std::make_shared<const pc::Space>(std::move(space)));
  }
  if (!o.space.empty() && saved.empty()) {
    std::vector<pc::Space> copies;
    for (const auto& l : levels) copies.push_back(*l);
    pc::write_space_levels(o.space, copies);
  }
  const pc::PairInterpolator pair(levels, pc::Interpolation::tricubic_hermite);
  const std::array<const pc::Space*, 2> spaces{levels[0].get(), levels[1].get()};
  std::printf("  held levels: %zu + %zu, %zu configurations, %zu solved, %.1f s wall on %u threads\n",
              spaces[1]->grid.size(), spaces[0]->grid.size(), points, solved, wall, o.threads);
  const Eigen::Matrix<double, 6, 6> k = rest_coupling(ma.body, a, b);
  const Mat3 k_ab = k.block<3, 3>(0, 3), k_ba = k.block<3, 3>(3, 0);
  std::printf("  rest coupling: |K_AB| %.4g N/m, |K_AA| %.4g N/m (Frobenius); K_BA = K_ABᵀ to %.2g\n", k_ab.norm(),
              k.block<3, 3>(0, 0).norm(), (k_ba - k_ab.transpose()).norm() / k_ab.norm());
  // The references: each point's force with both held, walked straight from rest.
  std::array<pc::SpaceSettings, 2> held{pc::pair_point(s, 0), pc::pair_point(s, 1)};
  for (auto& h : held) {
    h.held_node = h.pair.node;
    h.held_patch = h.pair.patch_nodes;
  }
  const pc::Interpolator ia(levels[0], pc::Interpolation::tricubic_hermite);
  const pc::Interpolator ib(levels[1], pc::Interpolation::tricubic_hermite);
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  struct Errors {
    double mean = 0.0, max = 0.0;
    void add(double e, std::size_t n) {
      mean += e / static_cast<double>(n);
      max = std::max(max, e);
    }
  };
  std::vector<std::array<Vec3, 2>> where, truth;
  for (int tries = 0; static_cast<int>(where.size()) < o.positions && tries < 20 * o.positions; ++tries) {
    const Vec3 pa = rest_a + Vec3(u(rng), u(rng), u(rng) - 1.0) * o.box;
    const Vec3 pb = rest_b + Vec3(u(rng), u(rng), u(rng) - 1.0) * o.box;
    if (!cell_solved(*spaces[0], pa) || !cell_solved(*spaces[1], pb)) continue;
    if (!pair.force(0, pa, &pb).valid || !pair.force(1, pb, &pa).valid) continue;  // the levels have a value there
    const double step = o.spacing / 6.0;
    const int steps = std::max(2, static_cast<int>(std::ceil(std::max((pa - rest_a).norm(), (pb - rest_b).norm()) / step)));
    std::array<Vec3, 2> f;
    bool ok = true;
    for (std::size_t finger = 0; finger < 2 && ok; ++finger) {
      held[finger].held_at = finger == 0 ? pb : pa;
      pc::ConfigurationSolver solver(ma.body, held[finger]);
      const pc::PointResult r = solver.solve_direct(finger == 0 ? pa : pb, steps);
      ok = r.status == pc::PointStatus::solved;
      f[finger] = r.force;
    }
    if (!ok) {
      std::printf("  reference at A (%.4f, %.4f, %.4f), B (%.4f, %.4f, %.4f) failed\n", pa.x(), pa.y(), pa.z(), pb.x(),
                  pb.y(), pb.z());
      continue;
    }
    where.push_back({pa, pb});
    truth.push_back(f);
  }
  const std::size_t n = where.size();
  Errors alone, corrected, at_configuration, paired;
  // Also against the sample's mean force: a finger barely loaded makes the relative error
  // large where the newtons are few.
  Errors alone_n, corrected_n, at_configuration_n, paired_n;
  int across_levels = 0, lowered_levels = 0, within_levels = 0;
  // The two-point space's relative errors by route: all 27 levels and their Hermite cells
  // whole, trilinear across levels, a level that fell back within itself only, or a stencil
  // of levels linear along one or two axes.
  std::array<std::vector<double>, 4> by_route;
  double mean_force = 0.0, mean_change = 0.0;
  for (const auto& t : truth) mean_force += (t[0].norm() + t[1].norm()) / static_cast<double>(2 * n);
  VecX ua, ub;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& [pa, pb] = where[i];
    const pc::Query qa = ia.shape(pa, ua), qb = ib.shape(pb, ub);
    // Where the other point sits in each point's own configuration, and how far the other
    // finger moves it from there.
    const Vec3 b_in_a = rest_b + ua.segment<3>(3 * b), a_in_b = rest_a + ub.segment<3>(3 * a);
    const std::array<Vec3, 2> own{qa.force, qb.force};
    const std::array<Vec3, 2> fixed{qa.force + k_ab * (pb - b_in_a), qb.force + k_ba * (pa - a_in_b)};
    // The coupling at the configurations instead of at rest: from each space's stiffness and
    // the other point's displacement gradient at its nearest grid point (two-point condensed
    // stiffness from single-point data: K_AA = K_A (I − G_AB G_BA)⁻¹, K_AB = −K_AA G_AB, with
    // G_XY = ∂u_X/∂p_Y; exact for a linear body).
    const std::size_t na = spaces[0]->grid.nearest(pa), nb = spaces[1]->grid.nearest(pb);
    const Mat3 g_ba = spaces[0]->displacement_gradient.block<3, 3>(3 * b, 3 * static_cast<Eigen::Index>(na));
    const Mat3 g_ab = spaces[1]->displacement_gradient.block<3, 3>(3 * a, 3 * static_cast<Eigen::Index>(nb));
    const Mat3 k_aa = spaces[0]->force_gradient[na] * (Mat3::Identity() - g_ab * g_ba).inverse();
    const Mat3 k_bb = spaces[1]->force_gradient[nb] * (Mat3::Identity() - g_ba * g_ab).inverse();
    const std::array<Vec3, 2> local{qa.force - k_aa * g_ab * (pb - b_in_a), qb.force - k_bb * g_ba * (pa - a_in_b)};
    const std::array<pc::Query, 2> from_pair{pair.force(0, pa, &pb), pair.force(1, pb, &pa)};
    for (std::size_t k2 = 0; k2 < 2; ++k2) {
      across_levels += from_pair[k2].across_levels ? 1 : 0;
      lowered_levels += from_pair[k2].levels_lowered ? 1 : 0;
      within_levels += from_pair[k2].fallback ? 1 : 0;
      const double scale = truth[i][k2].norm();
      const pc::Query& qp = from_pair[k2];
      by_route[qp.across_levels ? 1 : qp.levels_lowered ? 3 : qp.fallback ? 2 : 0].push_back(
          (from_pair[k2].force - truth[i][k2]).norm() / scale);
      paired.add((from_pair[k2].force - truth[i][k2]).norm() / scale, 2 * n);
      paired_n.add((from_pair[k2].force - truth[i][k2]).norm() / mean_force, 2 * n);
      alone.add((own[k2] - truth[i][k2]).norm() / scale, 2 * n);
      corrected.add((fixed[k2] - truth[i][k2]).norm() / scale, 2 * n);
      at_configuration.add((local[k2] - truth[i][k2]).norm() / scale, 2 * n);
      alone_n.add((own[k2] - truth[i][k2]).norm() / mean_force, 2 * n);
      corrected_n.add((fixed[k2] - truth[i][k2]).norm() / mean_force, 2 * n);
      at_configuration_n.add((local[k2] - truth[i][k2]).norm() / mean_force, 2 * n);
      mean_change += (own[k2] - truth[i][k2]).norm() / static_cast<double>(2 * n);
    }
  }
  std::printf("  %zu reference pairs (mean |force| %.4g N; the other finger changes a finger's force by %.4g N on "
              "average)\n",
              n, mean_force, mean_change);
  std::printf("| prediction | force error mean | max | against the mean force: mean | max |\n|---|---|---|---|---|\n");
  auto row = [](const char* name, const Errors& e, const Errors& en) {
    std::printf("| %s | %.2f%% | %.2f%% | %.2f%% | %.2f%% |\n", name, 100 * e.mean, 100 * e.max, 100 * en.mean,
                100 * en.max);
  };
  row("each point's space alone", alone, alone_n);
  // The couplings are those of the two nodes: with patches they are not the fingers'.
  if (o.pair_patch <= 0.0) {
    row("corrected by the rest coupling", corrected, corrected_n);
    row("corrected by the coupling at the configurations", at_configuration, at_configuration_n);
  }
  row("two-point space", paired, paired_n);
  std::printf("  (of %zu forces, where one of the 27 levels around the other point had no value, the two-point "
              "space made its stencil linear along one or two axes for %d and combined %d trilinearly across levels; "
              "%d used a level that fell back within itself, where a Hermite cell lacked a point)\n",
              2 * n, lowered_levels, across_levels, within_levels);
  const std::array<const char*, 4> route_names{"every level and cell whole", "trilinear across levels",
                                               "a level fell back within itself only",
                                               "stencil linear along one or two axes"};
  for (std::size_t r = 0; r < by_route.size(); ++r) {
    const auto& e = by_route[r];
    if (e.empty()) continue;
    double sum = 0.0;
    for (double x : e) sum += x;
    std::printf("  two-point space, %s: %zu forces, mean %.2f%%, max %.2f%%\n", route_names[r], e.size(),
                100.0 * sum / static_cast<double>(e.size()), 100.0 * *std::max_element(e.begin(), e.end()));
  }
  // Query latency: 100,000 queries of the first point's force, both points moving through
  // their boxes.
  std::vector<double> ns;
  ns.reserve(100'000);
  Vec3 sink = Vec3::Zero();
  for (int i = 0; i < 100'000; ++i) {
    const double t = 1e-4 * i;
    const Vec3 pa =
        rest_a + o.box * Vec3(0.5 + 0.4 * std::sin(t), 0.5 + 0.4 * std::cos(1.3 * t), -0.5 + 0.4 * std::sin(0.7 * t));
    const Vec3 pb = rest_b + o.box * Vec3(0.5 + 0.4 * std::cos(0.9 * t), 0.5 + 0.4 * std::sin(1.1 * t),
                                          -0.5 + 0.4 * std::cos(0.6 * t));
    const auto t0 = std::chrono::steady_clock::now();
    sink += pair.force(0, pa, &pb).force;
    ns.push_back(std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(ns.begin(), ns.end());
  std::printf("  force query (27 levels, tricubic Hermite within each): p50 %.2f µs, p99 %.2f µs, max %.2f µs%s\n",
              1e-3 * ns[ns.size() / 2], 1e-3 * ns[ns.size() * 99 / 100], 1e-3 * ns.back(),
              sink.allFinite() ? "" : " (a query was not finite)");
  return 0;
}

int online(const Options& o) {
  const Model m = load_model(o.nodes, o.law);
  const pc::SpaceSettings s = accuracy_grid(m, o.spacing);
  const pc::Space layout = pc::make_space(m.body, s, "");
  double load[3] = {0, 0, 0};
  getloadavg(load, 3);
  std::printf("online: %s, %zu nodes, spacing %.4g m, grid %d x %d x %d = %zu points, %u solver threads, "
              "load average %.2f\n",
              o.law.c_str(), m.body.model->node_count(), s.spacing, layout.grid.counts[0], layout.grid.counts[1],
              layout.grid.counts[2], layout.grid.size(), o.threads, load[0]);
  pc::OnlineSpeedOptions opt;
  opt.workers = o.threads;
  opt.first = o.first * 1e-3;
  opt.bisections = 2;
  std::vector<double> measured(layout.grid.size(), 0.0);
  opt.on_trial = [&](const pc::DriveResult& r, const pc::Space& space) {
    std::printf("  %7.2f mm/s: %5.1f%% of %zu queries complete (moved after %.2f s), %zu points solved, "
                "max force step %.3g N, finite %s\n",
                1e3 * r.speed, 100.0 * r.fraction(), r.queries, r.wait, r.solved, r.max_step, r.finite ? "yes" : "NO");
    std::fflush(stdout);
    for (std::size_t p = 0; p < space.grid.size(); ++p)
      if (space.status[p] == pc::PointStatus::solved) measured[p] = std::max(measured[p], space.seconds[p]);
  };
  const pc::SpeedSearch search = pc::online_speed(m.body, s, opt);
  getloadavg(load, 3);
  std::printf("maximum tool speed: %s%.2f mm/s with %u solver threads (>= 99%% of queries complete while moving); "
              "load average at the end %.2f\n",
              search.bounded ? "" : "at least ", 1e3 * search.max_speed, o.threads, load[0]);

  // The model: the same search in simulated time, each point costing its measured solve time
  // (the median of the measured ones where a point was never solved).
  std::vector<double> known;
  for (double v : measured)
    if (v > 0.0) known.push_back(v);
  if (known.empty()) return 0;
  std::nth_element(known.begin(), known.begin() + static_cast<std::ptrdiff_t>(known.size() / 2), known.end());
  const double median = known[known.size() / 2];
  auto cost = [&](std::size_t p) { return measured[p] > 0.0 ? measured[p] : median; };
  pc::ToolPath path = pc::scripted_path(layout.grid, layout.start);
  path.dwell = opt.dwell;
  std::printf("simulated with the measured solve times (median %.3f s per point):\n", median);
  for (unsigned w : {1u, 2u, 4u, 8u, 16u, 64u}) {
    const pc::SpeedSearch sim = pc::search_speed(
        [&](double v) {
          path.speed = v;
          return pc::simulate_online(layout.grid, layout.start, path, w, cost);
        },
        0.0005, 0.99, 6, 1.0);
    std::printf("  %2u workers: %.2f mm/s\n", w, 1e3 * sim.max_speed);
  }
  return 0;
}

int compare(const std::string& a_path, const std::string& b_path) {
  const std::vector<pc::Space> a_levels = pc::read_space_levels(a_path), b_levels = pc::read_space_levels(b_path);
  if (a_levels.size() != b_levels.size()) {
    std::printf("different numbers of probe levels\n");
    return 2;
  }
  std::size_t points = 0, solved = 0, differ = 0;
  for (std::size_t k = 0; k < a_levels.size(); ++k) {
    const pc::Space &a = a_levels[k], &b = b_levels[k];
    if (a.identity.model_hash != b.identity.model_hash || a.grid.size() != b.grid.size()) {
      std::printf("different models or grids\n");
      return 2;
    }
    for (std::size_t p = 0; p < a.grid.size(); ++p) {
      const auto c = static_cast<Eigen::Index>(p);
      if (a.status[p] != b.status[p] || a.source[p] != b.source[p] || a.force[p] != b.force[p] ||
          a.displacement.col(c) != b.displacement.col(c))
        ++differ;
    }
    points += a.grid.size();
    solved += a.count(pc::PointStatus::solved);
  }
  std::printf("%zu points, %zu solved in both; %zu differ\n", points, solved, differ);
  return differ ? 2 : 0;
}

int usage() {
  std::fprintf(stderr,
               "usage: precompute_bench compare A.h5 B.h5\n"
               "       precompute_bench line --nodes N --law L --from X,Y,Z --to X,Y,Z [--samples K]\n"
               "       precompute_bench cost|scaling|query|accuracy|online|probe|twopoint [--nodes N] [--law stvk|mooney_rivlin|mooney_rivlin_049|mooney_rivlin_nodal]\n"
               "         [--spacing S] [--points K] [--seconds T] [--positions M] [--threads N] [--seed S] [--space FILE]\n"
               "         [--box MM] [--spacings MM,MM,...] [--refine K] [--worst W] [--cells 1] [--tilt DEG] [--levels n] [--patch MM]\n"
               "         [--separation MM]\n");
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  if (std::string(argv[1]) == "compare") {
    if (argc != 4) return usage();
    try {
      return compare(argv[2], argv[3]);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      return 1;
    }
  }
  // The parallelism is across configurations: one thread per solve.
  set_thread_limit(1);
  try {
    Options o;
    o.command = argv[1];
    if ((argc - 2) % 2 != 0) return usage();  // every option takes a value
    for (int i = 2; i + 1 < argc; i += 2) {
      const std::string key = argv[i], value = argv[i + 1];
      if (key == "--nodes") o.nodes = std::stoi(value);
      else if (key == "--law") o.law = value;
      else if (key == "--spacing") o.spacing = std::stod(value);
      else if (key == "--points") o.points = std::stoul(value);
      else if (key == "--seconds") o.seconds = std::stod(value);
      else if (key == "--positions") o.positions = std::stoi(value);
      else if (key == "--threads") o.threads = static_cast<unsigned>(std::stoul(value));
      else if (key == "--seed") o.seed = static_cast<unsigned>(std::stoul(value));
      else if (key == "--space") o.space = value;
      else if (key == "--first") o.first = std::stod(value);
      else if (key == "--box") o.box = 1e-3 * std::stod(value);
      else if (key == "--refine") o.refine = std::stoul(value);
      else if (key == "--worst") o.worst = std::stoul(value);
      else if (key == "--cells") o.cells = std::stoi(value) != 0;
      else if (key == "--samples") o.samples = std::stoi(value);
      else if (key == "--from" || key == "--to") {
        Vec3 v;
        if (std::sscanf(value.c_str(), "%lf,%lf,%lf", &v.x(), &v.y(), &v.z()) != 3) return usage();
        (key == "--from" ? o.from : o.to) = 1e-3 * v;
      }
      else if (key == "--tilt") o.tilt = std::stod(value);
      else if (key == "--patch") o.patch = o.pair_patch = 1e-3 * std::stod(value);
      else if (key == "--separation") o.separation = 1e-3 * std::stod(value);
      else if (key == "--levels") o.levels = std::stoi(value);
      else if (key == "--spacings") {
        o.spacings.clear();
        std::stringstream list(value);
        for (std::string mm; std::getline(list, mm, ',');) o.spacings.push_back(1e-3 * std::stod(mm));
      }
      else return usage();
    }
    if (o.command == "line") return line(o);
    if (o.command == "cost") return cost(o);
    if (o.command == "scaling") return scaling(o);
    if (o.command == "query") return query(o);
    if (o.spacings.empty()) o.spacings = {o.box / 2, o.box / 3, o.box / 4, o.box / 6};
    // A spacing given to a few digits (6.667 mm) is the box's divisor it rounds from, so the
    // grid reaches the box's far side.
    for (double& d : o.spacings)
      if (const double n = std::round(o.box / d); std::abs(o.box / n - d) < 1e-3 * d) d = o.box / n;
    if (o.command == "accuracy") return accuracy(o);
    if (o.command == "online") return online(o);
    if (o.command == "probe") return probe(o);
    if (o.command == "twopoint") return twopoint(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return usage();
}
