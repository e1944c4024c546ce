// `tactus inspect FILE`: a mesh's or scene's summary and the problems found in it.
#include <fmt/format.h>

#include <cstdio>
#include <string>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "mesh/io/mesh_io.hpp"
#include "mesh/quality.hpp"
#include "mesh/tet_topology.hpp"
#include "mesh/validate.hpp"
#include "scene/scene.hpp"

namespace tactus::app {
namespace {

std::string vec(const Vec3& v) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", v.x(), v.y(), v.z()); }

std::string stats(const mesh::Stats& s, const char* unit = "") {
  if (s.count == 0) return "n/a";
  return fmt::format("min {:.4g}{} mean {:.4g}{} max {:.4g}{}", s.min, unit, s.mean, unit, s.max, unit);
}

void print_bounds(const Aabb& box) {
  std::printf("  bounds: min %s max %s, size %s m\n", vec(box.min).c_str(), vec(box.max).c_str(),
              vec(box.size()).c_str());
}

/// What inspect found: errors in all and the first one, for the line on stderr.
struct Verdict {
  std::size_t errors = 0;
  std::string first;
  void add(const mesh::ValidationReport& report) {
    for (const auto& p : report.problems)
      if (p.severity == mesh::Severity::error && first.empty()) first = p.what;
    errors += report.count(mesh::Severity::error);
  }
};

/// Prints the report's problems.
void print_problems(const mesh::ValidationReport& report) {
  if (report.problems.empty()) {
    std::printf("  no problems found\n");
    return;
  }
  std::printf("  problems: %zu error(s), %zu warning(s)\n", report.count(mesh::Severity::error),
              report.count(mesh::Severity::warning));
  for (const auto& p : report.problems)
    std::printf("    %s: %s\n", p.severity == mesh::Severity::error ? "error" : "warning", p.what.c_str());
}

mesh::ValidationReport inspect_surface(const mesh::TriMesh& m, const mesh::FileNumbering& numbering) {
  std::printf("surface: %zu vertices, %zu triangles\n", m.vertices.size(), m.triangles.size());
  const auto report = mesh::validate(m, {}, &numbering);
  const bool indices_ok = report.ok();
  if (indices_ok) {
    print_bounds(m.bounds());
    std::printf("  area: %.6g m²\n", m.area());
    std::printf("  enclosed volume: %.6g m³ (meaningful when closed and outward oriented)\n",
                m.signed_volume());
    const auto q = mesh::tri_quality(m);
    std::printf("  min angle: %s\n", stats(q.min_angle_deg, "°").c_str());
    std::printf("  aspect ratio: %s\n", stats(q.aspect_ratio).c_str());
    std::printf("  edge length: %s m\n", stats(q.edge_length).c_str());
  }
  print_problems(report);
  return report;
}

mesh::ValidationReport inspect_volume(const mesh::TetMesh& m, const mesh::FileNumbering& numbering,
                                      std::size_t flipped) {
  std::printf("volume: %zu vertices, %zu tetrahedra\n", m.vertices.size(), m.tets.size());
  if (flipped > 0)
    std::printf("  all %zu tetrahedra flipped on reading: the file orders corners the mirrored way\n", flipped);
  const auto report = mesh::validate(m, &numbering);
  bool indices_ok = true;
  for (const auto& p : report.problems)
    if (p.what.find("out of range") != std::string::npos) indices_ok = false;
  if (indices_ok && !m.tets.empty()) {
    print_bounds(m.bounds());
    std::printf("  volume: %.6g m³\n", m.volume());
    const auto b = mesh::extract_boundary(m);
    std::printf("  boundary: %zu vertices, %zu triangles, area %.6g m²\n", b.surface.vertices.size(),
                b.surface.triangles.size(), b.surface.area());
    const auto q = mesh::tet_quality(m);
    std::printf("  radius ratio (1 = regular): %s\n", stats(q.radius_ratio).c_str());
    std::printf("  dihedral angles: min %.4g°, max %.4g°\n", q.min_dihedral_deg.min, q.max_dihedral_deg.max);
    std::printf("  edge length ratio: %s\n", stats(q.edge_length_ratio).c_str());
    std::printf("  inverted: %zu, slivers (radius ratio < %.2g): %zu\n", q.inverted, mesh::kSliverRadiusRatio,
                q.slivers);
  }
  print_problems(report);
  return report;
}

}  // namespace

Action add_inspect(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  app.add_option("file", *path, "Mesh (obj stl off ply msh node/ele) or scene (toml)")->required();
  app.footer(
      "Checks: indices, repeated and duplicate elements, flat or inverted elements, open, non-manifold and\n"
      "misoriented edges, self-intersections (the first pairs and their count), vertices within 1e-9 of the\n"
      "bounding-box diagonal of each other, unused vertices. Elements and vertices are numbered as the file\n"
      "numbers them (OBJ from 1, OFF from 0, Gmsh tags, TetGen's first index), with the line each was read on.\n"
      "The report goes to stdout. Exit status 1 when the file cannot be read or has errors (warnings are\n"
      "fine), with a line on stderr naming the first error.");
  return [path] {
    const std::filesystem::path p(*path);
    if (!std::filesystem::exists(p)) throw InputError(SourceLocation{*path, {}, {}, {}}, "no such file");
    if (p.extension() == ".toml") {
      const auto model = scene::load_scene(p);
      std::fputs(scene::summarize(model).c_str(), stdout);
      return 0;
    }
    const auto file = mesh::read_mesh(p);
    std::printf("%s (%s)\n", path->c_str(), mesh::format_name(file.format));
    if (!file.skipped.empty()) std::printf("left out: %s (tetrahedra and triangles are read)\n", file.skipped.c_str());
    Verdict verdict;
    if (file.volume) verdict.add(inspect_volume(*file.volume, file.volume_numbering, file.flipped_tets));
    if (file.volume && file.surface) {
      // Gmsh, VTK: triangles beside tetrahedra are labelled boundary patches on the volume's nodes.
      std::printf("labelled surface patches: %zu triangles on the volume's nodes\n",
                  file.surface->triangles.size());
    } else if (file.surface) {
      verdict.add(inspect_surface(*file.surface, file.surface_numbering));
    }
    if (verdict.errors == 0) return 0;
    std::fflush(stdout);
    std::fprintf(stderr, "tactus: %s: %zu error%s; the first: %s (the report above lists them)\n", path->c_str(),
                 verdict.errors, verdict.errors == 1 ? "" : "s", verdict.first.c_str());
    return 1;
  };
}

}  // namespace tactus::app
