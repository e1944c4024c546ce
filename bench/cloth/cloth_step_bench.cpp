// The cloth global step of issue 25: a 20 × 20 cm denim sheet (data/fabrics.toml [denim])
// hanging from a clamped top edge, released from a 0.3 rad tilt out of its plane, one
// implicit Euler step per global step at dt = 10 ms and 2 ms, with the assembled
// Gauss–Seidel CG at its default tolerance (1e-4) or with CHOLMOD, at 5 mm (41 × 41 nodes)
// and 2.5 mm (81 × 81). Each run steps 0.1 s of simulated time (at least 20 steps) untimed,
// so that the sheet swings and the solver's caches and warm start are filled, then times
// 300 steps one by one.
// Counters: median and p90 step time [ms], mean and largest CG iterations, the mean time of
// the step's parts [ms] (forces with the linearization, assembly, linear solve; from
// physics::StepProfile), and the bottom edge's sideways swing over the timed steps [mm]. The
// label ends with a hash of the final positions, to check that a change keeps the bits.
// Run with OPENBLAS_NUM_THREADS=1 (docs/BENCHMARKS.md, "Cloth global step (issue 25)").
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <string>
#include <vector>

#include "hanging_sheet.hpp"

namespace {

using namespace tactus;
using namespace tactus::physics;
using namespace tactus::bench_cloth;

constexpr int kTimedSteps = 300;

void BM_ClothStep(benchmark::State& state) {
  const double spacing = state.range(0) == 0 ? 0.005 : 0.0025;
  const double dt = 1e-3 * static_cast<double>(state.range(1));
  const auto solver = static_cast<LinearSolver>(state.range(2));
  HangingSheet sheet = hanging_sheet(spacing, solver);
  BodyState s = make_state(sheet.body);
  s.x = sheet.start;
  const int warm_steps = std::max(20, static_cast<int>(std::lround(0.1 / dt)));
  for (int i = 0; i < warm_steps; ++i) step(sheet.body, s, dt);

  StepProfile profile;
  s.profile = &profile;
  std::vector<double> times;
  times.reserve(kTimedSteps);
  double iterations = 0.0, swing_min = s.x[3 * sheet.tip + 1], swing_max = swing_min;
  int most_iterations = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    step(sheet.body, s, dt);
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    iterations += s.last_linear_iterations;
    most_iterations = std::max(most_iterations, s.last_linear_iterations);
    swing_min = std::min(swing_min, s.x[3 * sheet.tip + 1]);
    swing_max = std::max(swing_max, s.x[3 * sheet.tip + 1]);
  }
  if (!s.x.allFinite()) {
    state.SkipWithError("the state became non-finite");
    return;
  }
  const auto steps = static_cast<double>(times.size());
  std::sort(times.begin(), times.end());
  state.counters["nodes"] = static_cast<double>(sheet.body.model->node_count());
  state.counters["median_ms"] = 1e3 * times[times.size() / 2];
  state.counters["p90_ms"] = 1e3 * times[std::min(times.size() - 1, times.size() * 9 / 10)];
  state.counters["cg_iters"] = iterations / steps;
  state.counters["cg_max"] = most_iterations;
  state.counters["forces_ms"] = 1e3 * profile.forces / steps;
  state.counters["assembly_ms"] = 1e3 * profile.assembly / steps;
  state.counters["solve_ms"] = 1e3 * profile.solve / steps;
  state.counters["swing_mm"] = 1e3 * (swing_max - swing_min);
  char hash[32];
  std::snprintf(hash, sizeof hash, "%016" PRIx64, state_hash(s.x));
  state.SetLabel(std::string(solver == LinearSolver::cholesky ? "cholmod" : "cg 1e-4") + " x=" + hash);
}

void cases(benchmark::internal::Benchmark* b) {
  const int cg = static_cast<int>(LinearSolver::conjugate_gradient), chol = static_cast<int>(LinearSolver::cholesky);
  for (int mesh : {0, 1})
    for (int dt_ms : {10, 2})
      for (int solver : {cg, chol}) b->Args({mesh, dt_ms, solver});
}

// Arguments: mesh (0: 5 mm, 1: 2.5 mm), dt [ms], solver (LinearSolver: 0 CG, 1 CHOLMOD).
BENCHMARK(BM_ClothStep)->Apply(cases)->Iterations(kTimedSteps)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
