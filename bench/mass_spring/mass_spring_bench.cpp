// Steps per second of the mass-spring models: seed 000's upper leg (2550 tets), seed 004's
// skin as a 30×30 sheet, and the upper leg restricted to a region around a contact.
#include <benchmark/benchmark.h>

#include <cmath>

#include "mesh/generators.hpp"
#include "physics/body.hpp"
#include "physics/mass_spring/region.hpp"
#include "physics/mass_spring/surface_builder.hpp"
#include "physics/mass_spring/tet_builder.hpp"
#include "physics/mass_spring/tissue_presets.hpp"

namespace tactus::physics {
namespace {

std::vector<std::int32_t> nodes_below(const VecX& x, double z) {
  std::vector<std::int32_t> out;
  for (Eigen::Index n = 0; 3 * n < x.size(); ++n)
    if (x[3 * n + 2] < z) out.push_back(static_cast<std::int32_t>(n));
  return out;
}

/// Upper leg of seed 000: 0.15 × 0.15 × 0.5 m, 5 × 5 × 17 cubes of 6 tets = 2550 tets, muscle.
/// with_arms: the standard-linear-solid arm of the preset; otherwise seed 000's Voigt model
/// (springs and nodal damping only).
Body upper_leg(bool with_arms, Integrator integrator) {
  TetSpringParams p = tet_spring_params(tissue_material("muscle"));
  if (!with_arms) p.viscoelastic.arms.clear();
  Body b;
  b.model = tet_mass_spring(mesh::box_volume(Vec3(0.15, 0.15, 0.5), 5, 5, 17), p);
  b.fix_nodes(nodes_below(b.model->rest_positions(), -0.249));
  b.settings.integrator = integrator;
  b.gravity = Vec3(0, 0, -9.81);
  return b;
}

VecX press(const Body& b, const Vec3& at, double radius, double total) {
  const VecX& x = b.model->rest_positions();
  VecX f = VecX::Zero(x.size());
  std::vector<Eigen::Index> hit;
  for (Eigen::Index n = 0; 3 * n < x.size(); ++n)
    if ((x.segment<3>(3 * n) - at).norm() < radius) hit.push_back(n);
  for (auto n : hit) f[3 * n + 2] = -total / static_cast<double>(hit.size());
  return f;
}

const Vec3 kContact(0.0, 0.0, 0.25);

void run(benchmark::State& state, const Body& b, double dt, const VecX& f) {
  BodyState s = make_state(b);
  for (int i = 0; i < 100; ++i) step(b, s, dt, f);  // warm: buffers sized, load applied
  for (auto _ : state) {
    step(b, s, dt, f);
    benchmark::DoNotOptimize(s.x.data());
  }
  if (!s.x.allFinite()) state.SkipWithError("state became non-finite: dt above the stability limit");
  state.counters["steps_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["nodes"] = static_cast<double>(b.model->node_count());
}

// Symplectic Euler at dt = 1 ms (below 2/ω_max of the instantaneous stiffness) for the
// haptic rate; implicit Euler with CG for comparison.
void BM_UpperLegVoigtSymplectic(benchmark::State& state) {
  const Body b = upper_leg(false, Integrator::symplectic_euler);
  run(state, b, 1e-3, press(b, kContact, 0.04, 5.0));
}
void BM_UpperLegSlsSymplectic(benchmark::State& state) {
  const Body b = upper_leg(true, Integrator::symplectic_euler);
  run(state, b, 1e-3, press(b, kContact, 0.04, 5.0));
}
void BM_UpperLegSlsImplicitCg(benchmark::State& state) {
  Body b = upper_leg(true, Integrator::implicit_euler);
  run(state, b, 1e-3, press(b, kContact, 0.04, 5.0));
}
/// Far nodes fixed (seed 000's "reduce the order"): radius in mm from the argument.
void BM_UpperLegSlsSymplecticRegion(benchmark::State& state) {
  const Body full = upper_leg(true, Integrator::symplectic_euler);
  const auto& net = static_cast<const SpringNetwork&>(*full.model);
  const Body r = restrict_to_region(full, net, net.rest_positions(), kContact, state.range(0) * 1e-3);
  state.counters["free_nodes"] = static_cast<double>(net.node_count() - r.fixed_node_count());
  run(state, r, 1e-3, press(r, kContact, 0.04, 5.0));
}
void BM_UpperLegSlsImplicitCgRegion(benchmark::State& state) {
  const Body full = upper_leg(true, Integrator::implicit_euler);
  const auto& net = static_cast<const SpringNetwork&>(*full.model);
  const Body r = restrict_to_region(full, net, net.rest_positions(), kContact, state.range(0) * 1e-3);
  state.counters["free_nodes"] = static_cast<double>(net.node_count() - r.fixed_node_count());
  run(state, r, 1e-3, press(r, kContact, 0.04, 5.0));
}
/// Cost of moving the region with the contact (rebuild + rebind), to amortize over steps.
void BM_UpperLegRegionRebuild(benchmark::State& state) {
  const Body full = upper_leg(true, Integrator::symplectic_euler);
  const auto& net = static_cast<const SpringNetwork&>(*full.model);
  BodyState s = make_state(full);
  double x = -0.05;
  for (auto _ : state) {
    x = x > 0.05 ? -0.05 : x + 0.001;
    const Body r = restrict_to_region(full, net, s.x, Vec3(x, 0.0, 0.25), 0.06);
    rebind_state(r, s);
    benchmark::DoNotOptimize(r.model.get());
  }
}

/// Seed 004's skin: 30 × 30 quads of 5 mm, longitudinal springs and damping, border pinned.
Body sheet(Integrator integrator) {
  Body b;
  b.model = surface_mass_spring(mesh::grid_plate_quads(0.15, 0.15, 30, 30), skin_seed004(50.0, 0.5, 1e-3));
  const VecX& x = b.model->rest_positions();
  std::vector<std::int32_t> border;
  for (Eigen::Index n = 0; 3 * n < x.size(); ++n)
    if (std::abs(x[3 * n]) > 0.0749 || std::abs(x[3 * n + 1]) > 0.0749) border.push_back(static_cast<std::int32_t>(n));
  b.fix_nodes(border);
  b.settings.integrator = integrator;
  b.gravity = Vec3(0, 0, -9.81);
  return b;
}
void BM_Sheet30ExplicitEuler(benchmark::State& state) {
  const Body b = sheet(Integrator::explicit_euler);  // seed 004 eq. 5
  run(state, b, 1e-4, press(b, Vec3::Zero(), 0.01, 0.05));
}
void BM_Sheet30Symplectic(benchmark::State& state) {
  const Body b = sheet(Integrator::symplectic_euler);
  run(state, b, 1e-3, press(b, Vec3::Zero(), 0.01, 0.05));
}

BENCHMARK(BM_UpperLegVoigtSymplectic);
BENCHMARK(BM_UpperLegSlsSymplectic);
BENCHMARK(BM_UpperLegSlsImplicitCg);
BENCHMARK(BM_UpperLegSlsSymplecticRegion)->Arg(60)->Arg(100);
BENCHMARK(BM_UpperLegSlsImplicitCgRegion)->Arg(60);
BENCHMARK(BM_UpperLegRegionRebuild);
BENCHMARK(BM_Sheet30ExplicitEuler);
BENCHMARK(BM_Sheet30Symplectic);

}  // namespace
}  // namespace tactus::physics

BENCHMARK_MAIN();
