#include "compile/device_setup.hpp"

#include "compile/touchables.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <optional>
#include <stdexcept>
#include <variant>

#include "compile/cspace_body.hpp"
#include "compile/touchables.hpp"
#include "contact/proxy.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "haptics/algorithms/fabric_proxy_on_patch.hpp"
#include "haptics/algorithms/field_lookup.hpp"
#include "haptics/algorithms/multi_surface_algorithm.hpp"
#include "haptics/algorithms/needle_algorithm.hpp"
#include "haptics/algorithms/proxy_on_patch.hpp"
#include "haptics/algorithms/proxy_on_plane.hpp"
#include "haptics/algorithms/pulse_overlay.hpp"
#include "haptics/algorithms/spheres_on_objects.hpp"
#include "haptics/algorithms/spheres_on_patch.hpp"
#include "haptics/algorithms/spheres_on_plane.hpp"

namespace tactus::compile {
namespace {

/// The tool a device drives, and which of its fingers when the tool has two.
struct DrivenTool {
  const scene::Tool* tool = nullptr;
  std::size_t finger = 0;
};

DrivenTool tool_of(const scene::Model& m, std::size_t device) {
  for (const scene::Tool& tool : m.tools)
    for (std::size_t k = 0; k < tool.devices.size(); ++k)
      if (tool.devices[k] == device) return {&tool, k};
  return {};
}

/// The tool's contact algorithm: its first enabled one that is not a pulse. A tool may have
/// several algorithms; the pulse composes with the contact (pulse_of).
const scene::Algorithm* algorithm_of(const scene::Model& m, const scene::Tool& tool) {
  for (const scene::Algorithm& a : m.algorithms)
    if (a.enabled && &m.tools[a.tool] == &tool && !std::holds_alternative<scene::PulseParams>(a.params)) return &a;
  return nullptr;
}

/// The tool's first enabled pulse algorithm, if any.
const scene::Algorithm* pulse_of(const scene::Model& m, const scene::Tool& tool) {
  for (const scene::Algorithm& a : m.algorithms)
    if (a.enabled && &m.tools[a.tool] == &tool && std::holds_alternative<scene::PulseParams>(a.params)) return &a;
  return nullptr;
}

/// The pulse of a tool's algorithm `a`: its point sources along the vessel body's rest mesh.
haptics::PulseForce make_pulse(const scene::Model& m, const scene::Algorithm& a) {
  const auto& p = std::get<scene::PulseParams>(a.params);
  const scene::Body& vessel = m.bodies[p.body];
  haptics::PulseConfig c;
  c.rate = p.rate;
  c.duty_cycle = p.duty_cycle;
  c.amplitude = p.amplitude;
  c.range = p.range;
  try {
    c.sources = haptics::pulse_sources_along_axis(vessel.simulation_vertices(), p.sources);
    return haptics::PulseForce(std::move(c));
  } catch (const std::invalid_argument& e) {
    throw InputError(SourceLocation{m.source, {}, {}, {}},
                     fmt::format("algorithm '{}': pulse from body '{}': {}", a.name, vessel.name, e.what()));
  }
}

/// A multiple-surface ray starts this far behind the tool, so it still enters the layers
/// above a proxy the device has pushed deep behind [m].
constexpr double kMultiSurfaceRayBehind = 0.05;

std::vector<std::size_t> bodies_of(const scene::Model& m, const scene::Algorithm& a) {
  if (!a.bodies.empty()) return a.bodies;
  std::vector<std::size_t> all(m.bodies.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  return all;
}

/// The stiffest tissue among the bodies (a body without material counts as rigid).
contact::ElasticMaterial stiffest_tissue(const scene::Model& m, const std::vector<std::size_t>& bodies) {
  contact::ElasticMaterial stiffest{0.0, 0.3};
  for (std::size_t b : bodies) {
    const auto& mat = m.bodies[b].material;
    const contact::ElasticMaterial t = mat ? contact::ElasticMaterial{m.materials[*mat].young_modulus,
                                                                      m.materials[*mat].poisson_ratio}
                                           : contact::ElasticMaterial{1e12, 0.3};
    if (t.youngs_modulus > stiffest.youngs_modulus) stiffest = t;
  }
  return stiffest;
}

/// A needle tool: its insertion algorithm's layers, and the planned path when the device
/// follows a scripted insertion line.
DeviceSetup setup_needle(const scene::Model& m, const scene::Device& d, const scene::Tool& tool,
                         const scene::NeedleTool& shape, DeviceSetup s) {
  const scene::Algorithm* a = algorithm_of(m, tool);
  if (!a) return s;
  const auto* p = std::get_if<scene::NeedleParams>(&a->params);
  if (!p)
    throw InputError(SourceLocation{m.source, {}, {}, {}},
                     fmt::format("algorithm '{}': a needle tool takes the 'needle' algorithm", a->name));
  haptics::NeedleConfig c;
  c.length = shape.length;
  c.lateral_stiffness = std::min(p->lateral_stiffness, d.max_stiffness);
  c.layers = p->layers;
  // Never stiffer than the device renders stably; the threshold is still reached, farther in.
  for (haptics::NeedleLayer& l : c.layers) l.stiffness = std::min(l.stiffness, d.max_stiffness);
  std::optional<Vec3> axis;
  if (const scene::NeedleLinePath* line = needle_line(d)) {
    const Vec3 entry = s.model.map.to_scene(line->entry), target = s.model.map.to_scene(line->target);
    if ((target - entry).norm() > 0.0) {
      c.planned = std::array<Vec3, 2>{entry, target};
      axis = (target - entry).normalized();
    }
  }
  for (const haptics::NeedleLayer& l : c.layers) s.bodies.push_back(l.body);
  try {
    s.model.algorithms.push_back(std::make_shared<haptics::NeedleAlgorithm>(std::move(c), axis));
  } catch (const std::invalid_argument& e) {
    throw InputError(SourceLocation{m.source, {}, {}, {}}, fmt::format("algorithm '{}': {}", a->name, e.what()));
  }
  s.renders = true;
  s.needle_length = shape.length;
  s.reach = shape.length;  // layers are looked for up to a needle's length ahead of the tip
  return s;
}

/// How an algorithm among touchable objects chooses their levels: the scene's [lod], the
/// device's stiffness limit, and whether other bodies come through the contact plane.
haptics::ObjectsSettings objects_settings(const scene::Model& m, const scene::Device& d,
                                          const std::vector<std::size_t>& plane_bodies) {
  haptics::ObjectsSettings os;
  os.budget = m.level_selection.haptic_budget;
  os.influence_radius = m.level_selection.influence_radius;
  os.blend_time = m.level_selection.blend_time;
  os.select = m.level_selection.select;
  os.max_stiffness = d.max_stiffness;
  os.plane = !plane_bodies.empty();
  return os;
}

}  // namespace

haptics::DeviceLimits device_limits(const scene::Device& device) {
  haptics::DeviceLimits limits;
  limits.max_force = device.max_force;
  limits.max_stiffness = device.max_stiffness;
  limits.workspace = device.workspace;
  return limits;
}

haptics::WorkspaceMap workspace_map(const scene::Device& device) {
  haptics::WorkspaceMap map;
  map.scale = device.scale;
  map.offset = device.offset;
  map.rotation = device.rotation;
  return map;
}

const scene::NeedleLinePath* needle_line(const scene::Device& d) {
  const scene::Trajectory* path = nullptr;
  if (const auto* scripted = std::get_if<scene::ScriptedDevice>(&d.source)) path = &scripted->trajectory;
  if (const auto* hand = std::get_if<scene::SimulatedOperatorDevice>(&d.source)) path = &hand->target;
  return path ? std::get_if<scene::NeedleLinePath>(path) : nullptr;
}

/// The longest edge of a surface [m].
double longest_edge(const mesh::TriMesh& surface) {
  double longest = 0.0;
  for (const mesh::Triangle& t : surface.triangles)
    for (std::size_t k = 0; k < 3; ++k)
      longest = std::max(longest, (surface.vertices[static_cast<std::size_t>(t[k])] -
                                   surface.vertices[static_cast<std::size_t>(t[(k + 1) % 3])]).norm());
  return longest;
}

/// Where a tool looks a field up, in its frame: its first sphere's centre.
Vec3 lookup_offset(const scene::Tool& tool) {
  if (const auto* set = std::get_if<scene::SphereSetTool>(&tool.shape); set && !set->spheres.empty())
    return set->spheres.front().center;
  return Vec3::Zero();
}

/// A tool on a two-point space: which of its points it is (the body's `tools`), and its
/// partner, the other point's tool, whose frames its loop reads (HapticModel::partner).
haptics::FieldPoint field_point_of(const scene::Model& m, const CspaceBody& cspace, const scene::Tool& tool,
                                   const std::string& algorithm, haptics::HapticModel& model) {
  const std::array<std::size_t, 2>& tools = cspace.pair_tools();
  const scene::Body& body = m.bodies[cspace.body()];
  int finger = -1;
  for (int k = 0; k < 2; ++k)
    if (&m.tools[tools[static_cast<std::size_t>(k)]] == &tool) finger = k;
  if (finger < 0)
    throw InputError(SourceLocation{m.source, {}, {}, {}},
                     fmt::format("algorithm '{}': tool '{}' touches body '{}', whose two-point space is felt by "
                                 "tools '{}' and '{}' only",
                                 algorithm, tool.name, body.name, m.tools[tools[0]].name, m.tools[tools[1]].name));
  const scene::Tool& partner = m.tools[tools[static_cast<std::size_t>(1 - finger)]];
  model.partner = static_cast<std::uint16_t>(partner.devices.front());
  return {finger, lookup_offset(partner)};
}

DeviceSetup setup_device(const scene::Model& m, std::size_t index, const CspaceBodies& cspaces,
                         const Touchables* touchables) {
  const scene::Device& d = m.devices[index];
  DeviceSetup s;
  haptics::HapticModel& model = s.model;
  model.device = static_cast<std::uint16_t>(index);
  model.rate = m.rates.haptic;
  model.map = workspace_map(d);
  model.safety.max_force = d.max_force;
  // The watchdog must not trip on a healthy simulation: allow a few of its periods.
  model.safety.watchdog_timeout = std::max(0.1, 3.0 / m.rates.simulation + 3.0 / m.rates.interaction);

  const DrivenTool driven = tool_of(m, index);
  if (!driven.tool) return s;  // a device with no tool is read and recorded, and feels nothing
  const scene::Tool& tool = *driven.tool;
  const scene::FingerProperties* finger = nullptr;
  std::vector<haptics::ToolSphere> spheres;
  if (const auto* one = std::get_if<scene::SphereTool>(&tool.shape)) {
    spheres.push_back({Vec3::Zero(), one->radius});
    finger = &one->finger;
  } else if (const auto* set = std::get_if<scene::SphereSetTool>(&tool.shape)) {
    for (const auto& sp : set->spheres) spheres.push_back({sp.center, sp.radius});
    finger = &set->finger;
  } else if (const auto* two = std::get_if<scene::TwoFingersTool>(&tool.shape)) {
    spheres.push_back({Vec3::Zero(), two->radius});
    finger = &two->finger;
  } else if (const auto* needle = std::get_if<scene::NeedleTool>(&tool.shape)) {
    return setup_needle(m, d, tool, *needle, std::move(s));
  } else {
    throw InputError(SourceLocation{m.source, {}, {}, {}},
                     fmt::format("tool '{}': a {} tool cannot be rendered by this version yet", tool.name,
                                 scene::tool_type_name(tool.shape)));
  }

  const scene::Algorithm* a = algorithm_of(m, tool);
  const scene::Algorithm* pulse = pulse_of(m, tool);
  if (!a) {
    if (pulse)
      throw InputError(SourceLocation{m.source, {}, {}, {}},
                       fmt::format("algorithm '{}': a pulse is felt by pressing, and tool '{}' has no enabled "
                                   "contact algorithm to press with",
                                   pulse->name, tool.name));
    return s;
  }
  s.renders = true;
  s.bodies = bodies_of(m, *a);
  std::shared_ptr<const CspaceBody> cspace;
  for (std::size_t b : s.bodies)
    if (m.bodies[b].cspace && !cspace) cspace = cspace_body(m, b, cspaces);
  const haptics::ToolSphere& first = spheres.front();

  // The force law of the tool's spheres, or the algorithm's own.
  std::optional<contact::ProxyParams> proxy;
  std::optional<haptics::ContactLaw> law;
  std::optional<haptics::MultiSurfaceConfig> multi;
  std::optional<contact::FabricProxyParams> fabric;
  std::optional<haptics::TwoFingerParams> two_fingers;
  std::optional<contact::HertzParameters> hertz;  ///< a Hertz finger's, for each touchable object's own material
  if (const auto* fabric_params = std::get_if<scene::FabricProxyParams>(&a->params)) {
    // A sphere fingertip is a capsule of zero length; friction against the fabric it touches.
    contact::FabricProxyParams p;
    p.finger.base = p.finger.tip = first.offset;
    p.finger.radius = first.radius;
    const scene::FabricProxyParams& fpp = *fabric_params;
    p.stiffness = std::min(fpp.stiffness, d.max_stiffness);  // never stiffer than the device renders stably
    const scene::Cloth& cloth = *m.bodies[s.bodies.front()].cloth;
    p.static_friction = fpp.static_friction.value_or(cloth.static_friction);
    p.kinetic_friction = fpp.kinetic_friction.value_or(cloth.kinetic_friction);
    p.side = fpp.side;
    p.mass = fpp.mass;
    p.damping = fpp.damping;
    fabric = p;
    if (fpp.partner) {
      // The partner's fingertip, a sphere like this one (the scene checks the pair).
      const scene::Tool& other = m.tools[*fpp.partner];
      const auto* other_sphere = std::get_if<scene::SphereTool>(&other.shape);
      if (!other_sphere)
        throw InputError(SourceLocation{m.source, {}, {}, {}},
                         fmt::format("algorithm '{}': partner tool '{}' must be a sphere fingertip", a->name, other.name));
      const scene::Algorithm* other_algorithm = algorithm_of(m, other);
      const auto& other_params = std::get<scene::FabricProxyParams>(other_algorithm->params);
      haptics::TwoFingerParams two;
      two.own = p.finger;
      two.own.pad_normal = fpp.pad_normal;
      two.partner.base = two.partner.tip = Vec3::Zero();
      two.partner.radius = other_sphere->radius;
      two.partner.pad_normal = other_params.pad_normal;
      two.finger_contact.static_friction = fpp.finger_static_friction;
      two.finger_contact.kinetic_friction = fpp.finger_kinetic_friction;
      two.fabric_thickness = fpp.fabric_thickness;
      two_fingers = two;
      model.partner = static_cast<std::uint16_t>(other.devices.front());
    }
  } else if (const auto* p = std::get_if<scene::ProxyParams>(&a->params)) {
    contact::ProxyParams pp;
    pp.radius = first.radius;
    pp.stiffness = std::min(p->stiffness, d.max_stiffness);  // never stiffer than the device renders stably
    pp.damping = p->damping;
    pp.static_friction = p->static_friction;
    pp.kinetic_friction = p->kinetic_friction;
    contact::validate_proxy_params(pp);
    proxy = pp;
    // No blending between local models: blending over one interaction period (8 ms) adds
    // that much lag to a stiff coupling, and the stiff-tissue stability test measured the
    // contact then doing net work on the hand (23% of the stored energy against −1% without).
  } else if (const auto* hz = std::get_if<scene::HertzFingerParams>(&a->params)) {
    // Hertz per sphere with the tissue's local mean curvature (seed 000 §3.1–3.2), against
    // the stiffest tissue the algorithm may touch.
    contact::HertzParameters hp;
    hp.finger_radius = first.radius;
    hp.finger = {finger->young_modulus, finger->poisson_ratio};
    hp.tissue = stiffest_tissue(m, s.bodies);
    law = haptics::ContactLaw::hertz(hp);
    hertz = hp;
    s.curvature_rings = hz->curvature_rings;
  } else if (const auto* pad = std::get_if<scene::FingerpadParams>(&a->params)) {
    contact::FingerpadParameters fp;
    fp.b = pad->b;
    fp.m = pad->m;
    law = haptics::ContactLaw::fingerpad(fp);
  } else if (const auto* ms = std::get_if<scene::MultiSurfaceParams>(&a->params)) {
    if (s.bodies.size() > haptics::kMaxSurfaceLayers)
      throw InputError(SourceLocation{m.source, {}, {}, {}},
                       fmt::format("algorithm '{}': multi_surface renders at most {} layers; name them under 'bodies'",
                                   a->name, haptics::kMaxSurfaceLayers));
    haptics::MultiSurfaceConfig c;
    c.stiffness = std::min(ms->stiffness, d.max_stiffness);  // never stiffer than the device renders stably
    c.damping = ms->damping;
    c.static_friction = ms->static_friction;
    c.kinetic_friction = ms->kinetic_friction;
    c.layers = s.bodies.size();
    c.radius = first.radius;
    // Seed 003 §3.5: interpolate linearly between the planes of successive ray queries.
    c.blend_time = 1.0 / m.rates.interaction;
    // Twice the depth of the device's force limit: deeper, the plane is not the pressed surface.
    c.max_depth = 2.0 * d.max_force / c.stiffness;
    multi = c;
    // The interaction loop casts the ray from this far behind the tool (its needle crossings).
    s.needle_length = kMultiSurfaceRayBehind;
  } else {
    throw InputError(SourceLocation{m.source, {}, {}, {}},
                     fmt::format("algorithm '{}': type '{}' cannot be rendered by this version yet", a->name,
                                 scene::algorithm_type_name(a->params)));
  }
  double extent = 0.0;
  for (const auto& sp : spheres) extent = std::max(extent, sp.offset.norm() + sp.radius);
  s.reach = 2.0 * extent + 0.01;

  // A proxy or a finger of contact-law spheres among touchable rigid objects (impostor levels,
  // property images) queries them at the haptic rate itself; the other bodies it touches come
  // through the contact plane.
  std::vector<haptics::TouchableObject> objects;
  if (proxy || (law && !multi)) {
    std::optional<Touchables> own;
    if (!touchables)
      for (std::size_t b : s.bodies)
        if (is_touchable(m.bodies[b]) && !own) touchables = &own.emplace(load_touchables(m));
    std::vector<std::size_t> rest;
    for (std::size_t b : s.bodies) {
      if (touchables && touchables->objects[b])
        objects.push_back(*touchables->objects[b]);
      else
        rest.push_back(b);
    }
    if (!objects.empty()) s.bodies = std::move(rest);
  }

  s.local_model = a->local_model;
  // Multiple surfaces hold the proxy on their own planes: no local patch under them. Among
  // touchable objects the other bodies come through the plane too.
  if (multi || !objects.empty()) s.local_model = contact::LocalModelKind::plane;
  if (a->local_model == contact::LocalModelKind::mass_spring && !multi)
    for (std::size_t b : s.bodies)
      if (m.bodies[b].kind != scene::BodyKind::rigid && m.bodies[b].kind != scene::BodyKind::embedded &&
          m.bodies[b].kind != scene::BodyKind::cloth && !m.bodies[b].material)
        throw InputError(SourceLocation{m.source, {}, {}, {}},
                         fmt::format("algorithm '{}': local_model = \"mass_spring\" fits its springs to the body's "
                                     "material, and body '{}' has none",
                                     a->name, m.bodies[b].name));
  // The patch covers the tool and where it can move until the next simulation step (seed 002
  // §IV: the cursor's position and its finite velocity bound the contact region).
  s.patch_radius = extent + a->max_tool_speed / m.rates.simulation;
  // A two-finger grasp holds the fabric at the pads' centre, on this fingertip's surface: the
  // patch keeps whole every triangle with a corner in its sphere, and a point of a triangle
  // lies within (its longest edge)/√3 of one of its corners (the circumradius bounds it).
  if (two_fingers) s.patch_radius += longest_edge(m.bodies[s.bodies.front()].surface) / std::sqrt(3.0);
  // Sized to the surface: a patch cut short of its radius leaves the tool at the patch's open
  // rim between steps, where the proxy slips off the edge and the force jumps.
  if (s.local_model != contact::LocalModelKind::plane)
    for (std::size_t b : s.bodies) {
      const auto& surface = m.bodies[b].surface;
      const contact::PatchSizing sizing = contact::size_patch(surface.vertices, surface.triangles, s.patch_radius);
      contact::PatchCapacity& c = s.patch_capacity;
      c.free_nodes = std::max(c.free_nodes, sizing.capacity.free_nodes);
      c.nodes = std::max(c.nodes, sizing.capacity.nodes);
      c.triangles = std::max(c.triangles, sizing.capacity.triangles);
      if (sizing.capped)
        log::warn("algorithm '{}': a local patch of {:.1f} mm on body '{}' would hold {} free nodes; it keeps the "
                  "nearest {}, and the tool may reach its rim between simulation steps (a coarser surface or a "
                  "higher simulation rate avoids it)",
                  a->name, 1e3 * s.patch_radius, m.bodies[b].name, sizing.needed_free_nodes, c.free_nodes);
    }
  model.force_smoothing = a->force_smoothing;
  model.passivity_control = a->passivity_control;
  model.max_damping = d.max_damping;
  model.spread_over_contact_disc = a->load_spread == scene::LoadSpread::contact_disc;

  // The contact algorithm: the layers' planes, a precomputed space, or the finger's law on the
  // contact plane or on a local patch; then the pulse over it.
  const bool on_patch = s.local_model != contact::LocalModelKind::plane;
  const bool spread = model.spread_over_contact_disc;
  try {
    if (multi) {
      model.algorithms.push_back(std::make_shared<haptics::MultiSurfaceAlgorithm>(*multi, s.bodies, first.offset));
    } else if (cspace && cspace->pair()) {
      const haptics::FieldPoint point = field_point_of(m, *cspace, tool, a->name, model);
      model.algorithms.push_back(std::make_shared<haptics::FieldLookup>(cspace, first.offset, point));
    } else if (cspace) {
      model.algorithms.push_back(std::make_shared<haptics::FieldLookup>(cspace, first.offset));
    } else if (fabric) {
      model.algorithms.push_back(
          std::make_shared<haptics::FabricProxyOnPatch>(*fabric, s.local_model, s.patch_capacity, spread, two_fingers));
    } else if (proxy && !objects.empty()) {
      model.algorithms.push_back(
          std::make_shared<haptics::ProxyOnObjects>(first, *proxy, std::move(objects), objects_settings(m, d, s.bodies)));
    } else if (law && !objects.empty()) {
      // Each object with its own law: Hertz against its material (a body without one is rigid),
      // then the plane's bodies with the algorithm's law against the stiffest of them.
      std::vector<haptics::ContactLaw> laws;
      for (const auto& o : objects) {
        if (!hertz) {
          laws.push_back(*law);
          continue;
        }
        contact::HertzParameters own = *hertz;
        own.tissue = stiffest_tissue(m, {static_cast<std::size_t>(o.body)});
        laws.push_back(haptics::ContactLaw::hertz(own));
      }
      if (hertz) {
        contact::HertzParameters plane = *hertz;
        plane.tissue = stiffest_tissue(m, s.bodies);
        laws.push_back(haptics::ContactLaw::hertz(plane));
      } else {
        laws.push_back(*law);
      }
      model.algorithms.push_back(std::make_shared<haptics::SpheresOnObjects>(spheres, std::move(laws), 0.0,
                                                                             std::move(objects),
                                                                             objects_settings(m, d, s.bodies)));
    } else if (proxy && on_patch) {
      model.algorithms.push_back(
          std::make_shared<haptics::ProxyOnPatch>(first, *proxy, s.local_model, s.patch_capacity, spread));
    } else if (proxy) {
      model.algorithms.push_back(std::make_shared<haptics::ProxyOnPlane>(first, *proxy));
    } else if (on_patch) {
      model.algorithms.push_back(
          std::make_shared<haptics::SpheresOnPatch>(spheres, *law, 0.0, s.local_model, s.patch_capacity, spread));
    } else {
      model.algorithms.push_back(std::make_shared<haptics::SpheresOnPlane>(spheres, *law));
    }
  } catch (const std::invalid_argument& e) {
    throw InputError(SourceLocation{m.source, {}, {}, {}}, fmt::format("algorithm '{}': {}", a->name, e.what()));
  } catch (const InputError& e) {
    throw InputError(SourceLocation{m.source, {}, {}, {}}, fmt::format("algorithm '{}': {}", a->name, e.what()));
  }
  if (pulse) model.algorithms.push_back(std::make_shared<haptics::PulseOverlay>(make_pulse(m, *pulse), first.offset));
  return s;
}

}  // namespace tactus::compile
