// [precompute]: the configuration space `tactus precompute` builds for one FEM body.
#include <algorithm>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "precompute/grid.hpp"
#include "scene/loader.hpp"

namespace tactus::scene::detail {

precompute::Interpolation read_interpolation(Reader& r, std::string_view key) {
  return r.choice<precompute::Interpolation>(key,
                                             {{"trilinear", precompute::Interpolation::trilinear},
                                              {"rbf_cubic", precompute::Interpolation::rbf_cubic},
                                              {"rbf_thin_plate", precompute::Interpolation::rbf_thin_plate},
                                              {"polynomial", precompute::Interpolation::polynomial},
                                              {"tricubic_hermite", precompute::Interpolation::tricubic_hermite},
                                              {"rbf_hermite", precompute::Interpolation::rbf_hermite}},
                                             precompute::Interpolation::trilinear);
}

precompute::SpaceSettings read_precompute(Reader& r, Model& model) {
  precompute::SpaceSettings s;
  std::optional<std::size_t> index;
  if (const auto name = r.string("body")) {
    index = resolve_name(r, "body", *name, model.bodies, "body");
  } else {
    for (std::size_t i = 0; i < model.bodies.size(); ++i)
      if (model.bodies[i].kind == BodyKind::fem) {
        if (index) r.fail_missing("body", "the scene has several FEM bodies; name the one to precompute");
        index = i;
      }
    if (!index) r.fail_here("a configuration space needs an FEM body, and the scene has none");
  }
  const Body& body = model.bodies[*index];
  if (body.kind != BodyKind::fem || !body.volume)
    r.fail("body", "body '" + body.name + "' is not an FEM body (kind = \"fem\")");
  s.body = body.name;

  // A point's contact node: the surface node nearest to where the key puts it; its patch:
  // the nodes within patch_radius of it. Neither may lie in a fixed region.
  const auto& vertices = body.volume->vertices;
  auto contact_node = [&](const char* key, const Vec3& at) {
    std::int32_t node = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t v = 0; v < body.surface.vertices.size(); ++v) {
      const double d = (body.surface.vertices[v] - at).squaredNorm();
      if (d < best) {
        best = d;
        node = static_cast<std::int32_t>(body.surface_to_volume[v]);
      }
    }
    for (const auto& f : body.fixed)
      if (std::binary_search(f.nodes.begin(), f.nodes.end(), static_cast<mesh::Index>(node)))
        r.fail(key, fmt::format("the nearest surface node ({}) lies in fixed region '{}'", node, f.name));
    return node;
  };
  auto patch_of = [&](std::int32_t node) {
    std::vector<std::int32_t> patch;
    const Vec3 centre = vertices[static_cast<std::size_t>(node)];
    for (std::size_t v = 0; v < vertices.size(); ++v)
      if ((vertices[v] - centre).norm() <= s.patch_radius) patch.push_back(static_cast<std::int32_t>(v));
    for (const auto& f : body.fixed)
      for (auto n : patch)
        if (std::binary_search(f.nodes.begin(), f.nodes.end(), static_cast<mesh::Index>(n)))
          r.fail("patch_radius", fmt::format("the contact patch reaches fixed region '{}' (node {})", f.name, n));
    return patch;
  };
  s.contact_node = contact_node("contact_point", r.required_vec3("contact_point"));
  const Vec3 node = vertices[static_cast<std::size_t>(s.contact_node)];
  s.patch_radius = r.number("patch_radius", 0.0, Range::non_negative());
  s.patch_nodes = patch_of(s.contact_node);

  s.spacing = r.required_number("spacing", Range::positive());
  s.bounds_min = r.required_vec3("min");
  s.bounds_max = r.required_vec3("max");
  if (!(s.bounds_min.array() < s.bounds_max.array()).all()) r.fail("max", "max must exceed min on every axis");
  s.load_steps = r.integer("load_steps", s.load_steps, 1, 1000);
  s.max_step_halvings = r.integer("max_step_halvings", s.max_step_halvings, 0, 20);
  s.max_iterations = r.integer("max_iterations", s.max_iterations, 1, 1000);
  s.tolerance = r.number("tolerance", s.tolerance, Range::open_closed(0.0, 1e-2));
  s.gravity = r.boolean("gravity", s.gravity);
  s.refine_points = r.integer("refine_points", s.refine_points, 0, 10'000'000);
  s.interpolation = read_interpolation(r, "interpolation");
  // A probe space: the patch is the bonded end of a rigid probe that may lean.
  if (const auto axis = r.vec3("probe_axis")) {
    if (!(axis->norm() > 0.0)) r.fail("probe_axis", "the probe's axis must be a non-zero direction");
    s.probe.axis = axis->normalized();
    s.probe.max_tilt = r.required_number("probe_tilt", Range::open(0.0, 90.0)) * std::numbers::pi / 180.0;
    s.probe.tilt_levels = r.integer("probe_tilt_levels", 3, 3, 15);
    if (s.probe.tilt_levels % 2 == 0)
      r.fail("probe_tilt_levels", "the leans per axis must be odd, so that the rest axis is one of them");
    if (s.patch_nodes.size() < 2)
      r.fail("patch_radius", "a probe turns its patch about the contact node: give it a patch_radius that takes in "
                             "more nodes than that one");
  } else {
    for (const char* key : {"probe_tilt", "probe_tilt_levels"})
      if (r.has(key)) r.fail(key, "a probe space also needs probe_axis (the probe's rest direction, into the body)");
  }
  // A two-point space: a second interaction point with its own box (precompute/pair.hpp).
  if (const auto second = r.vec3("second_point")) {
    if (s.probe.enabled()) r.fail("second_point", "a space holds either a probe or a second point, not both");
    s.pair.node = contact_node("second_point", *second);
    s.pair.patch_nodes = patch_of(s.pair.node);
    for (auto n : s.pair.patch_nodes)
      if (std::binary_search(s.patch_nodes.begin(), s.patch_nodes.end(), n))
        r.fail("second_point", fmt::format("the two points' patches share node {} (the nearest surface node to "
                                           "second_point is {}); put the points farther apart than twice "
                                           "patch_radius",
                                           n, s.pair.node));
    // The tools that feel the two points when `tactus run --space` renders the space.
    if (r.has("tools")) {
      const std::vector<std::string> names = r.string_list("tools", {});
      if (names.size() != 2) r.fail("tools", "name the tools at the first and the second point: tools = [A, B]");
      for (const auto& name : names)
        model.precompute_tools.push_back(resolve_name(r, "tools", name, model.tools, "tool"));
      if (model.precompute_tools[0] == model.precompute_tools[1])
        r.fail("tools", "the two points are felt by two different tools");
    }
    s.pair.bounds_min = r.required_vec3("second_min");
    s.pair.bounds_max = r.required_vec3("second_max");
    if (!(s.pair.bounds_min.array() < s.pair.bounds_max.array()).all())
      r.fail("second_max", "second_max must exceed second_min on every axis");
  } else {
    for (const char* key : {"second_min", "second_max", "tools"})
      if (r.has(key)) r.fail(key, "a two-point space also needs second_point (where the second point rests)");
  }
  auto check_grid = [&](const Vec3& anchor, const Vec3& lo, const Vec3& hi, const char* min_key, const char* what) {
    precompute::Grid grid;
    try {
      grid = precompute::Grid::through(anchor, lo, hi, s.spacing);
    } catch (const InputError& e) {
      r.fail(min_key, e.reason());
    }
    for (int a = 0; a < 3; ++a)
      if (grid.counts[static_cast<std::size_t>(a)] < 2)
        r.fail("spacing", fmt::format("the grid has a single point along {}; make the box wider than the spacing "
                                      "on either side of {}",
                                      "xyz"[a], what));
  };
  check_grid(node, s.bounds_min, s.bounds_max, "min", "the contact node");
  if (s.pair.enabled())
    check_grid(vertices[static_cast<std::size_t>(s.pair.node)], s.pair.bounds_min, s.pair.bounds_max, "second_min",
               "the second point's node");
  r.finish();
  return s;
}

}  // namespace tactus::scene::detail
