// Implicit Euler step time of tetrahedral FEM bodies against element count: box meshes
// near the seed 003 series (158 ... 14540 tets) and a liver-sized ~10k-tet block, soft
// tissue (E = 10 kPa, nu = 0.45), base clamped, gravity sideways; element loops on 1 or 2
// threads (the fifth argument).
// A second setup (the sixth argument, 1) is the Vega FEM comparison of issue 22: cubes of
// 12^3 and 24^3 cells (10,368 and 82,944 tets), E = 5 kPa, nu = 0.45, rho = 1000, consistent
// mass, Rayleigh (0, 0.01), CG to 1e-6.
// Counters: median and p99 step time [ms], median per tet [ns], mean CG iterations.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <set>
#include <utility>
#include <vector>

#include "core/parallel.hpp"
#include "mesh/generators.hpp"
#include "physics/body.hpp"
#include "physics/fem/tet_fem.hpp"

namespace {

using namespace tactus;
using namespace tactus::physics;

constexpr std::array<std::array<int, 3>, 10> kCells{{{3, 3, 3},     // 162 tets
                                                    {9, 6, 3},     // 972
                                                    {8, 8, 5},     // 1920
                                                    {10, 9, 5},    // 2700
                                                    {13, 12, 6},   // 5616
                                                    {11, 11, 11},  // 7986
                                                    {20, 11, 11},  // 14520
                                                    {14, 12, 10},  // 10080 tets, 2145 nodes
                                                    {12, 12, 12},  // 10368 tets (Vega's cube)
                                                    {24, 24, 24}}};  // 82944 tets (Vega's cube)

void BM_ImplicitStep(benchmark::State& state) {
  const auto law = static_cast<FemLaw>(state.range(0));
  const auto& c = kCells[static_cast<std::size_t>(state.range(1))];
  const double dt = 1e-3 * static_cast<double>(state.range(2));
  const auto solver = static_cast<LinearSolver>(state.range(3));
  const auto threads = static_cast<unsigned>(state.range(4));
  const bool vega = state.range(5) == 1;
  tactus::set_thread_limit(threads);
  const double h = 0.005;  // 5 mm cubes
  const mesh::TetMesh m = mesh::box_volume(Vec3(c[0] * h, c[1] * h, c[2] * h), c[0], c[1], c[2]);
  FemMaterial mat;
  mat.law = law;
  mat.young_modulus = vega ? 5e3 : 1e4;
  mat.poisson_ratio = 0.45;
  mat.density = vega ? 1000.0 : 1050.0;
  if (vega) mat.rayleigh_stiffness = 0.01;
  Body body;
  body.model = std::make_shared<TetFem>(m, mat, vega ? FemMass::consistent : FemMass::lumped);
  std::vector<std::int32_t> base;
  for (std::size_t i = 0; i < m.vertices.size(); ++i)
    if (m.vertices[i].z() < -0.5 * c[2] * h + 1e-9) base.push_back(static_cast<std::int32_t>(i));
  body.fix_nodes(base);
  body.gravity = Vec3(9.81, 0.0, -9.81);
  body.settings.solver = solver;
  body.settings.cg_tolerance = vega ? 1e-6 : 1e-4;
  BodyState s = make_state(body);
  for (int i = 0; i < 5; ++i) step(body, s, dt);  // warm-up: caches, CHOLMOD analysis

  std::vector<double> times;
  double iterations = 0.0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    step(body, s, dt);
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    iterations += s.last_linear_iterations;
  }
  std::sort(times.begin(), times.end());
  const double median = times[times.size() / 2];
  const double p99 = times[std::min(times.size() - 1, times.size() * 99 / 100)];
  const auto tets = static_cast<double>(m.tets.size());
  state.counters["tets"] = tets;
  state.counters["median_ms"] = 1e3 * median;
  state.counters["p99_ms"] = 1e3 * p99;
  state.counters["ns_per_tet"] = 1e9 * median / tets;
  state.counters["cg_iters"] = iterations / static_cast<double>(times.size());
  state.counters["threads"] = static_cast<double>(tactus::thread_count());
  // The assembled system's size: a 3x3 block per node and per edge (upper half), 72 bytes each.
  std::set<std::pair<std::int32_t, std::int32_t>> edges;
  for (const auto& t : m.tets)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) edges.emplace(std::min(t[a], t[b]), std::max(t[a], t[b]));
  state.counters["matrix_MB"] = 72.0 * static_cast<double>(edges.size() + m.vertices.size()) / 1e6;
  state.SetLabel(std::string(to_string(law)) + (solver == LinearSolver::cholesky ? " cholmod" : " cg") +
                 (vega ? " vega-setup" : ""));
  tactus::set_thread_limit(0);
}

void series(benchmark::internal::Benchmark* b) {
  const int cg = static_cast<int>(LinearSolver::conjugate_gradient), chol = static_cast<int>(LinearSolver::cholesky);
  const int corot = static_cast<int>(FemLaw::corotational);
  for (int threads : {1, 2}) {
    for (int mesh = 0; mesh < 7; ++mesh) b->Args({corot, mesh, 1, cg, threads, 0});
    // The liver-sized block at 1 ms and 10 ms.
    for (int dt : {1, 10}) b->Args({corot, 7, dt, cg, threads, 0});
    // Issue 22's comparison with Vega FEM.
    for (int mesh : {8, 9}) b->Args({corot, mesh, 1, cg, threads, 1});
  }
  for (auto law : {FemLaw::linear, FemLaw::stvk, FemLaw::neo_hookean, FemLaw::mooney_rivlin})
    for (int mesh = 0; mesh < 7; ++mesh) b->Args({static_cast<int>(law), mesh, 1, cg, 2, 0});
  // The direct solver on a few sizes.
  for (int mesh : {0, 2, 7}) b->Args({corot, mesh, 1, chol, 2, 0});
}

/// What the step is measured against: the triad a = b + s c (two streams read, one
/// written) over arrays of the given total size, as bytes moved per second. 8 MB stays in this
/// machine's L3 (32 MB), 768 MB goes to memory.
void BM_Triad(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0)) * 1000000 / 24;
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i) a[i] = b[i] + 0.5 * c[i];
    benchmark::DoNotOptimize(a.data());
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(24 * n));
}

BENCHMARK(BM_Triad)->Arg(8)->Arg(768)->Unit(benchmark::kMillisecond);

BENCHMARK(BM_ImplicitStep)->Apply(series)->Unit(benchmark::kMillisecond)->MinTime(0.5);

}  // namespace

BENCHMARK_MAIN();
