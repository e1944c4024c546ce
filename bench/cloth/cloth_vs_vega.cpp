// The cloth step of issue 25 side by side with Vega FEM's Baraff–Witkin cloth (clothBW,
// stepped by Vega's ImplicitBackwardEulerSparse with its Jacobi CG; vega/README.md): the
// same 20 × 20 cm sheet (hanging_sheet.hpp), node for node and triangle for triangle, the same
// node masses, clamp, gravity, release from the tilt, time step and warm-up, one implicit
// step per frame. In each round the two codes run one after the other; the table gives the
// medians over the rounds of each run's median and p90 step time.
//
// The mapping onto clothBW's parameters (per triangle of rest area A, α = A^¾ in clothBW):
// - stretch: clothBW's ½k_t α²(|w_u| − 1)² against Tactus's A·∫T dε ≈ ½A·k ε², so
//   k_t = k/√A with k [N/m] a slope of the warp curve. The KES curve has no linear range
//   (T ∝ ε^2.05 for denim, slope 0 at rest), so k is its tangent at the strain of the
//   tension at mid-height of the hanging sheet (ρ_A g L/2), and, for the sensitivity, the
//   secant F_m/EMT of the tensile test (29× stiffer: 8,550 against 292 N/m);
// - shear: ½k_s α²(w_u·w_v)² against ½A·G γ² (w_u·w_v = sin γ at rest length): k_s = G/√A;
// - bending: ½k_b θ² per interior edge; a cylindrical fold of curvature κ turns the edges
//   across it by θ = κh, one such edge per h² of fabric, so the energy per area ½k_b κ²
//   equals ½Bκ² with k_b = B. clothBW gives an edge along u its bend_u: the fold along u
//   bends the weft, so bend_u = B_weft and bend_v = B_warp (equal for this denim);
// - damping: Tactus damps each term by its time constant β times its stiffness; with the
//   three β equal (2 ms) that is Vega's Rayleigh damping D = β·K (no mass term).
// Tactus bends along its yarn lines (three nodes of a warp or weft line); clothBW at every
// interior edge, diagonals included.
//
// Usage: cloth_vs_vega [rounds=3] [spacing_mm=5]. Run with OPENBLAS_NUM_THREADS=1.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "hanging_sheet.hpp"
#include "vega_cloth.hpp"

namespace {

using namespace tactus;
using namespace tactus::physics;
using namespace tactus::bench_cloth;

constexpr int kTimedSteps = 300;

int warm_steps(double dt) { return std::max(20, static_cast<int>(std::lround(0.1 / dt))); }

struct Run {
  double median = 0.0, p90 = 0.0;  ///< [s]
  double iterations = 0.0;         ///< mean per step
  double forces = 0.0, solve = 0.0;  ///< mean per step [s]
  double swing = 0.0;              ///< sideways range of the bottom edge's middle [m]
};

void finish(std::vector<double>& times, Run& r) {
  std::sort(times.begin(), times.end());
  r.median = times[times.size() / 2];
  r.p90 = times[std::min(times.size() - 1, times.size() * 9 / 10)];
}

Run run_tactus(double spacing, double dt, LinearSolver solver, double tolerance) {
  HangingSheet sheet = hanging_sheet(spacing, solver);
  sheet.body.settings.cg_tolerance = tolerance;
  BodyState s = make_state(sheet.body);
  s.x = sheet.start;
  for (int i = 0; i < warm_steps(dt); ++i) step(sheet.body, s, dt);
  StepProfile profile;
  s.profile = &profile;
  std::vector<double> times;
  Run r;
  double lo = s.x[3 * sheet.tip + 1], hi = lo;
  for (int i = 0; i < kTimedSteps; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    step(sheet.body, s, dt);
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    r.iterations += s.last_linear_iterations;
    lo = std::min(lo, s.x[3 * sheet.tip + 1]);
    hi = std::max(hi, s.x[3 * sheet.tip + 1]);
  }
  if (!s.x.allFinite()) std::fprintf(stderr, "tactus: the state became non-finite\n");
  r.iterations /= kTimedSteps;
  r.forces = profile.forces / kTimedSteps;
  r.solve = profile.solve / kTimedSteps;
  r.swing = hi - lo;
  finish(times, r);
  return r;
}

enum class Tensile { tangent, secant };

/// The strain at which the warp curve reaches `tension` (bisection on the monotone curve).
double strain_at(const MeasuredCurve& c, double tension) {
  double lo = 0.0, hi = 1.0;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (c.value(mid) < tension ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

struct Mapping {
  double k = 0.0, area = 0.0;
  vega_bench::ClothSetup setup;
};

Mapping vega_setup(const HangingSheet& sheet, double spacing, double dt, Tensile tensile) {
  const auto& model = static_cast<const ClothModel&>(*sheet.body.model);
  const ClothMaterial& m = model.material();
  const auto& uv = sheet.grid.cloth.uv;
  Mapping out;
  vega_bench::ClothSetup& s = out.setup;
  const VecX& rest = model.rest_positions();
  s.rest.assign(rest.data(), rest.data() + rest.size());
  for (Eigen::Index n = 0; n < rest.size() / 3; ++n) s.masses.push_back(model.lumped_mass()[3 * n]);
  for (const auto& t : model.triangles()) {
    for (auto n : t) {
      s.triangles.push_back(n);
      s.triangle_uv.push_back(uv[static_cast<std::size_t>(n)].x());
      s.triangle_uv.push_back(uv[static_cast<std::size_t>(n)].y());
    }
    const Vec2 e1 = uv[static_cast<std::size_t>(t[1])] - uv[static_cast<std::size_t>(t[0])];
    const Vec2 e2 = uv[static_cast<std::size_t>(t[2])] - uv[static_cast<std::size_t>(t[0])];
    const double area = 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
    if (out.area == 0.0) out.area = area;
    if (std::abs(area - out.area) > 1e-12 * out.area) throw std::runtime_error("the mapping needs equal triangles");
  }
  const double free_length = kSide - spacing;  // below the clamp
  const double emt = m.warp.xs().back();  // the tensile curve's last point: EMT
  out.k = tensile == Tensile::tangent ? m.warp.slope(strain_at(m.warp, 0.5 * m.areal_density * kGravity * free_length))
                                      : m.warp.value(emt) / emt;
  const double root = std::sqrt(out.area);
  s.tensile = out.k / root;
  s.shear = m.shear.slope(0.0) / root;
  s.bend_u = m.bend_weft.slope(0.0);
  s.bend_v = m.bend_warp.slope(0.0);
  for (std::size_t d = 0; d < sheet.body.fixed_dofs.size(); ++d)
    if (sheet.body.fixed_dofs[d]) s.fixed_dofs.push_back(static_cast<int>(d));
  s.external.assign(s.rest.size(), 0.0);
  for (std::size_t n = 0; n < s.masses.size(); ++n) s.external[3 * n + 2] = -kGravity * s.masses[n];
  s.dt = dt;
  s.damping_stiffness = kDamping;
  return out;
}

/// Vega's run: timed, or (count) untimed with each step's system solved again to count the
/// integrator's CG iterations and to time its CG at Tactus's tolerance 1e-4.
Run run_vega(double spacing, double dt, Tensile tensile, bool count, double* cg_1e4 = nullptr,
             double* iterations_1e4 = nullptr) {
  const HangingSheet sheet = hanging_sheet(spacing, LinearSolver::conjugate_gradient);
  const Mapping map = vega_setup(sheet, spacing, dt, tensile);
  vega_bench::Cloth cloth(map.setup);
  std::vector<double> u(map.setup.rest.size()), v(u.size(), 0.0);
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = sheet.start[static_cast<Eigen::Index>(i)] - map.setup.rest[i];
  cloth.set_state(u, v);
  double seconds = 0.0;
  for (int i = 0; i < warm_steps(dt); ++i) {
    cloth.step();
    if (count) cloth.resolve(1e-6, seconds);
  }
  std::vector<double> times;
  Run r;
  const auto tip_y = [&] { return map.setup.rest[3 * static_cast<std::size_t>(sheet.tip) + 1] + cloth.displacements()[3 * sheet.tip + 1]; };
  double lo = tip_y(), hi = lo, time_1e4 = 0.0, its_1e4 = 0.0;
  for (int i = 0; i < kTimedSteps; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    cloth.step();
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    r.forces += cloth.force_time();
    r.solve += cloth.solve_time();
    if (count) {
      r.iterations += cloth.resolve(1e-6, seconds);
      its_1e4 += cloth.resolve(1e-4, seconds);
      time_1e4 += seconds;
    }
    lo = std::min(lo, tip_y());
    hi = std::max(hi, tip_y());
  }
  for (std::size_t i = 0; i < u.size(); ++i)
    if (!std::isfinite(cloth.displacements()[i])) {
      std::fprintf(stderr, "vega: the state became non-finite\n");
      break;
    }
  r.iterations /= kTimedSteps;
  r.forces /= kTimedSteps;
  r.solve /= kTimedSteps;
  r.swing = hi - lo;
  if (cg_1e4) *cg_1e4 = time_1e4 / kTimedSteps;
  if (iterations_1e4) *iterations_1e4 = its_1e4 / kTimedSteps;
  finish(times, r);
  return r;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const int rounds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  const double spacing = 1e-3 * (argc > 2 ? std::atof(argv[2]) : 5.0);
  {
    const HangingSheet sheet = hanging_sheet(spacing, LinearSolver::conjugate_gradient);
    for (Tensile t : {Tensile::tangent, Tensile::secant}) {
      const Mapping map = vega_setup(sheet, spacing, 0.01, t);
      std::printf("%s tensile slope k = %.1f N/m; clothBW: tensile %.4g, shear %.4g, bend_u %.4g, bend_v %.4g, "
                  "Rayleigh %.3g s·K (triangle area %.4g m², %zu nodes, %zu fixed dofs)\n",
                  t == Tensile::tangent ? "tangent at mid-height" : "secant F_m/EMT", map.k, map.setup.tensile,
                  map.setup.shear, map.setup.bend_u, map.setup.bend_v, map.setup.damping_stiffness, map.area,
                  map.setup.masses.size(), map.setup.fixed_dofs.size());
    }
  }
  struct Row {
    const char* name;
    std::vector<double> median, p90, iterations, forces, solve, swing;
  };
  for (double dt : {0.010, 0.002}) {
    std::vector<Row> rows{{"Tactus, block Gauss-Seidel CG 1e-4", {}, {}, {}, {}, {}, {}},
                          {"Tactus, block Gauss-Seidel CG 1e-6", {}, {}, {}, {}, {}, {}},
                          {"Tactus, CHOLMOD", {}, {}, {}, {}, {}, {}},
                          {"Vega clothBW, Jacobi CG 1e-6, tensile tangent", {}, {}, {}, {}, {}, {}},
                          {"Vega clothBW, Jacobi CG 1e-6, tensile secant", {}, {}, {}, {}, {}, {}}};
    auto add = [](Row& row, const Run& r) {
      row.median.push_back(r.median);
      row.p90.push_back(r.p90);
      row.iterations.push_back(r.iterations);
      row.forces.push_back(r.forces);
      row.solve.push_back(r.solve);
      row.swing.push_back(r.swing);
    };
    for (int round = 0; round < rounds; ++round) {
      add(rows[0], run_tactus(spacing, dt, LinearSolver::conjugate_gradient, 1e-4));
      add(rows[3], run_vega(spacing, dt, Tensile::tangent, false));
      add(rows[1], run_tactus(spacing, dt, LinearSolver::conjugate_gradient, 1e-6));
      add(rows[4], run_vega(spacing, dt, Tensile::secant, false));
      add(rows[2], run_tactus(spacing, dt, LinearSolver::cholesky, 1e-4));
    }
    // Vega's iterations, and its CG at 1e-4 on the same systems, from an untimed pass.
    double cg_1e4[2] = {}, its_1e4[2] = {};
    for (int t = 0; t < 2; ++t) {
      const Run counted = run_vega(spacing, dt, t == 0 ? Tensile::tangent : Tensile::secant, true, &cg_1e4[t], &its_1e4[t]);
      rows[3 + static_cast<std::size_t>(t)].iterations.assign(1, counted.iterations);
    }
    const double reference = median(rows[0].median);
    std::printf("\n%.0f mm, dt = %.0f ms, %d rounds of %d timed steps after %d untimed\n\n", 1e3 * spacing, 1e3 * dt,
                rounds, kTimedSteps, warm_steps(dt));
    std::printf("| code, solver | median [ms] | p90 [ms] | / Tactus CG 1e-4 | CG iterations | forces + K [ms] | solve [ms] | swing [mm] |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const Row& row : rows)
      std::printf("| %s | %.3f | %.3f | %.2f | %.1f | %.3f | %.3f | %.1f |\n", row.name, 1e3 * median(row.median),
                  1e3 * median(row.p90), median(row.median) / reference, median(row.iterations),
                  1e3 * median(row.forces), 1e3 * median(row.solve), 1e3 * median(row.swing));
    for (int t = 0; t < 2; ++t)
      std::printf("Vega's Jacobi CG to 1e-4 on the same systems (%s): %.1f iterations, %.3f ms a step\n",
                  t == 0 ? "tangent" : "secant", its_1e4[t], 1e3 * cg_1e4[t]);
  }
  return 0;
}
