// algorithms.<name>: the force algorithms that turn tool–tissue contact into a force.
#include <fmt/format.h>

#include "scene/loader.hpp"

namespace tactus::scene::detail {
namespace {

/// algorithms.<name>.layers of a needle: the bodies it pierces and how each resists, or one
/// layer with default values per body of the algorithm when the key is absent.
std::vector<NeedleLayer> read_needle_layers(Reader& r, const Algorithm& a, const Model& model) {
  const Tool& tool = model.tools[a.tool];
  const double max_force = tool.devices.empty() ? 0.0 : model.devices[tool.devices.front()].max_force;
  std::vector<NeedleLayer> layers;
  const auto default_layer = [](std::size_t body) {
    NeedleLayer l;
    l.body = body;
    return l;
  };
  if (!r.has("layers")) {
    if (a.bodies.empty())
      for (std::size_t b = 0; b < model.bodies.size(); ++b) layers.push_back(default_layer(b));
    else
      for (const std::size_t b : a.bodies) layers.push_back(default_layer(b));
    if (layers.size() > haptics::kMaxNeedleLayers)
      r.fail(a.bodies.empty() ? "type" : "bodies",
             fmt::format("a needle pierces at most {} layers; name them under 'layers'", haptics::kMaxNeedleLayers));
    return layers;
  }
  if (r.has("bodies")) r.fail("bodies", "a needle takes its bodies from 'layers'; give one or the other");
  std::vector<Reader> tables = r.table_array("layers");
  if (tables.empty()) r.fail("layers", "needs at least one layer");
  if (tables.size() > haptics::kMaxNeedleLayers)
    r.fail("layers", fmt::format("a needle pierces at most {} layers, not {}", haptics::kMaxNeedleLayers, tables.size()));
  for (Reader& t : tables) {
    NeedleLayer l;
    const auto body = t.string("body");
    if (!body) t.fail_missing("body", "the name of the body this layer is");
    l.body = resolve_name(t, "body", *body, model.bodies, "body");
    for (const NeedleLayer& seen : layers)
      if (seen.body == l.body) t.fail("body", "body '" + *body + "' is already a layer of this needle");
    l.rupture_force = t.number("rupture_force", l.rupture_force, Range::positive());
    if (max_force > 0.0 && l.rupture_force >= max_force)
      t.fail("rupture_force", fmt::format("{} N is not below the device's max_force ({} N): the hand would never "
                                          "feel the layer give way",
                                          l.rupture_force, max_force));
    l.stiffness = t.number("stiffness", l.stiffness, Range::positive());
    l.viscous_friction = t.number("viscous_friction", l.viscous_friction, Range::non_negative());
    l.coulomb_friction = t.number("coulomb_friction", l.coulomb_friction, Range::non_negative());
    t.finish();
    layers.push_back(l);
  }
  return layers;
}

}  // namespace

Algorithm read_algorithm(Reader& r, const std::string& name, const Model& model) {
  Algorithm a;
  a.name = name;
  enum Type { proxy, hertz_finger, fingerpad, multi_surface, pulse, needle, fabric_proxy };
  const Type type = r.choice<Type>("type",
                                   {{"proxy", proxy}, {"hertz_finger", hertz_finger}, {"fingerpad", fingerpad},
                                    {"multi_surface", multi_surface}, {"pulse", pulse}, {"needle", needle},
                                    {"fabric_proxy", fabric_proxy}},
                                   std::nullopt);
  const auto tool = r.string("tool");
  if (!tool) r.fail_missing("tool", "a tool name");
  a.tool = resolve_name(r, "tool", *tool, model.tools, "tool");
  const ToolShape& shape = model.tools[a.tool].shape;
  const bool is_needle = std::holds_alternative<NeedleTool>(shape);
  if ((type == needle) != is_needle)
    r.fail("tool", type == needle ? "the needle algorithm needs a tool of type 'needle'"
                                  : std::string("a needle tool takes the 'needle' algorithm, not this one"));
  if (type == hertz_finger && !std::holds_alternative<SphereTool>(shape) &&
      !std::holds_alternative<SphereSetTool>(shape))
    r.fail("tool", "hertz_finger needs a tool of type 'sphere' or 'sphere_set'");

  for (const auto& body : r.string_list("bodies", {})) {
    const std::size_t b = resolve_name(r, "bodies", body, model.bodies, "body");
    for (const std::size_t seen : a.bodies)
      if (seen == b) r.fail("bodies", "body '" + body + "' listed twice");
    a.bodies.push_back(b);
  }
  a.enabled = r.boolean("enabled", true);
  using contact::LocalModelKind;
  a.local_model = r.choice<LocalModelKind>("local_model",
                                           {{"plane", LocalModelKind::plane}, {"compliance", LocalModelKind::compliance},
                                            {"mass_spring", LocalModelKind::mass_spring}},
                                           a.local_model);
  a.max_tool_speed = r.number("max_tool_speed", a.max_tool_speed, Range::positive());
  a.force_smoothing = r.number("force_smoothing", a.force_smoothing, Range::closed(0.0, 0.1));
  a.load_spread = r.choice<LoadSpread>(
      "load_spread", {{"triangle", LoadSpread::triangle}, {"contact_disc", LoadSpread::contact_disc}}, a.load_spread);
  a.passivity_control = r.boolean("passivity_control", a.passivity_control);

  switch (type) {
    case fabric_proxy: {
      if (!std::holds_alternative<SphereTool>(shape)) r.fail("tool", "fabric_proxy needs a fingertip of type 'sphere'");
      if (a.bodies.empty()) r.fail_missing("bodies", "the cloth bodies the fingertip touches");
      for (std::size_t b : a.bodies)
        if (model.bodies[b].kind != BodyKind::cloth)
          r.fail("bodies", "fabric_proxy touches cloth bodies; '" + model.bodies[b].name + "' is '" +
                               std::string(to_string(model.bodies[b].kind)) + "'");
      if (a.local_model == contact::LocalModelKind::plane)
        r.fail("local_model", "a fabric is touched on its local patch: \"mass_spring\" (seed 002 §IV) or \"compliance\"");
      FabricProxyParams p;
      p.stiffness = r.number("stiffness", p.stiffness, Range::positive());
      p.static_friction = r.number("static_friction", Range::non_negative());
      p.kinetic_friction = r.number("kinetic_friction", Range::non_negative());
      if (p.static_friction.has_value() != p.kinetic_friction.has_value())
        r.fail(p.static_friction ? "static_friction" : "kinetic_friction",
               "give both friction coefficients, or neither (the fabric's own)");
      if (p.static_friction && *p.kinetic_friction > *p.static_friction)
        r.fail("kinetic_friction", "must not exceed static_friction");
      p.side = r.choice<int>("side", {{"front", +1}, {"back", -1}}, +1);
      p.mass = r.number("proxy_mass", p.mass, Range::positive());
      p.damping = r.number("proxy_damping", p.damping, Range::positive());
      if (const auto partner = r.string("partner")) {
        p.partner = resolve_name(r, "partner", *partner, model.tools, "tool");
        if (*p.partner == a.tool) r.fail("partner", "a fingertip cannot be its own partner");
        const auto pad = r.vec3("pad_normal");
        if (!pad) r.fail_missing("pad_normal", "the pad's side of the fingertip in the tool frame, for the grasp");
        if (!(pad->allFinite() && pad->norm() > 0.0)) r.fail("pad_normal", "must be finite and non-zero");
        p.pad_normal = pad->normalized();
        p.fabric_thickness = r.number("fabric_thickness", p.fabric_thickness, Range::positive());
        p.finger_static_friction = r.number("finger_static_friction", p.finger_static_friction, Range::non_negative());
        p.finger_kinetic_friction = r.number("finger_kinetic_friction", p.finger_kinetic_friction, Range::non_negative());
        if (p.finger_kinetic_friction > p.finger_static_friction)
          r.fail("finger_kinetic_friction", "must not exceed finger_static_friction");
      } else {
        for (const char* key : {"pad_normal", "fabric_thickness", "finger_static_friction", "finger_kinetic_friction"})
          if (r.has(key)) r.fail(key, "applies to a two-finger pair only: name the other fingertip's tool as 'partner'");
      }
      a.params = p;
      break;
    }
    case proxy: {
      ProxyParams p;
      p.stiffness = r.number("stiffness", p.stiffness, Range::positive());
      p.damping = r.number("damping", p.damping, Range::non_negative());
      p.static_friction = r.number("static_friction", p.static_friction, Range::non_negative());
      p.kinetic_friction = r.number("kinetic_friction", p.kinetic_friction, Range::non_negative());
      if (p.kinetic_friction > p.static_friction)
        r.fail("kinetic_friction", "must not exceed static_friction");
      a.params = p;
      break;
    }
    case hertz_finger: {
      HertzFingerParams p;
      // More rings smooth away the curvature a finger feels (mesh::CurvatureEstimator::kMaxRings).
      p.curvature_rings = r.integer("curvature_rings", p.curvature_rings, 1, 6);
      p.friction = r.number("friction", p.friction, Range::non_negative());
      p.weight_compensation = r.boolean("weight_compensation", p.weight_compensation);
      a.params = p;
      break;
    }
    case fingerpad: {
      FingerpadParams p;
      p.b = r.number("b", p.b, Range::positive());
      p.m = r.number("m", p.m, Range::positive());
      p.quasilinear_viscoelastic = r.boolean("quasilinear_viscoelastic", p.quasilinear_viscoelastic);
      a.params = p;
      break;
    }
    case multi_surface: {
      MultiSurfaceParams p;
      p.stiffness = r.number("stiffness", p.stiffness, Range::positive());
      p.damping = r.number("damping", p.damping, Range::non_negative());
      p.static_friction = r.number("static_friction", p.static_friction, Range::non_negative());
      p.kinetic_friction = r.number("kinetic_friction", p.kinetic_friction, Range::non_negative());
      if (p.kinetic_friction > p.static_friction) r.fail("kinetic_friction", "must not exceed static_friction");
      a.params = p;
      break;
    }
    case pulse: {
      PulseParams p;
      const auto body = r.string("body");
      if (!body) r.fail_missing("body", "the name of the body the pulse comes from");
      p.body = resolve_name(r, "body", *body, model.bodies, "body");
      p.rate = r.number("rate", p.rate, Range::closed(30.0, 200.0));
      p.duty_cycle = r.number("duty_cycle", p.duty_cycle, Range::open(0.0, 1.0));
      p.amplitude = r.number("amplitude", p.amplitude, Range::positive());
      p.sources = r.integer("sources", p.sources, 1, 10000);
      p.range = r.number("range", p.range, Range::positive());
      a.params = p;
      break;
    }
    case needle: {
      NeedleParams p;
      p.lateral_stiffness = r.number("lateral_stiffness", p.lateral_stiffness, Range::non_negative());
      p.layers = read_needle_layers(r, a, model);
      a.bodies.clear();
      for (const NeedleLayer& l : p.layers) a.bodies.push_back(l.body);
      a.params = p;
      break;
    }
  }
  r.finish();
  return a;
}

void check_partner(const Reader& r, const Model& model, std::size_t algorithm) {
  const Algorithm& a = model.algorithms[algorithm];
  const auto* p = std::get_if<FabricProxyParams>(&a.params);
  if (!p || !p->partner) return;
  const Tool& partner = model.tools[*p->partner];
  const Algorithm* other = nullptr;
  for (const Algorithm& b : model.algorithms)
    if (b.tool == *p->partner && std::holds_alternative<FabricProxyParams>(b.params)) other = &b;
  if (!other) r.fail("partner", "tool '" + partner.name + "' has no fabric_proxy algorithm");
  const auto& q = std::get<FabricProxyParams>(other->params);
  if (q.partner != a.tool)
    r.fail("partner", "algorithm '" + other->name + "' of tool '" + partner.name + "' must name tool '" +
                          model.tools[a.tool].name + "' as its partner");
  if (q.side == p->side)
    r.fail("partner", "the two fingers touch opposite sides of the fabric (the thumb the front, the index the back)");
  if (!other->enabled || !a.enabled) r.fail("partner", "both fingers of a pair must be enabled");
  if (other->bodies != a.bodies) r.fail("partner", "both fingers of a pair touch the same fabric bodies");
}

}  // namespace tactus::scene::detail
