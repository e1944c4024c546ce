// bodies.<name>.nodules (spheres under a skin sheet, seed 004) and the [feedback] table of
// palpation runs.
#include <algorithm>
#include <cctype>
#include <set>

#include <fmt/format.h>

#include "scene/loader.hpp"

namespace tactus::scene::detail {

namespace {

Nodule read_nodule(Reader& r, const Body& body, std::size_t index) {
  Nodule n;
  n.name = r.string("name", fmt::format("nodule{}", index));
  const bool name_ok = !n.name.empty() && n.name.size() <= 64 &&
                       std::all_of(n.name.begin(), n.name.end(), [](char c) {
                         return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
                       });
  if (!name_ok) r.fail("name", "a nodule name is 1 to 64 letters, digits, '_' or '-'");
  n.center = r.required_vec3("center");
  n.radius = r.required_number("radius", Range::positive());
  const bool has_rigid = r.table().contains("rigid");
  const bool rigid = r.boolean("rigid", false);
  const auto young = r.number("young_modulus", Range::positive());
  if (has_rigid && rigid && young)
    r.fail("young_modulus", "a rigid nodule takes no Young's modulus; give 'rigid = true' or 'young_modulus', not both");
  if (!rigid && !young)
    r.fail_missing("young_modulus", has_rigid ? "a soft nodule (rigid = false) needs its Young's modulus [Pa]"
                                              : "give 'rigid = true' or the Young's modulus of a soft nodule [Pa]");
  n.rigid = rigid;
  if (young) n.young_modulus = *young;
  if (rigid && r.table().contains("poisson_ratio"))
    r.fail("poisson_ratio", "a rigid nodule takes no Poisson ratio");
  n.poisson_ratio = r.number("poisson_ratio", n.poisson_ratio, Range::open(-1.0, 0.5));
  r.finish();

  // A held node inside the sphere could never be pushed out of it.
  const auto& nodes = body.simulation_vertices();
  for (const auto& region : body.fixed)
    for (const auto i : region.nodes)
      if ((nodes[static_cast<std::size_t>(i)] - n.center).norm() < n.radius)
        r.fail_here(fmt::format("nodule '{}' encloses node {} of fixed region '{}' (a held node cannot be pushed "
                                "out); move the nodule or shrink it",
                                n.name, i, region.name));
  return n;
}

}  // namespace

std::vector<Nodule> read_nodules(Reader& r, const Body& body) {
  std::vector<Nodule> out;
  if (!r.table().contains("nodules")) return out;
  if (body.kind != BodyKind::surface_mass_spring)
    r.fail("nodules", fmt::format("nodules lie under a 'surface_mass_spring' sheet; a '{}' body takes none",
                                  to_string(body.kind)));
  std::set<std::string> names;
  std::size_t index = 0;
  for (Reader& n : r.table_array("nodules")) {
    Nodule nodule = read_nodule(n, body, index++);
    if (!names.insert(nodule.name).second) n.fail("name", "duplicate nodule name '" + nodule.name + "'");
    out.push_back(std::move(nodule));
  }
  return out;
}

Feedback read_feedback(Reader& root) {
  Feedback f;
  if (auto r = root.table("feedback")) {
    f.safe_force = r->number("safe_force", f.safe_force, Range::non_negative());
    r->finish();
  }
  return f;
}

}  // namespace tactus::scene::detail
