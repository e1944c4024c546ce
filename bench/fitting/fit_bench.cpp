// `tactus fit`'s cost: a 20-point loading curve (synthetic, the forward model's own at known
// parameters with 2 % noise) fitted on a ~5k-tet specimen (14 × 14 × 4 cells: 4,704 tets),
// E free and ν fixed, from the analytic initial guess. Results in docs/BENCHMARKS.md.
#include <benchmark/benchmark.h>

#include <random>

#include "fitting/fit.hpp"

namespace tactus::fitting {
namespace {

Experiment specimen(IndenterShape shape, double radius, physics::FemLaw law) {
  Experiment e;
  e.file = "bench";
  e.indenter = {shape, radius};
  e.specimen.size = Vec2(0.04, 0.04);
  e.specimen.thickness = 0.02;
  e.specimen.cells = {14, 14, 4};
  e.law = law;
  e.parameters = {{"young_modulus", std::nullopt, true}, {"poisson_ratio", 0.45, false}};
  for (int i = 1; i <= 20; ++i) e.x.push_back(2e-3 * i / 20);
  return e;
}

void fit_curve(benchmark::State& state, IndenterShape shape, double radius, physics::FemLaw law) {
  Experiment e = specimen(shape, radius, law);
  const IndentationModel model(e);
  const auto clean = model.curve(make_material(e, {5e3, 0.45}));
  std::mt19937 rng(28);
  std::normal_distribution<double> noise(0.0, 0.02 * clean.back());
  for (double y : clean) e.y.push_back(y + noise(rng));
  FitResult r;
  for (auto _ : state) {
    r = fit(e, model);
    benchmark::DoNotOptimize(r.values.data());
  }
  state.counters["tets"] = static_cast<double>(model.mesh().tets.size());
  state.counters["forward_runs"] = r.evaluations;
  state.counters["E"] = r.values[0];
}

void BM_FitLinearFlatPunch(benchmark::State& s) { fit_curve(s, IndenterShape::flat_punch, 0.006, physics::FemLaw::linear); }
void BM_FitCorotationalFlatPunch(benchmark::State& s) {
  fit_curve(s, IndenterShape::flat_punch, 0.006, physics::FemLaw::corotational);
}
void BM_FitLinearSphere(benchmark::State& s) { fit_curve(s, IndenterShape::sphere, 0.008, physics::FemLaw::linear); }
void BM_FitCorotationalSphere(benchmark::State& s) {
  fit_curve(s, IndenterShape::sphere, 0.008, physics::FemLaw::corotational);
}

BENCHMARK(BM_FitLinearFlatPunch)->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3);
BENCHMARK(BM_FitCorotationalFlatPunch)->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3);
BENCHMARK(BM_FitLinearSphere)->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3);
BENCHMARK(BM_FitCorotationalSphere)->Unit(benchmark::kSecond)->Iterations(1)->Repetitions(3);

}  // namespace
}  // namespace tactus::fitting

BENCHMARK_MAIN();
