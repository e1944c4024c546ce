// bodies.<name> of kind = "cloth": the fabric (a key of the fabric database, or the scene's
// own measured curves), the sheet or mesh it is cut from, the stand's clamp, damping and
// friction against skin.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "core/input_file.hpp"
#include "mesh/io/mesh_io.hpp"
#include "physics/cloth/kes.hpp"
#include "physics/cloth/sheet.hpp"
#include "scene/loader.hpp"

namespace tactus::scene::detail {
namespace {

/// The fabric database where a scene names no other: the source tree's, else the installed one.
std::filesystem::path bundled_database() {
  const std::filesystem::path source = std::filesystem::path(TACTUS_DATA_DIR) / "fabrics.toml";
  std::error_code ec;
  if (std::filesystem::is_regular_file(source, ec)) return source;
  return std::filesystem::path(TACTUS_INSTALLED_DATA_DIR) / "fabrics.toml";
}

physics::KesDirection read_kes_direction(Reader& d, double tensile_max_load) {
  physics::KesDirection k;
  k.emt = d.required_number("EMT", Range::open(0.0, 100.0));
  k.lt = d.required_number("LT", Range::open_closed(0.0, 1.0));
  k.wt = d.required_number("WT", Range::positive());
  k.b = d.required_number("B", Range::positive());
  k.g = d.required_number("G", Range::positive());
  k.hg = d.number("2HG", 0.0, Range::non_negative());
  k.hg5 = d.number("2HG5", 0.0, Range::non_negative());
  // Recorded for the reader of the database; the model does not use them (no tensile
  // recovery or bending hysteresis).
  for (const char* key : {"RT", "2HB"}) (void)d.number(key, Range::non_negative());
  const double mismatch = physics::kes_tensile_energy_mismatch(k, tensile_max_load);
  if (mismatch > 0.05)
    d.fail("WT", fmt::format("WT = {} disagrees by {:.0f} % with LT·½·F_m·EMT/100 = {} (the definition of LT); "
                             "one of EMT, LT, WT is misprinted",
                             number_text(k.wt), 100.0 * mismatch, number_text(k.lt * 0.5 * tensile_max_load * k.emt / 100.0)));
  d.finish();
  return k;
}

struct DatabaseFabric {
  physics::KesFabric kes;
  bool illustrative = false;
  std::optional<std::pair<double, double>> friction;  ///< static, kinetic; none: the scene's defaults
};

/// Fabric `key` of the database at `path`; errors point into the database file.
DatabaseFabric read_database_fabric(Reader& body, const std::filesystem::path& path, const std::string& key) {
  const std::string text = read_input_file(path);
  toml::table root;
  Context ctx;
  ctx.file = path.string();
  ctx.base_dir = path.parent_path();
  try {
    root = toml::parse(text, path.string());
  } catch (const toml::parse_error& e) {
    throw InputError(location(ctx, e.source()), std::string(e.description()));
  }
  Reader db(ctx, root, "");
  std::vector<std::string> keys;
  for (const auto& [k, v] : root) keys.emplace_back(k.str());
  if (!root.contains(key)) {
    std::string message = fmt::format("no fabric '{}' in {}", key, path.generic_string());
    if (const auto s = suggestion(key, keys); !s.empty()) message += "; " + s;
    else message += fmt::format(" (it holds {})", fmt::join(keys, ", "));
    body.fail("fabric", message);
  }
  const auto table = db.table(key);
  if (!table) body.fail("fabric", fmt::format("'{}' in {} is not a table", key, path.generic_string()));
  Reader f = *table;
  DatabaseFabric out;
  for (const char* k : {"name", "structure", "fibre", "source", "illustrative_note"}) (void)f.string(k);
  out.illustrative = f.boolean("illustrative", false);
  out.kes.w = f.required_number("W", Range::positive());
  (void)f.number("T", Range::positive());
  out.kes.tensile_max_load = f.number("tensile_max_load", 500.0, Range::positive());
  auto direction = [&](const char* name) {
    auto d = f.table(name);
    if (!d) f.fail_missing(name, "the KES values of this direction");
    return read_kes_direction(*d, out.kes.tensile_max_load);
  };
  out.kes.warp = direction("warp");
  out.kes.weft = direction("weft");
  if (auto fr = f.table("friction")) {
    const double mu_s = fr->required_number("static", Range::positive());
    const double mu_k = fr->required_number("kinetic", Range::positive());
    if (mu_k > mu_s) fr->fail("kinetic", "the kinetic friction coefficient exceeds the static one");
    out.friction = {mu_s, mu_k};
    (void)fr->number("MIU", Range::positive());
    (void)fr->string("source");
    (void)fr->boolean("illustrative", false);
    fr->finish();
  }
  f.finish();
  return out;
}

/// One measured curve {x = [...], y = [...]} of the scene's own fabric.
physics::MeasuredCurve read_curve(Reader& c, std::string_view key, const char* x_name, const char* y_name,
                                  physics::MeasuredCurve::BelowZero below) {
  const std::string what = fmt::format("the {} against {}", y_name, x_name);
  auto t = c.table(key);
  if (!t) c.fail_missing(key, fmt::format("a table {{ {} = [...], {} = [...] }}", x_name, y_name));
  auto x = t->number_list(x_name), y = t->number_list(y_name);
  try {
    // A fabric resists compression feebly: 1 % of the secant modulus at the last point.
    const double slope = x.size() >= 2 && x.back() > 0.0 ? 0.01 * y.back() / x.back() : 0.0;
    physics::MeasuredCurve curve(std::move(x), std::move(y), below, slope, what);
    t->finish();
    return curve;
  } catch (const InputError& e) {
    t->fail_here(e.reason());
  }
}

physics::ClothMaterial read_curves(Reader& c) {
  physics::ClothMaterial m;
  using Below = physics::MeasuredCurve::BelowZero;
  m.areal_density = c.required_number("areal_density", Range::positive());
  m.warp = read_curve(c, "warp", "strain", "tension", Below::linear);
  m.weft = read_curve(c, "weft", "strain", "tension", Below::linear);
  m.shear = read_curve(c, "shear", "angle", "force", Below::mirror);
  m.bend_warp = read_curve(c, "bend_warp", "curvature", "moment", Below::mirror);
  m.bend_weft = read_curve(c, "bend_weft", "curvature", "moment", Below::mirror);
  m.shear_friction = c.number("shear_friction", 0.0, Range::non_negative());
  m.shear_friction_5 = c.number("shear_friction_5", 0.0, Range::non_negative());
  if (m.shear_friction_5 > 0.0 && !(m.shear_friction > 0.0))
    c.fail("shear_friction_5", "the friction at 5° needs `shear_friction` (at 0.5°) too");
  c.finish();
  return m;
}

Vec3 unit_axis(Reader& r, std::string_view key, const Vec3& fallback) {
  const Vec3 a = r.vec3(key, fallback);
  if (!(a.norm() > 0.0)) r.fail(key, "an axis needs a nonzero direction");
  return a.normalized();
}

}  // namespace

void read_cloth(Reader& r, Body& b) {
  Cloth c;
  physics::ClothMaterial material;
  physics::ClothMesh mesh;
  const bool named = r.table().contains("fabric"), own = r.table().contains("curves");
  if (named == own)
    r.fail_here("a cloth body takes either `fabric` (a key of the fabric database) or a `curves` table of its own");
  if (named) {
    c.fabric = r.required_string("fabric");
    std::filesystem::path database;
    if (const auto path = r.string("fabric_database")) {
      database = resolve_file(r, "fabric_database", *path);
    } else {
      if (!r.context().options.allow_file_access) r.fail("fabric", "file access is disabled; cannot read the fabric database");
      database = bundled_database();
    }
    const DatabaseFabric fabric = read_database_fabric(r, database, c.fabric);
    try {
      material = physics::kes_material(fabric.kes, "fabric '" + c.fabric + "'");
    } catch (const InputError& e) {
      r.fail("fabric", e.reason());
    }
    c.fabric_source = database.generic_string();
    c.illustrative = fabric.illustrative;
    if (fabric.friction) {
      c.static_friction = fabric.friction->first;
      c.kinetic_friction = fabric.friction->second;
    }
  } else {
    Reader curves = *r.table("curves");
    material = read_curves(curves);
    c.fabric_source = r.context().file;
  }
  // The shear loop (KES 2HG) only where the scene asks for it.
  if (!r.boolean("shear_hysteresis", false))
    material.shear_friction = material.shear_friction_5 = 0.0;
  else if (!(material.shear_friction > 0.0))
    r.fail("shear_hysteresis", named ? "fabric '" + c.fabric + "' has no 2HG (the shear loop's width) in the database"
                                     : "the scene's own curves give no `shear_friction`");
  // Damping time constants [s]: a choice, not a measurement (docs/scene-format.md).
  physics::ClothMaterial& m = material;
  m.stretch_damping = m.shear_damping = 1e-3;
  m.bend_damping = 1e-2;
  if (auto d = r.table("damping")) {
    m.stretch_damping = d->number("stretch", m.stretch_damping, Range::non_negative());
    m.shear_damping = d->number("shear", m.shear_damping, Range::non_negative());
    m.bend_damping = d->number("bend", m.bend_damping, Range::non_negative());
    d->finish();
  }
  if (auto fr = r.table("friction")) {
    c.static_friction = fr->number("static", c.static_friction, Range::positive());
    c.kinetic_friction = fr->number("kinetic", c.kinetic_friction, Range::positive());
    if (c.kinetic_friction > c.static_friction)
      fr->fail("kinetic", "the kinetic friction coefficient exceeds the static one");
    fr->finish();
  }

  const Vec3 warp = unit_axis(r, "warp_axis", -Vec3::UnitZ()), weft = unit_axis(r, "weft_axis", Vec3::UnitX());
  if (std::abs(warp.dot(weft)) > 1e-6) r.fail("weft_axis", "the weft axis must be perpendicular to the warp axis");
  const Vec3 origin = r.vec3("origin", Vec3::Zero());
  const auto bending = r.choice<physics::SheetBending>(
      "bending", {{"yarns", physics::SheetBending::yarns}, {"hinges", physics::SheetBending::hinges}},
      physics::SheetBending::yarns);
  if (r.table().contains("mesh")) {
    // A fabric cut to a shape: flat at rest, (u, v) its rest positions along warp and weft;
    // every interior edge bends as a hinge.
    for (const char* key : {"size", "spacing", "clamp"})
      if (r.table().contains(key)) r.fail(key, "a cloth given as a mesh takes no `" + std::string(key) + "` (hold it with [[fixed]] regions)");
    if (r.table().contains("bending") && bending == physics::SheetBending::yarns)
      r.fail("bending", "bending along the yarns needs a generated warp/weft sheet; a mesh bends at its edges (\"hinges\")");
    const auto path = resolve_file(r, "mesh", r.required_string("mesh"));
    mesh::MeshFile file;
    try {
      file = mesh::read_mesh(path);
    } catch (const InputError& e) {
      r.fail("mesh", e.what());
    }
    if (!file.surface || file.surface->triangles.empty()) r.fail("mesh", path.generic_string() + " holds no triangles");
    mesh.mesh = std::move(*file.surface);
    for (const Vec3& p : mesh.mesh.vertices) mesh.uv.emplace_back((p - origin).dot(warp), (p - origin).dot(weft));
    b.mesh_source = path.generic_string();
  } else {
    const Vec2 size = r.required_vec2("size");
    if (!(size.x() > 0.0 && size.y() > 0.0)) r.fail("size", "the sheet's warp length and weft width must be positive");
    const double spacing = r.required_number("spacing", Range::positive());
    if (spacing > 0.5 * std::min(size.x(), size.y())) r.fail("spacing", "the spacing must leave at least two cells each way");
    physics::SheetGrid grid;
    try {
      grid = physics::rectangular_sheet(size.x(), size.y(), spacing, origin, warp, weft, bending);
    } catch (const InputError& e) {
      r.fail("spacing", e.reason());
    }
    const int clamp = r.integer("clamp", 2, 0, grid.nodes_u - 1);
    if (clamp == 1) r.fail("clamp", "a clamp holds at least 2 warp columns (to hold the fabric level), or 0 for none");
    if (clamp > 0) {
      auto nodes = physics::clamp_warp_start(grid, clamp);
      std::sort(nodes.begin(), nodes.end());
      b.fixed.push_back({"clamp", fmt::format("first {} warp columns", clamp), std::move(nodes)});
    }
    c.nodes_u = grid.nodes_u;
    c.nodes_v = grid.nodes_v;
    mesh = std::move(grid.cloth);
    b.mesh_source = fmt::format("sheet {} × {} m, spacing {} m", number_text(size.x()), number_text(size.y()),
                                number_text(spacing));
  }
  try {
    c.model = std::make_shared<const physics::ClothModel>(mesh, std::move(material));
  } catch (const InputError& e) {
    if (c.nodes_u == 0) r.fail("mesh", e.reason());
    if (!c.fabric.empty()) r.fail("fabric", e.reason());
    r.fail_here(e.reason());
  }
  b.surface = std::move(mesh.mesh);
  b.cloth = std::move(c);
}

}  // namespace tactus::scene::detail
