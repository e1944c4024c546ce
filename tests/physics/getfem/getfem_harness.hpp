#pragma once
// The cases and both solvers of the GetFEM comparison (tests/physics/getfem and
// bench/fem/static_vs_getfem): the same P1 mesh, energy density, loads and fixed dofs go to
// getfem_reference.py (GetFEM, an independent FEM library) and to Tactus's static solve.
// TACTUS_SOURCE_DIR must name the source tree (the script's folder is found from it).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "core/clock.hpp"
#include "mesh/generators.hpp"
#include "mesh/tetrahedralize.hpp"
#include "physics/body.hpp"
#include "physics/fem/nodal_pressure.hpp"
#include "physics/fem/tet_fem.hpp"

namespace tactus::physics::getfem {

namespace fs = std::filesystem;

/// Debian's interpreter, the one python3-getfem installs into; TACTUS_GETFEM_PYTHON overrides.
inline std::string python() {
  const char* p = std::getenv("TACTUS_GETFEM_PYTHON");
  return p && *p ? p : "/usr/bin/python3";
}

inline bool getfem_available() {
  static const bool available =
      std::system((python() + " -c 'import getfem' > /dev/null 2>&1").c_str()) == 0;
  return available;
}

/// One component of one node: a prescribed displacement or a nodal force.
struct DofValue {
  std::int32_t node = 0;
  int component = 0;
  double value = 0.0;
};

struct Case {
  std::string name;
  mesh::TetMesh mesh;
  FemMaterial material;
  std::vector<DofValue> fixed, forces;
  int steps = 4;  ///< load steps, the same in both codes
  /// > 0: both codes stop each load step at this out-of-balance force [N] (GetFEM's max_res,
  /// Tactus's force_tolerance), for timing them alike. 0: GetFEM at 1e-12 of its residual at
  /// rest, Tactus at 1e-10 of the loads and reactions.
  double force_tolerance = 0.0;
  /// GetFEM solves the case this many times from rest in one process; its times are the last
  /// run's (> 1: with its matrices and the allocator's memory in hand, as a long-running program).
  int getfem_runs = 1;
};

inline constexpr double kBlock = 0.02, kLength = 0.1, kSide = 0.01;

inline std::vector<std::int32_t> nodes_at(const mesh::TetMesh& m, int axis, double value) {
  std::vector<std::int32_t> out;
  for (std::size_t i = 0; i < m.vertices.size(); ++i)
    if (std::abs(m.vertices[i][axis] - value) < 1e-9) out.push_back(static_cast<std::int32_t>(i));
  return out;
}

inline FemMaterial material_for(FemLaw law) {
  FemMaterial m;
  m.law = law;
  m.young_modulus = 1e6;
  m.poisson_ratio = law == FemLaw::stvk ? 0.3 : 0.4;
  // The default, projected tangent (what scenes get): it changes Newton's path, not the
  // equilibrium, and the energy line search keeps it descending on the slender beam.
  m.project_tangent = true;
  if (law == FemLaw::mooney_rivlin) {
    m.c10 = 1.2e5;
    m.c01 = 0.5e5;
    m.bulk_modulus = 1.5e6;
  }
  return m;
}

/// Cube [0, L]^3 clamped at x = 0; the x = L face is moved by (15%, 5%, -3%) of L:
/// stretch with shear.
inline Case block(FemLaw law) {
  Case c{"block_" + std::string(to_string(law)), mesh::box_volume(Vec3(kBlock, kBlock, kBlock), 3, 3, 3),
         material_for(law), {}, {}};
  for (auto& v : c.mesh.vertices) v += Vec3::Constant(kBlock / 2);
  const Vec3 d = kBlock * Vec3(0.15, 0.05, -0.03);
  for (auto n : nodes_at(c.mesh, 0, 0.0))
    for (int k = 0; k < 3; ++k) c.fixed.push_back({n, k, 0.0});
  for (auto n : nodes_at(c.mesh, 0, kBlock))
    for (int k = 0; k < 3; ++k) c.fixed.push_back({n, k, d[k]});
  return c;
}

/// Cube [0, L]^3 clamped at x = 0 (3 elements across), the x = L face pushed in by
/// `fraction` of L in `steps` load steps, sliding free in y and z.
inline Case squeezed_block(FemLaw law, double fraction, int steps) {
  Case c{"squeezed_" + std::string(to_string(law)) + "_" + std::to_string(steps),
         mesh::box_volume(Vec3(kBlock, kBlock, kBlock), 3, 3, 3), material_for(law), {}, {}, steps};
  for (auto& v : c.mesh.vertices) v += Vec3::Constant(kBlock / 2);
  for (auto n : nodes_at(c.mesh, 0, 0.0))
    for (int k = 0; k < 3; ++k) c.fixed.push_back({n, k, 0.0});
  for (auto n : nodes_at(c.mesh, 0, kBlock)) c.fixed.push_back({n, 0, -fraction * kBlock});
  return c;
}

/// Cantilever along x, clamped at x = 0, a traction on the x = L face in -z and +y given as
/// nodal forces (bilinear tributary areas); tip deflection near 15% of the length.
inline Case beam(FemLaw law) {
  Case c{"beam_" + std::string(to_string(law)), mesh::box_volume(Vec3(kLength, kSide, kSide), 10, 2, 2),
         material_for(law), {}, {}};
  for (auto& v : c.mesh.vertices) v.x() += kLength / 2;
  for (auto n : nodes_at(c.mesh, 0, 0.0))
    for (int k = 0; k < 3; ++k) c.fixed.push_back({n, k, 0.0});
  const Vec3 load(0.0, 0.04, -0.12);  // total force [N]
  const auto tip = nodes_at(c.mesh, 0, kLength);
  auto weight = [](double t) { return std::abs(std::abs(t) - kSide / 2) < 1e-9 ? 0.5 : 1.0; };
  double total = 0.0;
  for (auto n : tip) total += weight(c.mesh.vertices[n].y()) * weight(c.mesh.vertices[n].z());
  for (auto n : tip) {
    const double w = weight(c.mesh.vertices[n].y()) * weight(c.mesh.vertices[n].z()) / total;
    for (int k = 1; k < 3; ++k) c.forces.push_back({n, k, w * load[k]});
  }
  return c;
}

/// Seed 001's experiment: a liver-sized organ held along its underside, one node on its top
/// pushed `push` metres straight down in `steps` load steps (E 6 kPa, ν 0.47, no weight).
/// Each step moves the tool node several times the size of its tets' height change that
/// keeps them right side out, so a start with only the tool node moved inverts them.
inline Case liver(FemLaw law, double push, int steps, std::size_t nodes = 500) {
  static std::map<std::size_t, mesh::TetMesh> organs;
  if (!organs.count(nodes))
    organs[nodes] = mesh::tetrahedralize_to_node_count_detailed(mesh::organ(0.22, 8), nodes).mesh;
  Case c{"liver" + std::to_string(organs[nodes].vertices.size()) + "_" + std::string(to_string(law)) + "_" +
             std::to_string(steps),
         organs[nodes], material_for(law), {}, {}, steps};
  c.material.young_modulus = 6e3;
  c.material.poisson_ratio = 0.47;
  double z_min = 1e300, z_max = -1e300;
  for (const auto& v : c.mesh.vertices) {
    z_min = std::min(z_min, v.z());
    z_max = std::max(z_max, v.z());
  }
  // The tool node: on the top, in the fewest tets (the one a jumped start turns inside out
  // first), the nearest the top centre among those.
  std::vector<int> tets_at(c.mesh.vertices.size(), 0);
  for (const auto& t : c.mesh.tets)
    for (auto n : t) ++tets_at[static_cast<std::size_t>(n)];
  std::int32_t tool = -1;
  for (std::size_t i = 0; i < c.mesh.vertices.size(); ++i) {
    const Vec3& v = c.mesh.vertices[i];
    if (v.z() < z_min + 0.01)
      for (int k = 0; k < 3; ++k) c.fixed.push_back({static_cast<std::int32_t>(i), k, 0.0});
    if (v.z() < z_max - 0.015) continue;
    const auto better = [&](std::size_t a, std::size_t b) {
      if (tets_at[a] != tets_at[b]) return tets_at[a] < tets_at[b];
      return c.mesh.vertices[a].head<2>().norm() < c.mesh.vertices[b].head<2>().norm();
    };
    if (tool < 0 || better(i, static_cast<std::size_t>(tool))) tool = static_cast<std::int32_t>(i);
  }
  for (int k = 0; k < 3; ++k) c.fixed.push_back({tool, k, k == 2 ? -push : 0.0});
  return c;
}

struct Solution {
  VecX u;  ///< nodal displacements (3N)
  double min_J = 0.0;
  StaticResult result;  ///< of the last load step solved
  int newton_iterations = 0;  ///< over every load step
  long factorizations = 0;    ///< Cholesky factorizations, the predictors' included
  double seconds = 0.0;       ///< the load steps' solves, without building the model
  double cpu_seconds = 0.0;   ///< the same on every thread of the process (the pool's too)
};

inline Solution solve_tactus(const Case& c) {
  auto fem = std::make_shared<TetFem>(c.mesh, c.material);
  Body body;
  if (c.material.nodal_pressure) body.model = std::make_shared<NodalPressureFem>(fem);
  else body.model = fem;
  body.settings.solver = LinearSolver::cholesky;
  body.fixed_dofs.assign(3 * c.mesh.vertices.size(), 0);
  for (const auto& f : c.fixed) body.fixed_dofs[static_cast<std::size_t>(3 * f.node + f.component)] = 1;
  BodyState s = make_state(body);
  const VecX& rest = fem->rest_positions();
  Solution out;
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = process_cpu_seconds();
  for (int k = 1; k <= c.steps; ++k) {
    const double t = static_cast<double>(k) / c.steps;
    const VecX previous = s.x;
    for (const auto& f : c.fixed) s.x[3 * f.node + f.component] = rest[3 * f.node + f.component] + t * f.value;
    VecX f_ext = VecX::Zero(rest.size());
    for (const auto& f : c.forces) f_ext[3 * f.node + f.component] += t * f.value;
    // The free nodes follow the held ones, as GetFEM's Newton (whose constraints enter as
    // multipliers) does in its first iteration from the last solution.
    predict_static(body, s, previous, f_ext);
    // 1e-10 of the load: the beam's residual floors near 1e-11 (condition number ~1e8).
    out.result = c.force_tolerance > 0.0
                     ? solve_static(body, s, f_ext, StaticSettings{100, 0.0, c.force_tolerance})
                     : solve_static(body, s, f_ext, 100, 1e-10);
    out.newton_iterations += out.result.iterations;
    if (!out.result.converged) break;
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.cpu_seconds = process_cpu_seconds() - cpu0;
  out.factorizations = factorizations(s);
  out.u = s.x - rest;
  out.min_J = 1e300;
  for (std::size_t e = 0; e < fem->elements().size(); ++e)
    out.min_J = std::min(out.min_J, fem->deformation_gradient(s.x, e).determinant());
  return out;
}

inline std::string law_params(const Case& c) {
  const LawParams p = LawParams::from(c.material);
  char buf[128];
  if (c.material.law == FemLaw::mooney_rivlin)
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g", p.c10, p.c01, p.kappa);
  else
    std::snprintf(buf, sizeof buf, "%.17g %.17g", p.lambda, p.mu);
  return buf;
}

struct GetFemSolution {
  VecX u;  ///< nodal displacements (3N); empty when GetFEM failed (`error` says why)
  std::string error;
  int newton_iterations = 0;  ///< over every load step
  double seconds = 0.0;       ///< its Newton solves (assembly included), of the last run, without Python's start
  double cpu_seconds = 0.0;   ///< the same in CPU time of the Python process, every thread
};

/// Writes the case for getfem_reference.py, runs it and reads its displacements (3N).
inline GetFemSolution solve_getfem(const Case& c, const fs::path& dir) {
  const fs::path in = dir / (c.name + ".txt"), out = dir / (c.name + ".u"), log = dir / (c.name + ".log");
  {
    std::ofstream f(in);
    f.precision(17);
    f << "law " << to_string(c.material.law) << (c.material.nodal_pressure ? "_nodal" : "") << "\nparams " << law_params(c) << "\nsteps " << c.steps << "\n";
    if (c.force_tolerance > 0.0) f << "tolerance " << c.force_tolerance << "\n";
    if (c.getfem_runs > 1) f << "runs " << c.getfem_runs << "\n";
    f << "nodes " << c.mesh.vertices.size() << "\n";
    for (const auto& v : c.mesh.vertices) f << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
    f << "tets " << c.mesh.tets.size() << "\n";
    for (const auto& t : c.mesh.tets) f << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << t[3] << '\n';
    for (const auto* list : {&c.fixed, &c.forces}) {
      f << (list == &c.fixed ? "fixed " : "forces ") << list->size() << "\n";
      for (const auto& d : *list) f << d.node << ' ' << d.component << ' ' << d.value << '\n';
    }
  }
  // A path, not a concatenated string: GCC 12 at -O2 (the TSan build) warns of a memcpy out
  // of bounds in the inlined string concatenation (a false positive, -Werror=array-bounds).
  const std::string script = (std::filesystem::path(TACTUS_SOURCE_DIR) / "tests/physics/getfem/getfem_reference.py").string();
  const fs::path stats = dir / (c.name + ".stats");
  const std::string cmd = python() + " '" + script + "' '" + in.string() + "' '" + out.string() + "' '" +
                          stats.string() + "' > '" + log.string() + "' 2>&1";
  GetFemSolution g;
  if (std::system(cmd.c_str()) != 0) {
    std::ifstream l(log);
    g.error = "getfem_reference.py failed on " + c.name + ":\n" + std::string(std::istreambuf_iterator<char>(l), {});
    return g;
  }
  VecX u = VecX::Zero(static_cast<Eigen::Index>(3 * c.mesh.vertices.size()));
  std::ifstream f(out);
  for (Eigen::Index i = 0; i < u.size(); ++i)
    if (!(f >> u[i])) {
      g.error = "short GetFEM output for " + c.name;
      return g;
    }
  g.u = std::move(u);
  std::ifstream st(stats);
  std::string key;
  while (st >> key) {
    if (key == "newton_iterations") st >> g.newton_iterations;
    else if (key == "solve_seconds") st >> g.seconds;
    else if (key == "solve_cpu_seconds") st >> g.cpu_seconds;
  }
  return g;
}

}  // namespace tactus::physics::getfem
