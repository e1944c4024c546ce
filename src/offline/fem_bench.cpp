#include "offline/fem_bench.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>

#include "compile/bodies.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "physics/body.hpp"

namespace tactus::offline {

std::vector<FemBenchBody> bench_fem(const scene::Model& scene_model, const FemBenchOptions& o) {
  scene::Model model = scene_model;
  for (auto& m : model.materials)
    if (o.law && m.law) m.law = *o.law;
  if (o.threads > 0) set_thread_limit(o.threads);
  std::vector<FemBenchBody> results;
  for (std::size_t i = 0; i < model.bodies.size(); ++i) {
    scene::Body& b = model.bodies[i];
    if (b.kind != scene::BodyKind::fem || !b.volume) continue;
    if (o.solver) b.stepping.solver = *o.solver;
    if (o.cg_tolerance) b.stepping.cg_tolerance = *o.cg_tolerance;
    if (o.factor_reuse_steps) b.stepping.factor_reuse_steps = *o.factor_reuse_steps;
    if (b.stepping.factor_reuse_steps > 1 && !b.stepping.can_reuse_factor())
      throw InputError(SourceLocation{model.source, {}, {}, {}},
                       fmt::format("body '{}': a factorization is reused only by linearized steps solved by "
                                   "cholesky (--solver cholesky, newton_iterations 1)",
                                   b.name));
    const physics::Body body = compile::make_physics_body(model, i);
    physics::BodyState s = physics::make_state(body);
    const double dt = b.time_step;
    for (int k = 0; k < 5; ++k) physics::step(body, s, dt);  // caches, CHOLMOD's analysis

    physics::StepProfile profile;
    s.profile = &profile;
    std::vector<double> times;
    double iterations = 0.0, total = 0.0;
    for (int k = 0; k < o.steps; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      physics::step(body, s, dt);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      times.push_back(seconds);
      total += seconds;
      iterations += s.last_linear_iterations;
      if (!s.x.allFinite())
        throw std::runtime_error(fmt::format("body '{}' diverged during the benchmark", b.name));
    }
    std::sort(times.begin(), times.end());
    FemBenchBody r;
    r.body = b.name;
    const scene::Material* material = b.material ? &model.materials[*b.material] : nullptr;
    r.law = material && material->law ? std::string(physics::to_string(*material->law)) : "mass_spring";
    r.solver = b.stepping.solver == physics::LinearSolver::cholesky ? "cholesky" : "cg";
    if (b.stepping.factor_reuse_steps > 1) r.solver += fmt::format("/{}", b.stepping.factor_reuse_steps);
    r.nodes = b.volume->vertices.size();
    r.tets = b.volume->tets.size();
    r.time_step = dt;
    r.threads = thread_count();
    r.median_ms = 1e3 * times[times.size() / 2];
    r.p99_ms = 1e3 * times[std::min(times.size() - 1, times.size() * 99 / 100)];
    r.mean_ms = 1e3 * total / o.steps;
    r.ns_per_tet = 1e9 * times[times.size() / 2] / static_cast<double>(std::max<std::size_t>(r.tets, 1));
    r.mean_linear_iterations = iterations / o.steps;
    if (total > 0.0) {
      r.share_forces = profile.forces / total;
      r.share_assembly = profile.assembly / total;
      r.share_solve = profile.solve / total;
      r.share_other = std::max(0.0, 1.0 - r.share_forces - r.share_assembly - r.share_solve);
    }
    results.push_back(r);
  }
  if (results.empty())
    throw InputError(SourceLocation{model.source, {}, {}, {}}, "the scene has no FEM body (kind = \"fem\") to time");
  return results;
}

std::string format_fem_bench(const std::vector<FemBenchBody>& results) {
  std::string out =
      "body          law            solver    nodes    tets  dt ms  threads  median ms  p99 ms  mean ms  ns/tet  lin.its  "
      "forces  assembly  solve  other\n";
  for (const auto& r : results)
    out += fmt::format("{:<13} {:<14} {:<8} {:>6} {:>7} {:>6.2f} {:>8} {:>10.3f} {:>7.3f} {:>8.3f} {:>7.0f} {:>8.1f} {:>6.0f}% "
                       "{:>8.0f}% {:>5.0f}% {:>5.0f}%\n",
                       r.body, r.law, r.solver, r.nodes, r.tets, 1e3 * r.time_step, r.threads, r.median_ms, r.p99_ms,
                       r.mean_ms, r.ns_per_tet, r.mean_linear_iterations, 100 * r.share_forces, 100 * r.share_assembly,
                       100 * r.share_solve, 100 * r.share_other);
  return out;
}

}  // namespace tactus::offline
