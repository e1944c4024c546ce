// Static nonlinear solves side by side with GetFEM (python3-getfem): seed 001's experiment,
// a tool node pushed into a liver-sized organ held along its underside, on meshes of about
// 500 and 2,000 nodes, for StVK and neo-Hookean. Both codes stop each load step at the same
// out-of-balance force; the table gives their Newton iterations, the time of their solves
// (GetFEM: its Newton solves, without Python's start), the largest nodal difference relative
// to the largest displacement, and Tactus's Cholesky factorizations (the other linear solves
// reuse an earlier factor). Each code solves each case from rest several times in one process
// and the first run is not timed: its memory comes fresh from the kernel, each page faulted in
// (over 10 µs a page on some virtual machines), as it does once in a long-running program.
// Tactus's time is the median of four runs after it, GetFEM's its second run. CPU time counts
// every thread of each process: Tactus's pool splits the element loops of meshes over 8,000 tets.
//
//   build/release/bench/static_vs_getfem [--quick] [--threads N]
//     --quick: the 500-node mesh only; --threads: Tactus's element-loop threads (default: every
//     core; 1 compares CPU time with GetFEM's one thread without the pool's wake-ups)
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "core/parallel.hpp"
#include "core/realtime.hpp"
#include "physics/getfem/getfem_harness.hpp"

using namespace tactus;
using namespace tactus::physics;
using namespace tactus::physics::getfem;

int main(int argc, char** argv) {
  keep_freed_memory();  // as `tactus` does
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
      char* end = nullptr;
      const unsigned long threads = std::strtoul(argv[++i], &end, 10);
      if (*end != '\0' || threads < 1 || threads > 256) {
        std::fprintf(stderr, "static_vs_getfem: --threads takes a count from 1 to 256, not '%s'\n", argv[i]);
        return 2;
      }
      set_thread_limit(static_cast<unsigned>(threads));
    } else {
      std::fprintf(stderr, "usage: static_vs_getfem [--quick] [--threads N]\n");
      return 2;
    }
  }
  if (!getfem_available()) {
    std::fprintf(stderr, "static_vs_getfem: GetFEM is not installed for %s (apt-get install python3-getfem)\n",
                 python().c_str());
    return 1;
  }
  struct Run {
    FemLaw law;
    double push;
    int steps;
  };
  const std::vector<Run> runs = {{FemLaw::stvk, 0.01, 4}, {FemLaw::neo_hookean, 0.02, 8},
                                 {FemLaw::neo_hookean, 0.03, 12}};
  std::vector<std::size_t> sizes = {500};
  if (!quick) sizes.push_back(2000);
  const fs::path dir = fs::temp_directory_path() / ("tactus_static_vs_getfem_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::printf("| case | nodes | tets | Newton its Tactus / GetFEM | Tactus's factorizations "
              "| wall Tactus / GetFEM [ms] | CPU Tactus / GetFEM [ms] | less wall | less CPU | max rel diff |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  int failures = 0;
  for (std::size_t nodes : sizes)
    for (const Run& run : runs) {
      Case c = liver(run.law, run.push, run.steps, nodes);
      c.force_tolerance = 1e-10;
      c.getfem_runs = 2;
      std::vector<double> times, cpu;
      Solution t = solve_tactus(c);
      for (int k = 0; k < 4; ++k) {
        t = solve_tactus(c);
        times.push_back(t.seconds);
        cpu.push_back(t.cpu_seconds);
      }
      std::sort(times.begin(), times.end());
      std::sort(cpu.begin(), cpu.end());
      const GetFemSolution g = solve_getfem(c, dir);
      if (!g.error.empty() || !t.result.converged) {
        std::fprintf(stderr, "%s: %s\n", c.name.c_str(), g.error.empty() ? "Tactus did not converge" : g.error.c_str());
        ++failures;
        continue;
      }
      double max_u = 0.0, max_diff = 0.0;
      for (Eigen::Index i = 0; i < g.u.size(); i += 3) {
        max_u = std::max(max_u, g.u.segment<3>(i).norm());
        max_diff = std::max(max_diff, (t.u.segment<3>(i) - g.u.segment<3>(i)).norm());
      }
      // The median of four: the mean of the middle two.
      const double median = 0.5 * (times[1] + times[2]), median_cpu = 0.5 * (cpu[1] + cpu[2]);
      std::printf("| %s, %.0f mm in %d steps | %zu | %zu | %d / %d | %ld | %.1f / %.1f | %.1f / %.1f | %.1f× | %.1f× "
                  "| %.1e |\n",
                  to_string(run.law).data(), 1e3 * run.push, run.steps, c.mesh.vertices.size(), c.mesh.tets.size(),
                  t.newton_iterations, g.newton_iterations, t.factorizations, 1e3 * median, 1e3 * g.seconds,
                  1e3 * median_cpu, 1e3 * g.cpu_seconds, g.seconds / median, g.cpu_seconds / median_cpu,
                  max_diff / max_u);
      std::fflush(stdout);
    }
  fs::remove_all(dir);
  return failures == 0 ? 0 : 1;
}
