// `tactus solve SCENE`: the scene's bodies without devices, in lockstep, to static equilibrium
// or to a time; writes the deformed meshes (VTU) and a CSV of probes and reactions.
#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "mesh/io/mesh_io.hpp"
#include "compile/bodies.hpp"
#include "offline/solve.hpp"
#include "scene/scene.hpp"

namespace tactus::app {
namespace {

struct SolveArgs {
  std::string scene, probe_file, output, csv;
  bool static_solve = false;
  std::optional<double> until;
  double every = 0.0;
};

/// OUT for a single body, OUT's stem + "_" + body otherwise.
std::filesystem::path per_body(const std::string& path, const std::string& body, bool several) {
  std::filesystem::path p(path);
  if (!several) return p;
  return p.parent_path() / (p.stem().string() + "_" + body + p.extension().string());
}

void write_text(const std::filesystem::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
  out.flush();
  if (!out) throw InputError(SourceLocation{p.string(), {}, {}, {}}, "cannot write the file");
}

}  // namespace

Action add_solve(CLI::App& app) {
  auto a = std::make_shared<SolveArgs>();
  app.add_option("scene", a->scene, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
  auto* st = app.add_flag("--static", a->static_solve, "Solve for static equilibrium (load stepping per body)");
  app.add_option("--until", a->until, "Simulate to this time [s] (dynamic; default 1 s)")
      ->check(CLI::PositiveNumber)
      ->excludes(st);
  app.add_option("--every", a->every, "Dynamic: seconds between CSV rows (default: every step)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--probe", a->probe_file, "CSV of probe points 'name,x,y,z' (rest positions, m)")
      ->check(CLI::ExistingFile);
  app.add_option("-o,--output", a->output, "Deformed mesh (.vtu, .vtk, .msh, ...); one file per body");
  app.add_option("--csv", a->csv, "Probe displacements and reactions (CSV); default: stdout");
  app.footer("Columns of the CSV: docs/solve-output.md");
  return [a] {
    const scene::Model model = scene::load_scene(a->scene);
    offline::SolveOptions o;
    o.static_solve = a->static_solve;
    o.until = a->until.value_or(1.0);
    o.report_every = a->every;
    if (!a->probe_file.empty()) o.extra_probes = offline::read_probe_file(a->probe_file);
    const offline::SolveResult result = offline::solve(model, o);
    const bool several = result.bodies.size() > 1;
    int failures = 0;
    for (const auto& body : result.bodies) {
      const std::string csv = offline::to_csv(body, o.static_solve);
      if (a->csv.empty()) {
        if (several) std::printf("# body %s\n", body.body.c_str());
        std::fputs(csv.c_str(), stdout);
      } else {
        write_text(per_body(a->csv, body.body, several), csv);
      }
      for (const auto& row : body.rows) failures += row.converged ? 0 : 1;
      if (!body.failure.empty())
        std::fprintf(stderr, "tactus: body '%s' stopped at %s\n", body.body.c_str(), body.failure.c_str());
      else if (body.step_halvings > 0)
        std::fprintf(stderr, "body '%s': %d load step halving(s) to converge\n", body.body.c_str(), body.step_halvings);
      if (!a->output.empty()) {
        const scene::Body& sb = *model.find_body(body.body);
        const auto out = per_body(a->output, body.body, several);
        if (sb.volume) {
          mesh::TetMesh deformed = *sb.volume;
          deformed.vertices = body.final_positions;
          mesh::write_mesh(out, deformed);
        } else {
          mesh::TriMesh deformed = sb.surface;
          deformed.vertices = body.final_positions;
          mesh::write_mesh(out, deformed);
        }
        std::fprintf(stderr, "wrote %s\n", out.string().c_str());
        if (!sb.mapped.empty()) {
          // Mapped surfaces beside it: OUT.<surface name>.<extension>.
          VecX x(3 * static_cast<Eigen::Index>(body.final_positions.size()));
          for (std::size_t i = 0; i < body.final_positions.size(); ++i)
            x.segment<3>(3 * static_cast<Eigen::Index>(i)) = body.final_positions[i];
          std::vector<std::vector<Vec3>> surfaces;
          compile::mapped_surface_positions(sb, x, surfaces);
          for (std::size_t k = 0; k < sb.mapped.size(); ++k) {
            mesh::TriMesh deformed = sb.mapped[k].mesh;
            deformed.vertices = surfaces[k];
            std::filesystem::path path = out;
            path.replace_extension("." + sb.mapped[k].name + out.extension().string());
            mesh::write_mesh(path, deformed);
            std::fprintf(stderr, "wrote %s\n", path.string().c_str());
          }
        }
      }
    }
    if (failures > 0) {
      std::fprintf(stderr, "tactus: %d load step(s) did not converge (see the 'converged' column)\n", failures);
      return 1;
    }
    return 0;
  };
}

}  // namespace tactus::app
