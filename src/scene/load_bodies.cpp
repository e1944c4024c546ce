// bodies.<name>: kind, material, mesh (file or generator), fixed regions, time stepping.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <set>

#include <numbers>

#include <fmt/format.h>

#include "imaging/label_image.hpp"
#include "imaging/label_mesher.hpp"
#include "mesh/generators.hpp"
#include "mesh/io/mesh_io.hpp"
#include "mesh/tet_topology.hpp"
#include "mesh/tetrahedralize.hpp"
#include "physics/mapping.hpp"
#include "scene/loader.hpp"

namespace tactus::scene::detail {

namespace {

/// Whether two materials behave alike but for their elastic constants and density: the same
/// law, damping, viscoelasticity and volumetric term (what the regions of one FEM body share).
bool same_behaviour(const Material& a, const Material& b) {
  const auto& va = a.viscoelastic;
  const auto& vb = b.viscoelastic;
  bool same = a.law == b.law && a.nodal_pressure == b.nodal_pressure &&
              a.damping.rayleigh_alpha == b.damping.rayleigh_alpha &&
              a.damping.rayleigh_beta == b.damping.rayleigh_beta && va.model == vb.model && va.tau == vb.tau &&
              va.long_term_fraction == vb.long_term_fraction && va.prony.size() == vb.prony.size();
  for (std::size_t k = 0; same && k < va.prony.size(); ++k)
    same = va.prony[k].g == vb.prony[k].g && va.prony[k].tau == vb.prony[k].tau;
  return same;
}

/// bodies.<name>.regions: region tag = "material", for the volume mesh's tagged tetrahedra.
void read_region_materials(Reader& r, Body& b, const Model& model) {
  if (b.kind != BodyKind::fem)
    r.fail_here("regions give a 'fem' body's tagged tetrahedra their own materials; a '" +
                std::string(to_string(b.kind)) + "' body takes one material");
  if (!b.volume || b.volume->tet_regions.empty())
    r.fail_here("the mesh " + b.mesh_source + " tags no regions (Gmsh physical tags, VTK cell data 'region', "
                "TetGen region attributes, or `tactus mesh --labels`)");
  const std::set<int> present(b.volume->tet_regions.begin(), b.volume->tet_regions.end());
  std::vector<std::string> keys;
  for (auto&& [key, node] : r.table()) keys.emplace_back(key.str());
  for (const std::string& key : keys) {
    int tag = 0;
    const auto [end, error] = std::from_chars(key.data(), key.data() + key.size(), tag);
    if (error != std::errc() || end != key.data() + key.size())
      r.fail(key, "a region is named by its integer tag in the mesh, not '" + key + "'");
    if (!present.count(tag)) {
      std::string tags;
      for (const int t : present) tags += (tags.empty() ? "" : ", ") + std::to_string(t);
      r.fail(key, fmt::format("the mesh {} has no region {} (its regions: {})", b.mesh_source, tag, tags));
    }
    const std::string name = r.required_string(key);
    const std::size_t m = resolve_name(r, key, name, model.materials, "material");
    if (!model.materials[m].law)
      r.fail(key, "material '" + name + "' has model 'mass_spring'; a 'fem' body's region needs a continuum model");
    if (!same_behaviour(model.materials[m], model.materials[*b.material]))
      r.fail(key, "material '" + name + "' differs from the body's material '" + model.materials[*b.material].name +
                      "' in its model, damping, viscoelasticity or volumetric term; the regions of one body share those "
                      "and differ in elastic constants and density");
    b.region_materials.emplace_back(tag, m);
  }
  r.finish();
}

struct LoadedMesh {
  std::optional<mesh::TriMesh> surface;
  std::optional<mesh::TetMesh> volume;
  std::optional<mesh::QuadMesh> quads;
  std::string source;
};

/// Guards against generator calls that would run for hours or exhaust memory.
void check_budget(Reader& g, std::string_view key, double cells) {
  const auto limit = static_cast<double>(g.context().options.max_generated_cells);
  if (cells > limit)
    g.fail(key, fmt::format("asks for about {} cells; the limit is {}", number_text(cells), number_text(limit)));
}

/// `cells` as one integer (the same on every axis) or an array of N integers.
template <int N>
std::array<int, N> read_cells(Reader& g, std::array<int, N> fallback) {
  const toml::node* n = g.get("cells");
  if (!n) return fallback;
  std::array<int, N> out{};
  if (n->is_integer()) {
    const int c = g.integer("cells", 1, 1, 100000);
    out.fill(c);
    return out;
  }
  const auto list = g.integer_list("cells", 1, 100000);
  if (list.size() != static_cast<std::size_t>(N))
    g.fail("cells", fmt::format("expected an integer or an array of {} integers, got {} element{}", N, list.size(),
                                list.size() == 1 ? "" : "s"));
  for (int i = 0; i < N; ++i) out[static_cast<std::size_t>(i)] = static_cast<int>(list[static_cast<std::size_t>(i)]);
  return out;
}

LoadedMesh generate(Reader& g, const std::string& generator, bool volumetric) {
  LoadedMesh out;
  if (generator == "grid_plate") {
    const Vec2 size = g.required_vec2("size");
    if (!(size.array() > 0).all()) g.fail("size", "every extent must be > 0");
    const auto cells = read_cells<2>(g, {10, 10});
    check_budget(g, "cells", double(cells[0]) * cells[1]);
    const bool quads = g.boolean("quads", false);
    const mesh::QuadMesh q = mesh::grid_plate_quads(size.x(), size.y(), cells[0], cells[1]);
    out.surface = q.triangulated();
    if (quads) out.quads = q;
    out.source = fmt::format("grid_plate(size {}x{} m, {}x{} cells{})", number_text(size.x()),
                             number_text(size.y()), cells[0], cells[1], quads ? ", quads" : "");
  } else if (generator == "box") {
    const Vec3 size = g.required_vec3("size");
    if (!(size.array() > 0).all()) g.fail("size", "every extent must be > 0");
    const auto c = read_cells<3>(g, {1, 1, 1});
    check_budget(g, "cells", double(c[0]) * c[1] * c[2]);
    if (volumetric) {
      out.volume = mesh::box_volume(size, c[0], c[1], c[2]);
    } else {
      if (c[0] != c[1] || c[1] != c[2])
        g.fail("cells", "a box surface takes the same number of cells on every edge; give one integer");
      out.surface = mesh::box_surface(size, c[0]);
    }
    out.source = fmt::format("box({}x{}x{} m, {}x{}x{} cells)", number_text(size.x()), number_text(size.y()),
                             number_text(size.z()), c[0], c[1], c[2]);
  } else if (generator == "sphere") {
    const double radius = g.required_number("radius", Range::positive());
    const int subdivisions = g.integer("subdivisions", 3, 0, 10);
    check_budget(g, "subdivisions", 20.0 * std::pow(4.0, subdivisions));
    out.surface = mesh::sphere(radius, subdivisions);
    out.source = fmt::format("sphere(radius {} m, {} subdivisions)", number_text(radius), subdivisions);
  } else if (generator == "cylinder") {
    const double radius = g.required_number("radius", Range::positive());
    const double height = g.required_number("height", Range::positive());
    const int segments = g.integer("segments", 32, 3, 100000);
    const int rings = g.integer("rings", 8, 1, 100000);
    check_budget(g, "segments", double(segments) * (rings + 2));
    out.surface = mesh::cylinder(radius, height, segments, rings);
    out.source = fmt::format("cylinder(radius {} m, height {} m, {} segments, {} rings)", number_text(radius),
                             number_text(height), segments, rings);
  } else if (generator == "organ") {
    const double length = g.number("length", 0.22, Range::positive());
    const int resolution = g.integer("resolution", 40, 4, 100000);
    // The implicit surface is sampled on a grid of about resolution³ cells.
    check_budget(g, "resolution", std::pow(double(resolution), 3.0));
    out.surface = mesh::organ(length, resolution);
    out.source = fmt::format("organ(length {} m, resolution {})", number_text(length), resolution);
  } else {
    const std::vector<std::string> names{"grid_plate", "box", "sphere", "cylinder", "organ"};
    std::string msg = "unknown generator '" + generator + "'";
    if (const auto s = suggestion(generator, names); !s.empty()) msg += "; " + s;
    g.fail("generator", msg + " (expected one of: grid_plate, box, sphere, cylinder, organ)");
  }
  return out;
}

LoadedMesh read_file_mesh(Reader& r, std::string_view key, const std::string& value) {
  const std::filesystem::path path = resolve_file(r, key, value);
  LoadedMesh out;
  try {
    mesh::MeshFile file = mesh::read_mesh(path);
    out.surface = std::move(file.surface);
    out.volume = std::move(file.volume);
  } catch (const InputError& e) {
    // The mesh reader's message already names the mesh file and line; keep it whole.
    r.fail(key, std::string("cannot load mesh: ") + e.what());
  }
  out.source = path.generic_string();
  return out;
}

/// v → translate + scale · R v, where R turns by rotate.x() degrees about x, then rotate.y()
/// about y, then rotate.z() about z.
void transform(std::vector<Vec3>& vertices, double scale, const Vec3& rotate, const Vec3& translate) {
  const double deg = std::numbers::pi / 180.0;
  const Mat3 r = (Eigen::AngleAxisd(rotate.z() * deg, Vec3::UnitZ()) * Eigen::AngleAxisd(rotate.y() * deg, Vec3::UnitY()) *
                  Eigen::AngleAxisd(rotate.x() * deg, Vec3::UnitX()))
                     .toRotationMatrix();
  for (Vec3& v : vertices) v = scale * (r * v) + translate;
}

struct TetOptions {
  std::optional<double> max_volume;
  std::optional<std::int64_t> target_nodes;
  double radius_edge_ratio = 1.414;
};

TetOptions read_tet_options(Reader& m) {
  TetOptions o;
  o.max_volume = m.number("max_tet_volume", Range::positive());
  o.target_nodes = m.integer("target_nodes", 4, 100000000);
  o.radius_edge_ratio = m.number("radius_edge_ratio", o.radius_edge_ratio, Range::closed(1.0, 10.0));
  if (o.max_volume && o.target_nodes) m.fail("target_nodes", "give max_tet_volume or target_nodes, not both");
  return o;
}

/// Fills a volumetric body's tet mesh from its closed surface, through TetGen; errors are
/// reported at r[key].
void tetrahedralize_surface(Reader& r, std::string_view key, LoadedMesh& out, const TetOptions& o) {
  const double enclosed = std::abs(out.surface->signed_volume());
  if (o.max_volume) check_budget(r, key, enclosed / *o.max_volume);
  if (o.target_nodes) check_budget(r, key, 6.0 * double(*o.target_nodes));
  try {
    if (o.target_nodes) {
      out.volume = mesh::tetrahedralize_to_node_count(*out.surface, static_cast<std::size_t>(*o.target_nodes),
                                                      o.radius_edge_ratio);
    } else {
      mesh::TetrahedralizeOptions options;
      options.max_volume = o.max_volume;
      options.radius_edge_ratio = o.radius_edge_ratio;
      out.volume = mesh::tetrahedralize(*out.surface, options);
    }
  } catch (const InputError& e) {
    r.fail(key, out.source + ": cannot tetrahedralize: " + e.what());
  }
  out.source += ", tetrahedralized";
}

/// mesh = { labels = "segmentation.nii.gz", cell_size = ... }: every nonzero label of a
/// label image meshed as its own region (imaging/label_mesher.hpp; `tactus mesh --labels`).
LoadedMesh mesh_labels(Reader& m) {
  const std::filesystem::path path = resolve_file(m, "labels", m.required_string("labels"));
  const auto png_spacing = m.vec3("spacing");
  if (png_spacing && !(png_spacing->array() > 0.0).all()) m.fail("spacing", "every spacing must be positive");
  imaging::LabelMeshOptions o;
  o.cell_size = m.required_number("cell_size", Range::positive());
  for (const auto& [key, by_label] : {std::pair{"cell_size_label", &o.cell_size_by_label},
                                      std::pair{"facet_distance_label", &o.facet_distance_by_label}})
    if (auto sizes = m.table(key)) {
      std::vector<std::string> labels;
      for (auto&& [label_key, node] : sizes->table()) labels.emplace_back(label_key.str());
      for (const std::string& text : labels) {
        int label = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), label);
        if (error != std::errc() || end != text.data() + text.size() || label == 0)
          sizes->fail(text, "a label is named by its nonzero integer value in the image, not '" + text + "'");
        (*by_label)[label] = sizes->required_number(text, Range::positive());
      }
      sizes->finish();
    }
  o.facet_distance = m.number("facet_distance", Range::positive());
  o.smooth_sigma = m.number("smooth", 0.0, Range::closed(0.0, 10.0));
  o.sliver_bound_deg = m.number("sliver_bound", o.sliver_bound_deg, Range::closed(0.0, 15.0));
  o.min_voxels = static_cast<std::size_t>(m.integer("min_voxels", 8, 1, 1000000000));
  o.progress = false;  // a scene loads in a second or two; the command prints the bar
  LoadedMesh out;
  try {
    const imaging::LabelImage image = imaging::read_label_image(path, png_spacing);
    // About one tetrahedron per tenth of a cell's cube (circumradius r): the refinement's
    // cost, checked before it starts.
    double cells = 0.0;
    for (const auto& l : imaging::count_labels(image)) {
      const auto size = o.cell_size_by_label.find(l.label);
      const double r = size == o.cell_size_by_label.end() ? o.cell_size : std::min(o.cell_size, size->second);
      cells += static_cast<double>(l.voxels) * image.voxel_volume() / (0.1 * r * r * r);
    }
    check_budget(m, "cell_size", cells);
    out.volume = imaging::mesh_label_image(image, o);
  } catch (const InputError& e) {
    if (e.where().line) throw;
    m.fail("labels", e.what());
  }
  out.source = path.generic_string() + ", meshed by label";
  return out;
}

/// Region tags: one integer or an array of them.
std::vector<int> read_tags(Reader& m, std::string_view key) {
  const toml::node* n = m.get(key);
  if (n && n->is_integer()) return {static_cast<int>(*m.integer(key, -1000000000, 1000000000))};
  std::vector<int> out;
  for (const auto t : m.integer_list(key, -1000000000, 1000000000)) out.push_back(static_cast<int>(t));
  return out;
}

/// mesh = { region = [...], facing = [...] }: where the host's tetrahedra tagged `region` meet
/// those tagged `facing` (0: outside the host; default: every other tag and the outside),
/// oriented out of `region`. The surface's vertices are the host's nodes.
LoadedMesh region_surface(Reader& m, const Body& host) {
  if (!host.volume || host.volume->tet_regions.empty())
    m.fail("region", "body '" + host.name + "''s mesh " + host.mesh_source + " tags no regions");
  const std::set<int> present(host.volume->tet_regions.begin(), host.volume->tet_regions.end());
  std::string tags;
  for (const int t : present) tags += (tags.empty() ? "" : ", ") + std::to_string(t);
  const std::vector<int> inside = read_tags(m, "region");
  if (inside.empty()) m.fail("region", "give at least one region tag");
  for (const int t : inside)
    if (!present.count(t) || t == mesh::kOutsideRegion)
      m.fail("region", fmt::format("body '{}' has no region {} (its regions: {})", host.name, t, tags));
  std::vector<int> facing = read_tags(m, "facing");
  if (!m.has("facing")) {
    facing.push_back(mesh::kOutsideRegion);
    for (const int t : present)
      if (std::find(inside.begin(), inside.end(), t) == inside.end()) facing.push_back(t);
  }
  if (facing.empty()) m.fail("facing", "give at least one region tag (0: the outside of the body)");
  for (const int t : facing) {
    if (t != mesh::kOutsideRegion && !present.count(t))
      m.fail("facing", fmt::format("body '{}' has no region {} (its regions: {}; 0 is its outside)", host.name, t, tags));
    if (std::find(inside.begin(), inside.end(), t) != inside.end())
      m.fail("facing", fmt::format("region {} is in both 'region' and 'facing'", t));
  }
  LoadedMesh out;
  out.surface = mesh::extract_region_surface(*host.volume, mesh::TetTopology(*host.volume), inside, facing).surface;
  const auto list = [](const std::vector<int>& v) {
    std::string text;
    for (const int t : v) text += (text.empty() ? "" : ", ") + std::to_string(t);
    return text;
  };
  out.source = fmt::format("body '{}', region {} facing {}", host.name, list(inside), list(facing));
  if (out.surface->triangles.empty()) m.fail("region", out.source + ": the regions do not meet");
  return out;
}

/// Reads `mesh`: a file name, or a table with one source (file, generator, labels, or the
/// region keys, which take their tetrahedra from `host`: an embedded body's, a mapped
/// surface's own body).
LoadedMesh read_mesh_key(Reader& r, bool volumetric, const Body* host = nullptr) {
  const toml::node* n = r.get("mesh");
  if (!n) r.fail_missing("mesh", "a file name or a table with 'file', 'generator', 'labels' or 'region'");
  if (n->is_string()) {
    LoadedMesh out = read_file_mesh(r, "mesh", r.required_string("mesh"));
    if (volumetric && !out.volume && out.surface) tetrahedralize_surface(r, "mesh", out, TetOptions{});
    return out;
  }
  if (!n->is_table()) r.fail("mesh", "expected a string (file name) or a table, got " + type_name(n->type()));

  Reader m = *r.table("mesh");
  const char* source = nullptr;
  for (const char* key : {"file", "generator", "labels", "region"})
    if (m.table().contains(key)) {
      if (source) m.fail(key, fmt::format("give one of 'file', 'generator', 'labels' and 'region', not both '{}' and '{}'",
                                          source, key));
      source = key;
    }
  if (!source) m.fail_here("give one of 'file', 'generator', 'labels' (a label image) and 'region' (a host's regions)");
  if (std::string_view(source) == "region" && !host)
    m.fail("region", "a region's surface is cut from the tetrahedra of a host: for 'embedded' bodies and 'mapped' "
                     "surfaces");
  if (std::string_view(source) == "labels" && !volumetric)
    m.fail("labels", "a label image gives tetrahedra: for 'fem' and 'tet_mass_spring' bodies");
  LoadedMesh out;
  const std::string_view kind = source;
  try {
    out = kind == "file"      ? read_file_mesh(m, "file", m.required_string("file"))
          : kind == "labels"  ? mesh_labels(m)
          : kind == "region"  ? region_surface(m, *host)
                              : generate(m, m.required_string("generator"), volumetric);
  } catch (const InputError& e) {
    if (e.where().line) throw;  // already located in the scene
    m.fail(kind, e.what());
  }
  const double scale = m.number("scale", 1.0, Range::positive());
  const Vec3 rotate = m.vec3("rotate", Vec3::Zero());
  const Vec3 translate = m.vec3("translate", Vec3::Zero());
  if (scale != 1.0 || !rotate.isZero() || !translate.isZero()) {
    if (kind == "region") m.fail_here("a region's surface lies on its host's nodes; it takes no scale, rotate or translate");
    if (out.surface) transform(out.surface->vertices, scale, rotate, translate);
    if (out.volume) transform(out.volume->vertices, scale, rotate, translate);
    if (out.quads) transform(out.quads->vertices, scale, rotate, translate);
  }
  if (volumetric && !out.volume && out.surface) {
    const TetOptions options = read_tet_options(m);
    tetrahedralize_surface(m, kind, out, options);
  }
  m.finish();
  return out;
}

/// Puts the loaded mesh into the body in the form its kind needs.
void attach_mesh(Reader& r, Body& b, LoadedMesh&& m) {
  b.mesh_source = m.source;
  const std::string kind = to_string(b.kind);
  if (b.volumetric()) {
    if (!m.volume || m.volume->tets.empty())
      r.fail("mesh", "a '" + kind + "' body needs a tetrahedral mesh or a closed surface, but " + m.source +
                         " holds neither");
    try {
      mesh::BoundarySurface boundary = mesh::extract_boundary(*m.volume);
      b.surface = std::move(boundary.surface);
      b.surface_to_volume = std::move(boundary.surface_to_volume);
    } catch (const InputError& e) {
      r.fail("mesh", std::string("invalid tetrahedral mesh: ") + e.what());
    }
    b.volume = std::move(m.volume);
  } else if (m.surface && !m.surface->triangles.empty()) {
    b.surface = std::move(*m.surface);
    b.quads = std::move(m.quads);
  } else if (b.kind == BodyKind::rigid && m.volume && !m.volume->tets.empty()) {
    try {
      b.surface = mesh::extract_boundary(*m.volume).surface;
    } catch (const InputError& e) {
      r.fail("mesh", std::string("invalid tetrahedral mesh: ") + e.what());
    }
  } else {
    r.fail("mesh", "a '" + kind + "' body needs a triangle surface, but " + m.source + " holds none");
  }
}

/// Nodes on edges used by one triangle only: the border of an open sheet.
std::vector<mesh::Index> border_nodes(const mesh::TriMesh& s) {
  std::map<std::pair<mesh::Index, mesh::Index>, int> edge_uses;
  for (const auto& t : s.triangles)
    for (int i = 0; i < 3; ++i) {
      const mesh::Index a = t[static_cast<std::size_t>(i)], c = t[static_cast<std::size_t>((i + 1) % 3)];
      ++edge_uses[{std::min(a, c), std::max(a, c)}];
    }
  std::vector<mesh::Index> out;
  for (const auto& [e, uses] : edge_uses)
    if (uses == 1) {
      out.push_back(e.first);
      out.push_back(e.second);
    }
  return out;
}

/// The nodes one of the selectors (nodes, box, side, marker, border, region) picks; sets `selector`
/// to a description. Used by fixed regions, loads and prescribed displacements.
std::vector<mesh::Index> select_nodes(Reader& f, const Body& b, std::string& selector) {
  const auto& vertices = b.simulation_vertices();
  const auto& t = f.table();
  const int selectors = int(t.contains("nodes")) + int(t.contains("box")) + int(t.contains("side")) +
                        int(t.contains("marker")) + int(t.contains("border")) + int(t.contains("region"));
  if (selectors != 1)
    f.fail_here(selectors == 0 ? "missing a node selector: give one of nodes, box, side, marker, border, region"
                               : "give only one node selector (nodes, box, side, marker, border or region)");
  std::vector<mesh::Index> nodes;
  if (t.contains("nodes")) {
    selector = "nodes";
    const auto list = f.integer_list("nodes", 0, std::int64_t(vertices.size()) - 1);
    if (list.empty()) f.fail("nodes", "the list is empty");
    for (const auto i : list) nodes.push_back(static_cast<mesh::Index>(i));
  } else if (auto box = f.table("box")) {
    selector = "box";
    Aabb a;
    a.min = box->required_vec3("min");
    a.max = box->required_vec3("max");
    box->finish();
    if (!(a.min.array() <= a.max.array()).all()) f.fail("box", "min must not exceed max on any axis");
    for (std::size_t i = 0; i < vertices.size(); ++i)
      if (a.contains(vertices[i])) nodes.push_back(static_cast<mesh::Index>(i));
  } else if (t.contains("side")) {
    enum Side { x_min, x_max, y_min, y_max, z_min, z_max };
    const Side side = f.choice<Side>("side",
                                     {{"x_min", x_min}, {"x_max", x_max}, {"y_min", y_min},
                                      {"y_max", y_max}, {"z_min", z_min}, {"z_max", z_max}},
                                     std::nullopt);
    selector = "side " + f.required_string("side");
    Aabb bounds;
    for (const Vec3& v : vertices) bounds.add(v);
    const double tol = f.number("tolerance", 1e-4 * bounds.size().norm(), Range::non_negative());
    const int axis = side / 2;
    const double plane = (side % 2 == 0) ? bounds.min[axis] : bounds.max[axis];
    for (std::size_t i = 0; i < vertices.size(); ++i)
      if (std::abs(vertices[i][axis] - plane) <= tol) nodes.push_back(static_cast<mesh::Index>(i));
  } else if (t.contains("marker")) {
    const int marker = f.integer("marker", 0, -1000000000, 1000000000);
    selector = fmt::format("marker {}", marker);
    if (!b.volume || b.volume->face_markers.empty())
      f.fail("marker", "the body's mesh carries no face markers (Gmsh physical surfaces, TetGen .face markers)");
    for (std::size_t i = 0; i < b.volume->faces.size(); ++i)
      if (b.volume->face_markers[i] == marker)
        for (const auto v : b.volume->faces[i]) nodes.push_back(v);
  } else if (t.contains("region")) {
    // Every node of the tetrahedra tagged so: the tissue on a segmented bone.
    const std::vector<int> tags = read_tags(f, "region");
    if (tags.empty()) f.fail("region", "give at least one region tag");
    if (!b.volume || b.volume->tet_regions.empty())
      f.fail("region", "the body's mesh " + b.mesh_source + " tags no regions");
    selector = "region";
    for (const int tag : tags) {
      if (std::find(b.volume->tet_regions.begin(), b.volume->tet_regions.end(), tag) == b.volume->tet_regions.end())
        f.fail("region", fmt::format("the mesh {} has no region {}", b.mesh_source, tag));
      selector += " " + std::to_string(tag);
    }
    for (std::size_t k = 0; k < b.volume->tets.size(); ++k)
      if (std::find(tags.begin(), tags.end(), b.volume->tet_regions[k]) != tags.end())
        for (const auto v : b.volume->tets[k]) nodes.push_back(v);
  } else {
    selector = "border";
    if (!f.boolean("border", true)) f.fail("border", "only 'border = true' selects nodes");
    if (b.volumetric()) f.fail("border", "'border' selects the open edge of a surface sheet; use side, box or marker on a volume");
    nodes = border_nodes(b.surface);
  }
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

FixedRegion read_fixed(Reader& f, const Body& b, std::size_t index) {
  FixedRegion region;
  region.name = f.string("name", fmt::format("fixed{}", index));
  auto nodes = select_nodes(f, b, region.selector);
  f.finish();
  if (nodes.empty()) f.fail_here("fixed region '" + region.name + "' (" + region.selector + ") selects no node");
  region.nodes = std::move(nodes);
  return region;
}

/// Loads and prescribed motions: a named node set with one vector and a ramp time.
template <class T>
T read_ramped_nodes(Reader& f, const Body& b, std::string default_name, const char* vector_key, Vec3 T::*vector,
                    const char* what) {
  T t;
  t.name = f.string("name", std::move(default_name));
  t.nodes = select_nodes(f, b, t.selector);
  t.*vector = f.required_vec3(vector_key);
  t.ramp_time = f.number("ramp_time", 0.0, Range::non_negative());
  f.finish();
  if (t.nodes.empty()) f.fail_here(fmt::format("{} '{}' ({}) selects no node", what, t.name, t.selector));
  return t;
}

NodeLoad read_load(Reader& f, const Body& b, std::size_t index) {
  return read_ramped_nodes(f, b, fmt::format("load{}", index), "force", &NodeLoad::force, "load");
}

PrescribedMotion read_prescribed(Reader& f, const Body& b, std::size_t index) {
  return read_ramped_nodes(f, b, fmt::format("prescribed{}", index), "displacement", &PrescribedMotion::displacement,
                           "prescribed motion");
}

/// The mapping of `mesh`'s vertices into body b's tetrahedra, refusing (at f["mesh"]) a vertex
/// farther outside them than f's `tolerance` (default 0.1% of the body's size: vertices may sit
/// on its boundary up to round-off and a mesher's tolerance). `what` names the surface.
std::shared_ptr<const physics::BarycentricMapping> map_into_volume(Reader& f, const Body& b, const mesh::TriMesh& mesh,
                                                                   const std::string& what) {
  const double tolerance = f.number("tolerance", 1e-3 * b.volume->bounds().size().norm(), Range::non_negative());
  auto mapping = std::make_shared<physics::BarycentricMapping>(*b.volume, mesh.vertices);
  if (mapping->max_outside_distance() > tolerance)
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
      if (mapping->outside_distance(v) > tolerance) {
        const Vec3& p = mesh.vertices[v];
        f.fail("mesh", fmt::format("{}: vertex {} at ({:g}, {:g}, {:g}) m lies {:g} m outside body '{}''s tetrahedra "
                                   "(tolerance {:g} m; set 'tolerance' or move the mesh)",
                                   what, v, p.x(), p.y(), p.z(), mapping->outside_distance(v), b.name, tolerance));
      }
  return mapping;
}

/// bodies.<name>.mapped[i]: a surface carried by the body's tetrahedra, mapped at load time.
MappedSurface read_mapped_surface(Reader& f, const Body& b, std::size_t index) {
  MappedSurface s;
  s.name = f.string("name", fmt::format("mapped{}", index));
  s.role = f.choice<MappedRole>("role",
                                {{"visual", MappedRole::visual},
                                 {"collision", MappedRole::collision},
                                 {"embedded", MappedRole::embedded}},
                                std::nullopt);
  LoadedMesh m = read_mesh_key(f, false, &b);
  s.source = m.source;
  if (m.surface && !m.surface->triangles.empty()) {
    s.mesh = std::move(*m.surface);
  } else if (m.volume && !m.volume->tets.empty()) {
    try {
      s.mesh = mesh::extract_boundary(*m.volume).surface;
    } catch (const InputError& e) {
      f.fail("mesh", std::string("invalid tetrahedral mesh: ") + e.what());
    }
  } else {
    f.fail("mesh", m.source + " holds no triangles");
  }
  s.mapping = map_into_volume(f, b, s.mesh, "mapped surface '" + s.name + "' (" + s.source + ")");
  f.finish();
  return s;
}

Probe read_probe(Reader& f, std::size_t index) {
  Probe p;
  p.name = f.string("name", fmt::format("probe{}", index));
  p.position = f.required_vec3("position");
  f.finish();
  return p;
}

}  // namespace

void read_cspace_tools(Reader& r, Model& model, std::size_t body) {
  const std::vector<std::string> names = r.string_list("tools", {});
  if (names.size() != 2)
    r.fail("tools", "a two-point space is felt by two tools, at its first and its second point: "
                    "tools = [\"first\", \"second\"]");
  Body::ConfigurationSpace& c = *model.bodies[body].cspace;
  for (const auto& name : names) {
    const std::size_t t = resolve_name(r, "tools", name, model.tools, "tool");
    if (model.tools[t].devices.size() != 1)
      r.fail("tools", fmt::format("tool '{}' must be driven by one device of its own", name));
    c.tools.push_back(t);
  }
  if (model.tools[c.tools[0]].devices == model.tools[c.tools[1]].devices)
    r.fail("tools", "the two points are felt by two tools on two devices");
}

Body read_body(Reader& r, const std::string& name, const Model& model) {
  Body b;
  b.name = name;
  b.kind = r.choice<BodyKind>("kind",
                              {{"surface_mass_spring", BodyKind::surface_mass_spring},
                               {"tet_mass_spring", BodyKind::tet_mass_spring},
                               {"fem", BodyKind::fem},
                               {"rigid", BodyKind::rigid},
                               {"embedded", BodyKind::embedded},
                               {"cloth", BodyKind::cloth},
                               {"cspace", BodyKind::fem}},  // an FEM body rendered from a precomputed space
                              std::nullopt);
  if (r.string("kind") == "cspace") {
    Body::ConfigurationSpace c;
    c.online = r.boolean("online", false);
    if (c.online) {
      // Forces from the solved points as they come (trilinear over a cell, the nearest solved
      // corner until it is complete): no other interpolation applies.
      if (r.has("space")) r.fail("space", "an on-line space is built during the run; give either `space` or `online = true`");
      if (r.has("interpolation")) r.fail("interpolation", "an on-line space is interpolated trilinearly over its solved points");
      c.workers = r.integer("workers", 1, 1, 256);
    } else {
      c.file = resolve_file(r, "space", r.required_string("space"));
      c.interpolation = read_interpolation(r, "interpolation");
      if (r.has("workers")) r.fail("workers", "`workers` is for an on-line space (online = true)");
    }
    // `tools` names tools, which are read after the bodies: read_cspace_tools resolves it.
    if (r.has("tools") && c.online)
      r.fail("tools", "on-line construction builds spaces of one point; a two-point space is built with "
                      "`tactus precompute` and given as `space`");
    b.cspace = std::move(c);
  }
  if (b.kind == BodyKind::embedded) {
    // Read after every other body (read_model), so the host exists whatever the order.
    const std::size_t host = resolve_name(r, "host", r.required_string("host"), model.bodies, "body");
    if (!model.bodies[host].volumetric())
      r.fail("host", fmt::format("body '{}' is '{}'; an embedded surface rides on the tetrahedra of a 'fem' or "
                                 "'tet_mass_spring' body", model.bodies[host].name, to_string(model.bodies[host].kind)));
    LoadedMesh m = read_mesh_key(r, false, &model.bodies[host]);
    b.mesh_source = m.source;
    if (!m.surface || m.surface->triangles.empty()) r.fail("mesh", m.source + " holds no triangle surface");
    b.surface = std::move(*m.surface);
    b.host = host;
    b.host_mapping = map_into_volume(r, model.bodies[host], b.surface, "embedded body '" + b.name + "' (" + b.mesh_source + ")");
    r.finish();
    return b;
  }
  const bool rigid = b.kind == BodyKind::rigid;

  if (b.kind == BodyKind::cloth) {
    if (r.table().contains("material")) r.fail("material", "a cloth body takes its properties from `fabric` or `curves`");
    read_cloth(r, b);
  } else if (const auto material = r.string("material")) {
    b.material = resolve_name(r, "material", *material, model.materials, "material");
    if (b.kind == BodyKind::fem && !model.materials[*b.material].law)
      r.fail("material", "material '" + *material + "' has model 'mass_spring'; a 'fem' body needs a continuum model"
                         " (linear, corotational, stvk, neo_hookean or mooney_rivlin)");
  } else if (!rigid) {
    r.fail_missing("material", "a material name");
  }

  if (b.kind != BodyKind::cloth) attach_mesh(r, b, read_mesh_key(r, b.volumetric()));
  if (auto regions = r.table("regions")) read_region_materials(*regions, b, model);

  for (const char* key : {"levels", "properties"})
    if (!rigid && r.table().contains(key))
      r.fail(key, fmt::format("'{}' is for rigid bodies (many touchable objects in a scene); body '{}' is '{}'", key,
                              b.name, to_string(b.kind)));
  if (auto t = r.table("levels")) b.levels = read_levels(*t);
  if (auto t = r.table("properties")) b.properties = read_properties(*t);

  if (rigid) {
    if (r.table().contains("fixed")) r.fail("fixed", "a rigid body does not move; it takes no fixed regions");
    r.finish();
    return b;
  }

  std::set<std::string> region_names;
  std::size_t index = 0;
  for (Reader& f : r.table_array("fixed")) {
    FixedRegion region = read_fixed(f, b, index++);
    if (!region_names.insert(region.name).second)
      f.fail("name", "duplicate fixed region name '" + region.name + "'");
    b.fixed.push_back(std::move(region));
  }
  index = 0;
  for (Reader& f : r.table_array("loads")) {
    NodeLoad load = read_load(f, b, index++);
    if (!region_names.insert(load.name).second) f.fail("name", "duplicate region name '" + load.name + "'");
    b.loads.push_back(std::move(load));
  }
  index = 0;
  for (Reader& f : r.table_array("prescribed")) {
    PrescribedMotion p = read_prescribed(f, b, index++);
    if (!region_names.insert(p.name).second) f.fail("name", "duplicate region name '" + p.name + "'");
    for (const auto& fixed : b.fixed)
      for (auto n : p.nodes)
        if (std::binary_search(fixed.nodes.begin(), fixed.nodes.end(), n))
          f.fail_here(fmt::format("prescribed motion '{}' moves node {}, which fixed region '{}' holds", p.name, n,
                                  fixed.name));
    b.prescribed.push_back(std::move(p));
  }
  index = 0;
  std::set<std::string> probe_names;
  for (Reader& f : r.table_array("probes")) {
    Probe p = read_probe(f, index++);
    if (!probe_names.insert(p.name).second) f.fail("name", "duplicate probe name '" + p.name + "'");
    b.probes.push_back(std::move(p));
  }
  index = 0;
  for (Reader& f : r.table_array("mapped")) {
    if (!b.volumetric())
      f.fail_here("mapped surfaces ride on tetrahedra; a '" + std::string(to_string(b.kind)) + "' body has none");
    MappedSurface s = read_mapped_surface(f, b, index++);
    for (const auto& other : b.mapped)
      if (other.name == s.name) f.fail("name", "duplicate mapped surface name '" + s.name + "'");
    b.mapped.push_back(std::move(s));
  }
  b.load_steps = r.integer("load_steps", 1, 1, 100000);

  physics::StepSettings& step = b.stepping;
  const physics::StepSettings defaults;
  if (r.string("integrator") == "static")
    r.fail("integrator", "'static' is not a time integrator: bodies step in time in a run (use implicit_euler); "
                         "`tactus solve --static` solves a scene for equilibrium");
  step.integrator = r.choice<physics::Integrator>("integrator",
                                                  {{"explicit_euler", physics::Integrator::explicit_euler},
                                                   {"symplectic_euler", physics::Integrator::symplectic_euler},
                                                   {"rk4", physics::Integrator::rk4},
                                                   {"implicit_euler", physics::Integrator::implicit_euler}},
                                                  defaults.integrator);
  b.time_step = r.number("time_step", 1.0 / model.rates.simulation, Range::open_closed(0.0, 1.0));
  step.solver = r.choice<physics::LinearSolver>(
      "solver", {{"cg", physics::LinearSolver::conjugate_gradient}, {"cholesky", physics::LinearSolver::cholesky}},
      defaults.solver);
  step.cg_tolerance = r.number("solver_tolerance", defaults.cg_tolerance, Range::open(0.0, 1.0));
  step.cg_max_iterations = r.integer("solver_max_iterations", defaults.cg_max_iterations, 1, 1000000);
  b.mass_matrix = r.choice<MassMatrix>("mass_matrix",
                                       {{"lumped", MassMatrix::lumped}, {"consistent", MassMatrix::consistent}},
                                       MassMatrix::lumped);
  if (b.mass_matrix == MassMatrix::consistent) {
    if (b.kind != BodyKind::fem) r.fail("mass_matrix", "a consistent mass is for 'fem' bodies; spring networks carry lumped masses");
    if (step.integrator != physics::Integrator::implicit_euler)
      r.fail("mass_matrix", "a consistent mass needs integrator = \"implicit_euler\": explicit integrators divide by"
                            " a lumped mass");
  }
  step.newton_iterations = r.integer("newton_iterations", defaults.newton_iterations, 1, 100);
  if (step.newton_iterations > 1 && step.integrator != physics::Integrator::implicit_euler)
    r.fail("newton_iterations", "only implicit_euler steps iterate Newton; remove the key or use implicit_euler");
  step.factor_reuse_steps = r.integer("factor_reuse_steps", defaults.factor_reuse_steps, 1, 1000);
  if (step.factor_reuse_steps > 1 && !step.can_reuse_factor())
    r.fail("factor_reuse_steps", "a factorization is reused only by linearized implicit_euler steps solved by "
                                 "cholesky (newton_iterations 1); remove the key or set those");
  // A fabric's tensile curve stiffens many times over within a step's stretch: a tangent from
  // a step before underestimates it, and what it leaves out acts explicitly. Measured on
  // scenes/fabric.toml with 2: the grasped fabric slipped through the fingers (20 N clamped).
  if (step.factor_reuse_steps > 1 && b.kind == BodyKind::cloth)
    r.fail("factor_reuse_steps", "a cloth body factorizes every step: its stretch stiffens too fast within a step "
                                 "for a tangent from an earlier one (docs/scene-format.md); remove the key");

  if (b.kind == BodyKind::surface_mass_spring) {
    b.thickness = r.number("thickness", 0.001, Range::open_closed(0.0, 1.0));
    const auto springs = r.string_list("springs", {"longitudinal"});
    if (springs.empty()) r.fail("springs", "give at least one spring type");
    const std::vector<std::pair<std::string, SpringType>> known{{"longitudinal", SpringType::longitudinal},
                                                                {"diagonal", SpringType::diagonal},
                                                                {"torsional", SpringType::torsional},
                                                                {"bending", SpringType::bending}};
    for (const auto& s : springs) {
      auto it = std::find_if(known.begin(), known.end(), [&](const auto& k) { return k.first == s; });
      if (it == known.end())
        r.fail("springs", "unknown spring type '" + s + "' (expected longitudinal, diagonal, torsional or bending)");
      if (std::find(b.springs.begin(), b.springs.end(), it->second) != b.springs.end())
        r.fail("springs", "spring type '" + s + "' listed twice");
      b.springs.push_back(it->second);
    }
  }
  b.nodules = read_nodules(r, b);
  r.finish();
  return b;
}

}  // namespace tactus::scene::detail
