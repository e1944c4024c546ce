// `tactus mesh`: convert between formats, generate shapes, tetrahedralize closed surfaces,
// mesh label images.
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <optional>

#include <fmt/format.h>
#include <string>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "imaging/label_image.hpp"
#include "imaging/label_mesher.hpp"
#include "mesh/generators.hpp"
#include "mesh/io/mesh_io.hpp"
#include "mesh/tet_topology.hpp"
#include "mesh/tetrahedralize.hpp"
#include "mesh/validate.hpp"

namespace tactus::app {
namespace {

struct MeshOptions {
  std::string input, output, generate;
  double size = 0.1;
  int resolution = 0;
  std::optional<double> max_volume;
  std::optional<double> quality;
  std::optional<double> min_dihedral;
  std::optional<std::size_t> nodes;
  bool binary = false;
  int msh_version = 41;
  bool boundary = false;
  double timeout = 300.0;
  double max_memory_gib = 0.0;
  // --labels
  std::string labels;
  std::optional<double> cell_size;
  std::vector<std::string> cell_size_label;
  std::vector<std::string> facet_distance_label;
  std::optional<double> facet_distance;
  double smooth = 0.0;
  std::vector<double> spacing;
  std::size_t min_voxels = 8;
  double sliver_bound = 5.0;
};

/// "L=SIZE" of --cell-size-label and --facet-distance-label.
std::pair<std::int32_t, double> label_size(const std::string& option, const std::string& text) {
  const auto eq = text.find('=');
  const std::string bad = option + " '" + text + "': expected LABEL=SIZE, e.g. 3=0.002";
  if (eq == std::string::npos) throw InputError(bad);
  try {
    std::size_t used = 0;
    const long label = std::stol(text.substr(0, eq), &used);
    if (used != eq || label == 0 || label < INT32_MIN || label > INT32_MAX) throw InputError(bad);
    const std::string size_text = text.substr(eq + 1);
    const double size = std::stod(size_text, &used);
    if (used != size_text.size() || !(size > 0.0)) throw InputError(bad);
    return {static_cast<std::int32_t>(label), size};
  } catch (const std::logic_error&) {
    throw InputError(bad);
  }
}

int mesh_labels(const MeshOptions& o) {
  if (!o.cell_size) throw InputError("--labels needs --cell-size (metres)");
  std::optional<Vec3> spacing;
  if (!o.spacing.empty()) {
    if (o.spacing.size() != 3) throw InputError("--spacing: expected SX,SY,SZ (metres)");
    spacing = Vec3(o.spacing[0], o.spacing[1], o.spacing[2]);
  }
  const auto format = mesh::format_from_path(o.output);
  if (format != mesh::MeshFormat::vtu && format != mesh::MeshFormat::vtk && format != mesh::MeshFormat::msh &&
      format != mesh::MeshFormat::tetgen)
    throw InputError(SourceLocation{o.output, {}, {}, {}}, "a labelled mesh is written as .vtu, .vtk, .msh or TetGen");
  const imaging::LabelImage image = imaging::read_label_image(o.labels, spacing);
  imaging::LabelMeshOptions mo;
  mo.cell_size = *o.cell_size;
  for (const auto& text : o.cell_size_label) {
    const auto entry = label_size("--cell-size-label", text);
    mo.cell_size_by_label[entry.first] = entry.second;
  }
  for (const auto& text : o.facet_distance_label) {
    const auto entry = label_size("--facet-distance-label", text);
    mo.facet_distance_by_label[entry.first] = entry.second;
  }
  mo.facet_distance = o.facet_distance;
  mo.smooth_sigma = o.smooth;
  mo.min_voxels = o.min_voxels;
  mo.sliver_bound_deg = o.sliver_bound;
  mo.progress = true;  // Progress itself stays quiet under CI
  const auto start = std::chrono::steady_clock::now();
  const mesh::TetMesh tets = imaging::mesh_label_image(image, mo);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  mesh::write_mesh(o.output, tets, mesh::WriteOptions{o.binary, o.msh_version});
  std::printf("%s: %zu nodes, %zu tetrahedra, %.1f s\n", o.output.c_str(), tets.vertices.size(), tets.tets.size(),
              seconds);
  std::map<int, std::pair<std::size_t, double>> by_label;
  for (std::size_t t = 0; t < tets.tets.size(); ++t) {
    auto& entry = by_label[tets.tet_regions[t]];
    ++entry.first;
    entry.second += tets.tet_volume(t);
  }
  const auto counts = imaging::count_labels(image);
  std::printf("%8s %10s %12s %14s %14s\n", "label", "voxels", "tetrahedra", "volume [m³]", "voxels [m³]");
  std::string lost;
  for (const auto& c : counts) {
    const auto& entry = by_label[c.label];
    const double voxels = static_cast<double>(c.voxels) * image.voxel_volume();
    std::printf("%8d %10zu %12zu %14.6g %14.6g\n", c.label, c.voxels, entry.first, entry.second, voxels);
    // A label thinner than the cells (a sheet one voxel thick) can be meshed to a sliver of itself.
    if (std::abs(entry.second / voxels - 1.0) > 0.25)
      lost.append(fmt::format("{}{} ({:.0f}%)", lost.empty() ? "" : ", ", c.label, 100.0 * entry.second / voxels));
  }
  if (!lost.empty())
    std::fprintf(stderr, "tactus: %s: warning: meshed volume far from the voxels' for label %s; give the label a "
                 "smaller --cell-size-label, or less --smooth\n", o.labels.c_str(), lost.c_str());
  return 0;
}

mesh::TetGenBudget budget(const MeshOptions& o) {
  mesh::TetGenBudget b;
  b.seconds = o.timeout;
  b.memory_bytes = static_cast<std::size_t>(o.max_memory_gib * 1024.0 * 1024.0 * 1024.0);
  return b;
}

mesh::TriMesh generate(const MeshOptions& o) {
  const double s = o.size;
  if (!(s > 0.0)) throw InputError("--size must be positive");
  const int r = o.resolution;
  if (o.generate == "organ") return mesh::organ(s, r > 0 ? r : 24);
  if (o.generate == "sphere") return mesh::sphere(s, r > 0 ? r : 3);
  if (o.generate == "box") return mesh::box_surface(Vec3::Constant(s), r > 0 ? r : 4);
  if (o.generate == "cylinder") return mesh::cylinder(s, 4.0 * s, r > 0 ? r : 24, r > 0 ? r : 8);
  if (o.generate == "plate") return mesh::grid_plate(s, s, r > 0 ? r : 20, r > 0 ? r : 20);
  throw InputError("--generate: unknown shape '" + o.generate +
                   "' (organ, sphere, box, cylinder, plate)");
}

bool wants_tets(const MeshOptions& o) { return o.max_volume || o.quality || o.min_dihedral || o.nodes; }

/// Says on stderr what happened to tetrahedra that were inside out in the file: flipped as
/// a whole (a file in the mirrored convention), or, in a file with a mix, written as they
/// are for the user to look at.
void report_orientation(const std::string& source, const mesh::MeshFile& in) {
  const mesh::TetMesh& m = *in.volume;
  if (in.flipped_tets > 0) {
    std::fprintf(stderr, "tactus: %s: flipped all %zu tetrahedra (the file orders their corners the mirrored way)\n",
                 source.c_str(), in.flipped_tets);
    return;
  }
  std::size_t inverted = 0;
  std::string listed;
  constexpr std::size_t kListed = 10;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    if (m.tet_volume(t) >= 0.0) continue;
    if (inverted++ < kListed) {
      const auto& numbers = in.volume_numbering.element_number;
      listed.append(fmt::format("{}{}", listed.empty() ? "" : ", ",
                                t < numbers.size() ? numbers[t] : static_cast<std::int64_t>(t)));
    }
  }
  if (inverted == 0) return;
  std::fprintf(stderr, "tactus: %s: warning: %zu inverted tetrahedra written as they are: %s%s (%s); "
               "'tactus inspect' lists them\n",
               source.c_str(), inverted, listed.c_str(), inverted > kListed ? ", ..." : "",
               in.volume_numbering.element_number.empty() ? "counted from 0" : "file numbering");
}

}  // namespace

Action add_mesh(CLI::App& app) {
  auto o = std::make_shared<MeshOptions>();
  app.add_option("input", o->input, "Input mesh (omit with --generate)");
  app.add_option("-o,--output", o->output, "Output mesh; the format follows the extension")->required();
  app.add_option("--generate", o->generate, "Generate a shape: organ, sphere, box, cylinder, plate");
  app.add_option("--size", o->size,
                 "Generated size [m]: organ length, sphere/cylinder radius, box/plate edge")
      ->check(CLI::PositiveNumber);
  app.add_option("--resolution", o->resolution,
                 "Generated resolution: organ cells along its length (default 24; 7 gives ~500 "
                 "nodes, 12 ~2000 with --nodes), sphere subdivisions, cells per edge")
      ->check(CLI::Range(1, 400));
  app.add_option("--max-volume", o->max_volume, "Tetrahedralize: largest tetrahedron volume [m³]")
      ->check(CLI::PositiveNumber);
  app.add_option("--quality", o->quality, "Tetrahedralize: radius-edge ratio bound (TetGen q, >= 1.1)")
      ->check(CLI::Range(1.1, 10.0));
  app.add_option("--min-dihedral", o->min_dihedral, "Tetrahedralize: minimum dihedral angle [°]")
      ->check(CLI::Range(0.0, 30.0));
  app.add_option("--nodes", o->nodes, "Tetrahedralize to about this many nodes (within 10%)")
      ->check(CLI::Range(std::size_t{4}, std::size_t{10'000'000}));
  app.add_option("--timeout", o->timeout,
                 "Tetrahedralize: give up after this many seconds (default 300; 0 = no limit). TetGen runs in a "
                 "child process that is stopped then")
      ->check(CLI::Range(0.0, 1e6));
  app.add_option("--max-memory", o->max_memory_gib, "Tetrahedralize: cap TetGen's memory [GiB] (default: no cap)")
      ->check(CLI::Range(0.0, 1e6));
  app.add_flag("--binary", o->binary, "STL and PLY: write binary (little endian)");
  app.add_option("--msh-version", o->msh_version, "Gmsh output version: 22 or 41")->check(CLI::IsMember({22, 41}));
  app.add_flag("--boundary", o->boundary, "Write the boundary surface of a volume mesh");
  app.add_option("--labels", o->labels,
                 "Mesh a label image: .nii, .nii.gz, .nrrd, or a directory/glob of PNG slices; every nonzero "
                 "label becomes a region (tet_regions) of one tetrahedral mesh");
  app.add_option("--cell-size", o->cell_size, "--labels: largest tetrahedron circumradius [m]")
      ->check(CLI::PositiveNumber);
  app.add_option("--cell-size-label", o->cell_size_label, "--labels: LABEL=SIZE, that label's cell size [m]; repeat");
  app.add_option("--facet-distance-label", o->facet_distance_label,
                 "--labels: LABEL=DISTANCE, that label's facet distance [m]; repeat");
  app.add_option("--facet-distance", o->facet_distance,
                 "--labels: largest distance from a boundary facet to the label boundary [m] (default: half the "
                 "smallest voxel spacing)")
      ->check(CLI::PositiveNumber);
  app.add_option("--smooth", o->smooth,
                 "--labels: Gaussian smoothing of the label boundaries, sigma in units of the smallest voxel "
                 "spacing (0: none; 0.75 to 1 removes the voxel staircase)")
      ->check(CLI::Range(0.0, 20.0));
  app.add_option("--spacing", o->spacing, "--labels with PNG slices: voxel spacing SX,SY,SZ [m]")->delimiter(',');
  app.add_option("--min-voxels", o->min_voxels, "--labels: refuse a label with fewer voxels (default 8)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1'000'000'000}));
  app.add_option("--sliver-bound", o->sliver_bound,
                 "--labels: smallest dihedral angle [°] the optimizers aim for (default 5; 8 takes ten times longer)")
      ->check(CLI::Range(0.0, 15.0));
  app.footer(
      "Without tetrahedralization options the input is converted (a volume stays a volume).\n"
      "Tetrahedralization stops at --timeout (and --max-memory) with an error naming the option.\n"
      "Errors and warnings go to stderr; exit status 1 for a refused input.\n"
      "Examples:\n"
      "  tactus mesh --generate organ --size 0.22 -o organ.stl\n"
      "  tactus mesh organ.stl -o organ.msh --max-volume 2e-7 --quality 1.4\n"
      "  tactus mesh organ.msh -o organ.vtu\n"
      "  tactus mesh --labels segmentation.nii.gz -o tissue.vtu --cell-size 0.002 --smooth 1\n"
      "  tactus mesh --labels 'slices/*.png' --spacing 5e-4,5e-4,1e-3 -o tissue.msh --cell-size 0.003");

  return [o] {
    if (!o->labels.empty()) {
      if (!o->input.empty() || !o->generate.empty())
        throw InputError("give either --labels IMAGE, an input mesh or --generate SHAPE");
      return mesh_labels(*o);
    }
    if (o->input.empty() && o->generate.empty()) throw InputError("give an input mesh or --generate SHAPE");
    if (!o->input.empty() && !o->generate.empty())
      throw InputError("give either an input mesh or --generate SHAPE, not both");
    if (o->nodes && o->max_volume) throw InputError("--nodes and --max-volume exclude each other");
    (void)mesh::format_from_path(o->output);  // an unknown output extension is refused before any work
    mesh::MeshFile in;
    if (!o->generate.empty()) {
      in.surface = generate(*o);
    } else {
      in = mesh::read_mesh(o->input);
    }
    const mesh::WriteOptions wo{o->binary, o->msh_version};
    const std::string source = o->generate.empty() ? o->input : "--generate " + o->generate;

    if (wants_tets(*o)) {
      if (!in.surface || in.volume)
        throw InputError(SourceLocation{source, {}, {}, {}}, "tetrahedralization needs a surface mesh");
      const auto report = mesh::validate(*in.surface, mesh::SurfaceChecks{true}, &in.surface_numbering);
      const std::size_t errors = report.count(mesh::Severity::error);
      for (const auto& p : report.problems)
        if (p.severity == mesh::Severity::error)
          throw InputError(SourceLocation{source, {}, {}, {}},
                           "cannot tetrahedralize: " + p.what +
                               (errors > 1 ? fmt::format(" ({} errors; 'tactus inspect' lists them)", errors) : ""));
      mesh::TetMesh tets;
      if (o->nodes) {
        tets = mesh::tetrahedralize_to_node_count(*in.surface, *o->nodes, o->quality.value_or(1.414), 0.1, true,
                                                  budget(*o));
      } else {
        mesh::TetrahedralizeOptions to;
        to.max_volume = o->max_volume;
        if (o->quality) to.radius_edge_ratio = *o->quality;
        if (o->min_dihedral) to.min_dihedral_deg = *o->min_dihedral;
        to.budget = budget(*o);
        tets = mesh::tetrahedralize(*in.surface, to);
      }
      mesh::write_mesh(o->output, tets, wo);
      std::printf("%s: %zu nodes, %zu tetrahedra, volume %.6g m³\n", o->output.c_str(), tets.vertices.size(),
                  tets.tets.size(), tets.volume());
      return 0;
    }

    if (in.volume && o->boundary) {
      const auto b = mesh::extract_boundary(*in.volume);
      mesh::write_mesh(o->output, b.surface, wo);
      std::printf("%s: boundary, %zu vertices, %zu triangles\n", o->output.c_str(), b.surface.vertices.size(),
                  b.surface.triangles.size());
    } else if (in.volume) {
      mesh::write_mesh(o->output, *in.volume, wo);
      report_orientation(source, in);
      std::printf("%s: %zu nodes, %zu tetrahedra\n", o->output.c_str(), in.volume->vertices.size(),
                  in.volume->tets.size());
    } else {
      mesh::write_mesh(o->output, *in.surface, wo);
      std::printf("%s: %zu vertices, %zu triangles\n", o->output.c_str(), in.surface->vertices.size(),
                  in.surface->triangles.size());
    }
    return 0;
  };
}

}  // namespace tactus::app
