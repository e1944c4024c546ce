// The human-readable summary printed by `tactus inspect` and `tactus run`.
#include <cmath>
#include <map>
#include <string>

#include <fmt/format.h>

#include "scene/scene.hpp"

namespace tactus::scene {

namespace {

std::string g(double v) { return fmt::format("{:g}", v); }
std::string vec(const Vec3& v) { return fmt::format("({:g}, {:g}, {:g})", v.x(), v.y(), v.z()); }

bool closed(const mesh::TriMesh& s) {
  std::map<std::pair<mesh::Index, mesh::Index>, int> uses;
  for (const auto& t : s.triangles)
    for (std::size_t i = 0; i < 3; ++i) {
      const mesh::Index a = t[i], b = t[(i + 1) % 3];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  for (const auto& [e, n] : uses)
    if (n != 2) return false;
  return !s.triangles.empty();
}

std::string material_line(const Material& m) {
  std::string s = fmt::format("  {}: {}, E {} Pa, nu {}, density {} kg/m^3", m.name, model_name(m),
                              g(m.young_modulus), g(m.poisson_ratio), g(m.density));
  if (m.law == physics::FemLaw::mooney_rivlin) s += fmt::format(", C10 {} Pa, C01 {} Pa", g(m.c10), g(m.c01));
  if (m.nodal_pressure) s += ", pressure at the nodes";
  const Damping& d = m.damping;
  if (d.rayleigh_alpha > 0 || d.rayleigh_beta > 0)
    s += fmt::format(", Rayleigh alpha {} 1/s beta {} s", g(d.rayleigh_alpha), g(d.rayleigh_beta));
  if (d.nodal > 0) s += fmt::format(", nodal damping {} N*s/m", g(d.nodal));
  const Viscoelasticity& v = m.viscoelastic;
  switch (v.model) {
    case ViscoelasticModel::none: break;
    case ViscoelasticModel::kelvin_voigt: s += fmt::format(", Kelvin-Voigt tau {} s", g(v.tau)); break;
    case ViscoelasticModel::standard_linear_solid:
      s += fmt::format(", standard linear solid tau {} s, E_inf/E_0 {}", g(v.tau), g(v.long_term_fraction));
      break;
    case ViscoelasticModel::prony: s += fmt::format(", Prony series of {} terms", v.prony.size()); break;
  }
  return s + "\n";
}

std::string body_lines(const Model& model, const Body& b) {
  std::string s = fmt::format("  {}: {}", b.name, to_string(b.kind));
  if (b.material) s += ", material " + model.materials[*b.material].name;
  if (b.host) s += ", carried by " + model.bodies[*b.host].name;
  s += "\n    mesh: " + b.mesh_source + "\n";
  if (b.volume)
    s += fmt::format("    tet mesh: {} vertices, {} tets\n", b.volume->vertices.size(), b.volume->tets.size());
  s += fmt::format("    surface: {} vertices, {} triangles", b.surface.vertices.size(), b.surface.triangles.size());
  if (b.quads) s += fmt::format(", {} quads", b.quads->quads.size());
  s += "\n";
  const Aabb box = b.volume ? b.volume->bounds() : b.surface.bounds();
  s += fmt::format("    bounds: {} .. {} m (size {})\n", vec(box.min), vec(box.max), vec(box.size()));
  if (b.volume)
    s += fmt::format("    volume: {} m^3\n", g(b.volume->volume()));
  else if (closed(b.surface))
    s += fmt::format("    volume: {} m^3\n", g(b.surface.signed_volume()));
  if (b.levels) {
    const SurfaceLevels& l = *b.levels;
    s += fmt::format("    impostor levels: {} coarser (x{:g} each), {} Loop; finer above {:g} N, coarser below {:g} N "
                     "after {:g} s{}\n",
                     l.build.coarse_levels, l.build.reduction, l.build.subdivision_levels, l.raise_force, l.lower_force,
                     l.hold_time, l.file.empty() ? "" : ", from " + l.file.string());
  }
  if (b.properties) {
    const SurfacePropertyImages& p = *b.properties;
    s += fmt::format("    property images: {}; strokes painted at load: {}\n",
                     p.file.empty() ? fmt::format("{} pixels along the longest side, stiffness {:g} N/m", p.resolution,
                                                  p.base[property_images::Channel::stiffness])
                                    : "from " + p.file.string(),
                     p.paint.size());
  }
  for (const FixedRegion& f : b.fixed)
    s += fmt::format("    fixed '{}' ({}): {} nodes\n", f.name, f.selector, f.nodes.size());
  for (const NodeLoad& l : b.loads)
    s += fmt::format("    load '{}' ({}): {} nodes, total force ({:g}, {:g}, {:g}) N\n", l.name, l.selector,
                     l.nodes.size(), l.force.x(), l.force.y(), l.force.z());
  for (const PrescribedMotion& p : b.prescribed)
    s += fmt::format("    prescribed '{}' ({}): {} nodes, displacement ({:g}, {:g}, {:g}) m\n", p.name, p.selector,
                     p.nodes.size(), p.displacement.x(), p.displacement.y(), p.displacement.z());
  for (const Probe& p : b.probes)
    s += fmt::format("    probe '{}' at ({:g}, {:g}, {:g}) m\n", p.name, p.position.x(), p.position.y(), p.position.z());
  for (const MappedSurface& m : b.mapped)
    s += fmt::format("    mapped {} surface '{}' ({}): {} vertices, {} triangles\n", to_string(m.role), m.name, m.source,
                     m.mesh.vertices.size(), m.mesh.triangles.size());
  if (b.cspace && b.cspace->online) {
    s += fmt::format("    rendered from a configuration space built on-line during the run ({} solver thread{}), "
                     "not simulated\n",
                     b.cspace->workers, b.cspace->workers == 1 ? "" : "s");
  } else if (b.cspace) {
    s += fmt::format("    rendered from the configuration space {} ({} interpolation), not simulated\n",
                     b.cspace->file.string(), precompute::to_string(b.cspace->interpolation));
  } else if (b.kind != BodyKind::rigid && b.kind != BodyKind::embedded) {
    if (b.cloth) {
      const physics::ClothMaterial& m = b.cloth->model->material();
      s += fmt::format("    fabric: {} ({}){}; {} kg/m², bending along {}, friction against skin μs {} μk {}\n",
                       b.cloth->fabric.empty() ? "the scene's own curves" : "'" + b.cloth->fabric + "'",
                       b.cloth->fabric_source, b.cloth->illustrative ? ", illustrative values (not measured)" : "",
                       g(m.areal_density), b.cloth->model->yarns().empty() ? "the edges" : "the yarns",
                       g(b.cloth->static_friction), g(b.cloth->kinetic_friction));
    }
    s += fmt::format("    stepping: {}, dt {} s, solver {} (tolerance {:g}, at most {} iterations), {} mass",
                     to_string(b.stepping.integrator), g(b.time_step), to_string(b.stepping.solver),
                     b.stepping.cg_tolerance, b.stepping.cg_max_iterations, to_string(b.mass_matrix));
    if (b.stepping.newton_iterations > 1) s += fmt::format(", {} Newton iterations", b.stepping.newton_iterations);
    if (b.stepping.factor_reuse_steps > 1)
      s += fmt::format(", one factorization per {} steps", b.stepping.factor_reuse_steps);
    if (!b.springs.empty()) {
      s += ", springs";
      for (const SpringType t : b.springs) s += std::string(" ") + to_string(t);
    }
    s += "\n";
  }
  return s;
}

std::string finger_text(const FingerProperties& f) {
  return fmt::format("mass {} kg, E {} Pa, nu {}", g(f.mass), g(f.young_modulus), g(f.poisson_ratio));
}

std::string tool_line(const Model& model, const Tool& t) {
  std::string s = fmt::format("  {}: {}", t.name, tool_type_name(t.shape));
  if (const auto* p = std::get_if<SphereTool>(&t.shape))
    s += fmt::format(", radius {} m, {}", g(p->radius), finger_text(p->finger));
  else if (const auto* q = std::get_if<SphereSetTool>(&t.shape))
    s += fmt::format(", {} spheres of radius {} m, {}", q->spheres.size(), g(q->spheres.front().radius),
                     finger_text(q->finger));
  else if (const auto* n = std::get_if<NeedleTool>(&t.shape))
    s += fmt::format(", length {} m, diameter {} m, mass {} kg", g(n->length), g(n->diameter), g(n->mass));
  else if (const auto* f = std::get_if<TwoFingersTool>(&t.shape))
    s += fmt::format(", radius {} m, {} (each)", g(f->radius), finger_text(f->finger));
  s += t.devices.size() == 1 ? "; device " : "; devices ";
  for (std::size_t i = 0; i < t.devices.size(); ++i) s += (i ? ", " : "") + model.devices[t.devices[i]].name;
  return s + "\n";
}

std::string device_line(const Device& d) {
  std::string s = fmt::format("  {}: {}", d.name, device_type_name(d.source));
  if (const auto* sc = std::get_if<ScriptedDevice>(&d.source))
    s += fmt::format(" ({} trajectory)", trajectory_type_name(sc->trajectory));
  else if (const auto* op = std::get_if<SimulatedOperatorDevice>(&d.source))
    s += fmt::format(" ({} target, hand {} kg, {} N/m, {} N*s/m)", trajectory_type_name(op->target),
                     g(op->hand_mass), g(op->hand_stiffness), g(op->hand_damping));
  else if (const auto* rp = std::get_if<ReplayDevice>(&d.source))
    s += " (" + rp->file.generic_string() + ")";
  else if (const auto* nw = std::get_if<NetworkDevice>(&d.source))
    s += fmt::format(" (udp {}:{})", nw->address, nw->port);
  s += fmt::format(", max force {} N, max stiffness {} N/m, max damping {} N*s/m, workspace {} .. {} m",
                   g(d.max_force), g(d.max_stiffness), g(d.max_damping), vec(d.workspace.min), vec(d.workspace.max));
  if (d.scale != 1.0 || d.offset != Vec3::Zero() || !d.rotation.isApprox(Quat::Identity()))
    s += fmt::format(", to scene: scale {}, rotation {} deg, offset {} m", g(d.scale),
                     g(2.0 * std::acos(std::min(1.0, std::abs(d.rotation.w()))) * 180.0 / 3.141592653589793),
                     vec(d.offset));
  return s + "\n";
}

std::string algorithm_line(const Model& model, const Algorithm& a) {
  std::string s = fmt::format("  {}: {}, tool {}", a.name, algorithm_type_name(a.params), model.tools[a.tool].name);
  if (const auto* pulse = std::get_if<PulseParams>(&a.params)) {
    s += fmt::format(", sources along {}: {} beats/min, duty cycle {}, {} N within {} m", model.bodies[pulse->body].name,
                     g(pulse->rate), g(pulse->duty_cycle), g(pulse->amplitude), g(pulse->range));
  } else if (a.bodies.empty()) {
    s += ", every body";
  } else {
    s += ", bodies";
    for (std::size_t b : a.bodies) s += " " + model.bodies[b].name;
  }
  if (!a.enabled) s += ", disabled";
  return s + "\n";
}

}  // namespace

std::string summarize(const Model& m, bool real_time) {
  std::string s = fmt::format("scene '{}' ({})\n", m.name, m.source);
  if (!m.description.empty()) s += "  " + m.description + "\n";
  s += fmt::format("  rates: haptic {} Hz, simulation {} Hz, interaction {} Hz, visual {} Hz\n", g(m.rates.haptic),
                   g(m.rates.simulation), g(m.rates.interaction), g(m.rates.visual));
  if (real_time)
    s += fmt::format("  real time: SCHED_FIFO priority {}, haptic CPU {}, {}\n", m.realtime.priority,
                   m.realtime.haptic_cpu < 0 ? std::string("any") : std::to_string(m.realtime.haptic_cpu),
                   m.realtime.dedicated_core ? std::string("spinning through every period")
                                             : fmt::format("spin {} us before each deadline", g(m.realtime.spin * 1e6)));
  if (real_time && m.rates.catch_up > 1.0)
    s += fmt::format("  a late simulation step spans up to {} periods (catch_up)\n", g(m.rates.catch_up));
  s += fmt::format("  gravity: {} m/s^2\n", vec(m.gravity));
  s += fmt::format("materials: {}\n", m.materials.size());
  for (const auto& x : m.materials) s += material_line(x);
  s += fmt::format("bodies: {}\n", m.bodies.size());
  for (const auto& x : m.bodies) s += body_lines(m, x);
  s += fmt::format("devices: {}\n", m.devices.size());
  for (const auto& x : m.devices) s += device_line(x);
  s += fmt::format("tools: {}\n", m.tools.size());
  for (const auto& x : m.tools) s += tool_line(m, x);
  s += fmt::format("algorithms: {}\n", m.algorithms.size());
  for (const auto& x : m.algorithms) s += algorithm_line(m, x);
  if (m.recording.path.empty()) {
    s += "recording: none\n";
  } else {
    s += "recording: " + m.recording.path + " (";
    std::string items;
    const std::pair<bool, const char*> flags[] = {{m.recording.poses, "poses"},     {m.recording.forces, "forces"},
                                                  {m.recording.contacts, "contacts"}, {m.recording.timings, "timings"},
                                                  {m.recording.events, "events"}};
    for (const auto& [on, name] : flags)
      if (on) items += (items.empty() ? "" : ", ") + std::string(name);
    s += items + ")\n";
  }
  return s;
}

}  // namespace tactus::scene
