// `tactus curves`: seed 000's Fig. 3 and Fig. 5 from scripted presses (app/curves.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "app/curves.hpp"
#include "contact/hertz.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "mesh/curvature.hpp"
#include "mesh/generators.hpp"
#include "mesh/half_edge.hpp"
#include "runtime/session.hpp"
#include "offline/solve.hpp"
#include "scene/scene.hpp"

namespace tactus::app::curves {
namespace {

namespace fs = std::filesystem;

/// What presses one tissue: its body, algorithm, tool, device and press path.
struct Press {
  std::size_t body = 0, algorithm = 0, tool = 0, device = 0;
  haptics::PressPath path;
  const scene::SphereTool* finger = nullptr;
  int curvature_rings = 2;
};

std::optional<Press> press_of(const scene::Model& m, std::size_t algorithm) {
  const scene::Algorithm& a = m.algorithms[algorithm];
  const auto* hertz = std::get_if<scene::HertzFingerParams>(&a.params);
  if (!hertz || a.bodies.size() != 1) return std::nullopt;
  const scene::Tool& tool = m.tools[a.tool];
  const auto* finger = std::get_if<scene::SphereTool>(&tool.shape);
  if (!finger || tool.devices.size() != 1) return std::nullopt;
  const auto* scripted = std::get_if<scene::ScriptedDevice>(&m.devices[tool.devices[0]].source);
  if (!scripted) return std::nullopt;
  const auto* path = std::get_if<haptics::PressPath>(&scripted->trajectory);
  if (!path || m.bodies[a.bodies[0]].kind == scene::BodyKind::rigid) return std::nullopt;
  return Press{a.bodies[0], algorithm, a.tool, tool.devices[0], *path, finger, hertz->curvature_rings};
}

Press find_press(const scene::Model& m, const std::string& tissue) {
  for (std::size_t a = 0; a < m.algorithms.size(); ++a)
    if (auto p = press_of(m, a); p && m.bodies[p->body].name == tissue) return *p;
  throw InputError(SourceLocation{m.source, {}, {}, {}},
                   fmt::format("no tissue '{}' to press: curves need a deformable body touched alone by a "
                               "hertz_finger algorithm whose sphere tool's scripted device follows a press trajectory",
                               tissue));
}

/// Where a ray first meets a surface: the point, its triangle and barycentric weights.
struct RayHit {
  Vec3 point = Vec3::Zero();
  mesh::Index triangle = -1;
  Vec3 barycentric = Vec3::Zero();
};

std::optional<RayHit> cast_ray(const mesh::TriMesh& s, const Vec3& origin, const Vec3& direction) {
  std::optional<RayHit> best;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {  // Möller–Trumbore
    const Vec3& a = s.vertices[static_cast<std::size_t>(s.triangles[t][0])];
    const Vec3 e1 = s.vertices[static_cast<std::size_t>(s.triangles[t][1])] - a;
    const Vec3 e2 = s.vertices[static_cast<std::size_t>(s.triangles[t][2])] - a;
    const Vec3 p = direction.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-18) continue;
    const Vec3 o = origin - a;
    const double u = o.dot(p) / det;
    const Vec3 q = o.cross(e1);
    const double v = direction.dot(q) / det;
    const double distance = e2.dot(q) / det;
    if (u < -1e-9 || v < -1e-9 || u + v > 1.0 + 1e-9 || distance < 0.0 || distance >= nearest) continue;
    nearest = distance;
    best = RayHit{origin + distance * direction, static_cast<mesh::Index>(t), Vec3(1.0 - u - v, u, v)};
  }
  return best;
}

/// The rest surface point the press line meets, or an error naming the device.
RayHit press_target(const scene::Model& m, const Press& p, const mesh::TriMesh& surface) {
  const auto hit = cast_ray(surface, p.path.position, p.path.direction);
  if (!hit)
    throw InputError(SourceLocation{m.source, {}, {}, {}},
                     fmt::format("device '{}': its press line misses body '{}'", m.devices[p.device].name,
                                 m.bodies[p.body].name));
  return *hit;
}

double estimated_curvature(const mesh::TriMesh& surface, const RayHit& hit, int rings) {
  const mesh::HalfEdgeMesh topology(surface);
  const mesh::CurvatureEstimator estimator(topology, rings);
  const mesh::VertexCurvature c = estimator.estimate_at_point(surface.vertices, hit.triangle, hit.barycentric);
  return c.valid ? c.kmean : 0.0;
}

contact::HertzContact hertz_of(const scene::Model& m, const scene::SphereTool& finger, std::size_t material) {
  const scene::Material& tissue = m.materials[material];
  return contact::HertzContact({finger.radius,
                                {finger.finger.young_modulus, finger.finger.poisson_ratio},
                                {tissue.young_modulus, tissue.poisson_ratio}});
}

/// A copy of `base` with only the given body, device, tool and algorithm, no gravity (the
/// curves start from the rest shape) and no recording.
scene::Model single_press_model(const scene::Model& base, const Press& p, scene::Body body) {
  scene::Model m;
  m.name = base.name + "-" + body.name;
  m.source = base.source;
  m.gravity = Vec3::Zero();
  m.rates = base.rates;
  m.materials = base.materials;
  m.bodies.push_back(std::move(body));
  m.devices.push_back(base.devices[p.device]);
  scene::Tool tool = base.tools[p.tool];
  tool.devices = {0};
  m.tools.push_back(std::move(tool));
  scene::Algorithm a = base.algorithms[p.algorithm];
  a.tool = 0;
  a.bodies = {0};
  m.algorithms.push_back(std::move(a));
  m.recording.path.clear();
  return m;
}

/// Lockstep run of a one-press model to the end of the hold (before the finger withdraws),
/// with a progress bar labelled `phase`.
std::vector<runtime::HapticFrame> run_press(const scene::Model& m, const haptics::PressPath& path,
                                            const std::string& phase) {
  runtime::SessionOptions o;
  o.scheduling = runtime::Scheduling::lockstep;
  o.keep_frames = true;
  o.progress = phase;
  o.duration = path.depth / path.speed + path.hold;
  o.max_duration = o.duration + 1.0;
  return runtime::run_session(m, o).frames;
}

struct ScenePose {
  Vec3 position;
  Vec3 force;
};

/// A frame's finger centre and force in scene coordinates (docs/scene-format.md: devices).
ScenePose scene_pose(const scene::Device& d, const runtime::HapticFrame& f) {
  return {d.offset + d.scale * (d.rotation * f.position), d.rotation * f.force};
}

}  // namespace

std::vector<std::string> pressed_tissues(const scene::Model& model) {
  std::vector<std::string> names;
  for (std::size_t a = 0; a < model.algorithms.size(); ++a)
    if (auto p = press_of(model, a)) names.push_back(model.bodies[p->body].name);
  return names;
}

std::vector<TissueIndentation> force_vs_indentation(const scene::Model& model, const std::vector<std::string>& tissues) {
  std::vector<TissueIndentation> out;
  for (const std::string& name : tissues) {
    const Press p = find_press(model, name);
    const scene::Body& body = model.bodies[p.body];
    if (!body.material) throw InputError(fmt::format("body '{}' has no material for Hertz's law", name));
    const RayHit rest = press_target(model, p, body.surface);
    const Vec3 u = p.path.direction.normalized();
    const double radius = p.finger->radius;

    TissueIndentation t;
    t.tissue = name;
    t.nodes = body.simulation_vertices().size();
    t.tets = body.volume ? body.volume->tets.size() : 0;
    const contact::HertzContact hertz = hertz_of(model, *p.finger, *body.material);
    t.effective_modulus = hertz.effective_modulus();
    t.rest_curvature = estimated_curvature(body.surface, rest, p.curvature_rings);
    t.effective_radius = 1.0 / (1.0 / radius + t.rest_curvature);

    log::info("curves: pressing {} ({} nodes, {} tets)", name, t.nodes, t.tets);
    const scene::Model m = single_press_model(model, p, body);
    const double stroke = p.path.depth / p.path.speed;
    for (const runtime::HapticFrame& f : run_press(m, p.path, "indentation of " + name)) {
      if (f.contact == 0 || f.t > stroke || f.frame % 10 != 0) continue;
      const ScenePose pose = scene_pose(m.devices[0], f);
      IndentationSample s;
      s.time = f.t;
      s.indentation = radius - (rest.point - pose.position).dot(u);
      s.penetration = radius - (f.proxy - pose.position).dot(u);
      s.force = -pose.force.dot(u);
      s.hertz_at_indentation = hertz.evaluate(s.indentation, t.rest_curvature).force;
      s.hertz_at_penetration = hertz.evaluate(s.penetration, t.rest_curvature).force;
      t.samples.push_back(s);
    }
    out.push_back(std::move(t));
  }
  return out;
}

std::vector<CurvatureSample> force_vs_curvature(const scene::Model& model, const std::string& tissue, double depth) {
  if (!(depth > 0.0)) throw InputError(fmt::format("curvature depth must be positive, got {}", depth));
  const Press p = find_press(model, tissue);
  const scene::Body& base_body = model.bodies[p.body];
  if (!base_body.material) throw InputError(fmt::format("body '{}' has no material for Hertz's law", tissue));
  const double finger = p.finger->radius;
  const contact::HertzContact hertz = hertz_of(model, *p.finger, *base_body.material);

  // Each surface has its pressed point at the origin with outward normal +z. Cylinders lie
  // along y and are pressed at the centre of a face, midway between two rings (odd count).
  struct Shape {
    std::string kind;
    double radius;
  };
  std::vector<Shape> shapes{{"plane", 0.0}};
  for (double r : {0.04, 0.02, 0.012, 0.008}) shapes.push_back({"sphere", r});
  for (double r : {0.04, 0.02, 0.012, 0.008}) shapes.push_back({"cylinder", r});

  std::vector<CurvatureSample> out;
  for (const Shape& shape : shapes) {
    mesh::TriMesh surface;
    double exact = 0.0;
    if (shape.kind == "plane") {
      surface = mesh::box_surface(Vec3(0.1, 0.1, 0.02), 10);
      for (Vec3& v : surface.vertices) v.z() -= 0.01;
    } else if (shape.kind == "sphere") {
      surface = mesh::sphere(shape.radius, 4);
      for (Vec3& v : surface.vertices) v.z() -= shape.radius;
      exact = 1.0 / shape.radius;
    } else {
      constexpr int segments = 64;
      const double height = std::max(0.06, 8.0 * shape.radius);
      const double ring_spacing = 2.0 * std::numbers::pi * shape.radius / segments;
      const int rings = 2 * static_cast<int>(std::ceil(height / ring_spacing / 2.0)) + 1;
      surface = mesh::cylinder(shape.radius, height, segments, rings);
      // Turn the face centre (π/segments round from vertex 0) to +z and the axis to −y.
      const Eigen::AngleAxisd spin(std::numbers::pi / 2.0 - std::numbers::pi / segments, Vec3::UnitZ());
      const Eigen::AngleAxisd lay(std::numbers::pi / 2.0, Vec3::UnitX());
      const double face = shape.radius * std::cos(std::numbers::pi / segments);
      for (Vec3& v : surface.vertices) v = lay * (spin * v) + Vec3(0.0, height / 2.0, -face);
      exact = 1.0 / (2.0 * shape.radius);
    }
    scene::Body body;
    body.name = shape.kind + fmt::format("_{:.0f}mm", shape.radius * 1e3);
    body.kind = scene::BodyKind::rigid;
    body.material = base_body.material;
    body.mesh_source = shape.kind;
    body.surface = std::move(surface);

    Press press = p;
    press.path.position = Vec3(0.0, 0.0, finger + 0.002);
    press.path.direction = Vec3(0.0, 0.0, -1.0);
    press.path.depth = 0.002 + depth;
    press.path.speed = 0.005;
    press.path.hold = 0.2;
    scene::Model m = single_press_model(model, press, body);
    auto& device = m.devices[0];
    device.offset = Vec3::Zero();
    device.scale = 1.0;
    device.rotation = Quat::Identity();
    std::get<scene::ScriptedDevice>(device.source).trajectory = press.path;

    CurvatureSample s;
    s.surface = shape.kind;
    s.radius = shape.radius;
    s.exact_curvature = exact;
    const RayHit hit = press_target(m, press, m.bodies[0].surface);
    s.estimated_curvature = estimated_curvature(m.bodies[0].surface, hit, p.curvature_rings);
    s.depth = depth;
    s.hertz_force = hertz.evaluate(depth, exact).force;
    const double hold_start = press.path.depth / press.path.speed;
    double sum = 0.0;
    int count = 0;
    for (const runtime::HapticFrame& f : run_press(m, press.path, "curvature: pressing the " + m.bodies[0].name))
      if (f.t >= hold_start + 0.05) {  // past the stroke and the first interaction updates
        sum += f.force.z();
        ++count;
      }
    s.force = count > 0 ? sum / count : 0.0;
    out.push_back(s);
  }
  return out;
}

std::vector<TissueViscoelastic> creep_and_relaxation(const scene::Model& model, const std::vector<std::string>& tissues) {
  std::vector<TissueViscoelastic> out;
  for (const std::string& name : tissues) {
    const Press p = find_press(model, name);
    const scene::Body& body = model.bodies[p.body];
    if (!body.material || !body.volume) throw InputError(fmt::format("body '{}' is not a volumetric tissue", name));
    const scene::Material& material = model.materials[*body.material];
    const RayHit rest = press_target(model, p, body.surface);
    const Vec3 u = p.path.direction.normalized();

    TissueViscoelastic t;
    t.tissue = name;
    t.time_step = body.time_step;
    // The closed forms, in the scene's terms (docs/scene-format.md: viscoelastic).
    double tau = 1.0, g = 0.0;
    switch (material.viscoelastic.model) {
      case scene::ViscoelasticModel::none: t.model = "elastic"; break;
      case scene::ViscoelasticModel::kelvin_voigt: t.model = "kelvin_voigt"; tau = material.viscoelastic.tau; break;
      case scene::ViscoelasticModel::standard_linear_solid:
        t.model = "standard_linear_solid";
        tau = material.viscoelastic.tau;
        g = (1.0 - material.viscoelastic.long_term_fraction) / material.viscoelastic.long_term_fraction;
        break;
      case scene::ViscoelasticModel::prony: t.model = "prony"; break;
    }
    t.relaxation_time = t.model == "elastic" || t.model == "prony" ? 0.0 : tau;
    t.arm_ratio = g;
    const double creep_time = t.model == "standard_linear_solid" ? tau * (1.0 + g) : tau;

    // The finger's footprint: the free surface nodes within its radius of the pressed point,
    // and at least the five nearest (on a coarse mesh the finger's radius holds one node, and
    // a load on one node strains its springs far past small strain).
    std::vector<mesh::Index> fixed;
    for (const auto& f : body.fixed) fixed.insert(fixed.end(), f.nodes.begin(), f.nodes.end());
    std::sort(fixed.begin(), fixed.end());
    std::vector<std::pair<double, mesh::Index>> by_distance;
    for (mesh::Index n : body.surface_to_volume)
      if (!std::binary_search(fixed.begin(), fixed.end(), n))
        by_distance.emplace_back((body.volume->vertices[static_cast<std::size_t>(n)] - rest.point).norm(), n);
    std::sort(by_distance.begin(), by_distance.end());
    by_distance.erase(std::unique(by_distance.begin(), by_distance.end()), by_distance.end());
    if (by_distance.empty()) throw InputError(fmt::format("body '{}': no free surface node under the finger", name));
    const double footprint =
        std::max(p.finger->radius, 1.2 * by_distance[std::min<std::size_t>(4, by_distance.size() - 1)].first);
    std::vector<mesh::Index> patch;
    for (const auto& [d, n] : by_distance)
      if (d <= footprint) patch.push_back(n);
    std::sort(patch.begin(), patch.end());

    scene::Model m = single_press_model(model, p, body);
    m.devices.clear();
    m.tools.clear();
    m.algorithms.clear();
    scene::Body& relaxed = m.bodies[0];

    // How far to hold the footprint: 5 % of its radius (small strain), less where that would
    // take more than 1 N (bone): the instantaneous stiffness from a static 1 µm push.
    constexpr double kProbe = 1e-6, kTargetForce = 1.0;
    relaxed.prescribed.push_back({"finger", "finger footprint", patch, kProbe * u, 0.0});
    offline::SolveOptions probe;
    probe.static_solve = true;
    probe.progress = "stiffness of " + name;
    const double probe_force = offline::solve(m, probe).bodies.at(0).rows.back().reactions.back().dot(u);
    t.held_displacement = 0.05 * footprint;
    if (probe_force > 0.0) t.held_displacement = std::min(t.held_displacement, kTargetForce * kProbe / probe_force);

    // Relaxation: the footprint held in (a step at t = 0) for six relaxation times.
    offline::SolveOptions so;
    so.until = t.model == "elastic" || t.model == "prony" ? 1.0 : 6.0 * tau;
    so.report_every = so.until / 200.0;
    relaxed.prescribed.back().displacement = t.held_displacement * u;
    so.progress = fmt::format("relaxation of {} for {:.0f} s", name, so.until);
    log::info("curves: {}", so.progress);
    const offline::BodySolve r = offline::solve(m, so).bodies.at(0);
    for (const offline::SolveRow& row : r.rows) t.relaxation.push_back({row.time, row.reactions.back().dot(u), 0.0});

    // Creep: the long-term reaction of the relaxation, as a constant load on the footprint.
    t.load = t.relaxation.back().value;
    relaxed.prescribed.clear();
    relaxed.loads.push_back({"finger", "finger footprint", patch, t.load * u, 0.0});
    relaxed.probes.push_back({"finger", rest.point + 1e-4 * u});
    so.until = t.model == "elastic" || t.model == "prony" ? 1.0 : 6.0 * creep_time;  // six retardation times
    so.report_every = so.until / 200.0;
    so.progress = fmt::format("creep of {} for {:.0f} s", name, so.until);
    log::info("curves: {}", so.progress);
    const offline::BodySolve c = offline::solve(m, so).bodies.at(0);
    for (const offline::SolveRow& row : c.rows) t.creep.push_back({row.time, row.probe_displacements.at(0).dot(u), 0.0});

    // The closed forms with the run's last value as their scale: the spring network's
    // stiffness depends on the mesh (docs/validation-mass-spring.md), the time course only
    // on the material.
    const double nan = std::numeric_limits<double>::quiet_NaN();
    auto relaxation_shape = [&](double time) -> double {
      if (t.model == "standard_linear_solid") return 1.0 + g * std::exp(-time / tau);
      if (t.model == "prony") return nan;
      return 1.0;  // elastic, and Kelvin–Voigt's spring after the dashpot's impulse
    };
    auto creep_shape = [&](double time) -> double {
      if (t.model == "standard_linear_solid") return 1.0 - g / (1.0 + g) * std::exp(-time / creep_time);
      if (t.model == "kelvin_voigt") return 1.0 - std::exp(-time / tau);
      if (t.model == "prony") return nan;
      return 1.0;
    };
    const double relaxation_scale = t.relaxation.back().value / relaxation_shape(t.relaxation.back().time);
    const double creep_scale = t.creep.back().value / creep_shape(t.creep.back().time);
    for (auto& s : t.relaxation) s.analytic = s.time > 0.0 ? relaxation_scale * relaxation_shape(s.time) : nan;
    for (auto& s : t.creep) s.analytic = s.time > 0.0 ? creep_scale * creep_shape(s.time) : nan;
    out.push_back(std::move(t));
  }
  return out;
}

std::vector<fs::path> write_csv(const fs::path& dir, const std::vector<TissueIndentation>& a,
                                const std::vector<CurvatureSample>& b, const std::vector<TissueViscoelastic>& c) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create the output folder ({})", dir.string(), ec.message()));
  std::vector<fs::path> written;
  auto save = [&](const std::string& file, const std::string& text) {
    const fs::path path = dir / file;
    std::ofstream os(path, std::ios::binary);
    os << text;
    if (!os) throw InputError(fmt::format("{}: cannot write", path.string()));
    written.push_back(path);
  };
  if (!a.empty()) {
    std::string s =
        "tissue,nodes,tets,effective_modulus_pa,effective_radius_m,time_s,indentation_m,penetration_m,force_n,"
        "hertz_at_indentation_n,hertz_at_penetration_n\n";
    for (const auto& t : a)
      for (const auto& x : t.samples)
        s += fmt::format("{},{},{},{:.6g},{:.6g},{:.4f},{:.6e},{:.6e},{:.6g},{:.6g},{:.6g}\n", t.tissue, t.nodes, t.tets,
                         t.effective_modulus, t.effective_radius, x.time, x.indentation, x.penetration, x.force,
                         x.hertz_at_indentation, x.hertz_at_penetration);
    save("force_indentation.csv", s);
  }
  if (!b.empty()) {
    std::string s = "surface,radius_m,exact_mean_curvature_per_m,estimated_mean_curvature_per_m,depth_m,force_n,hertz_force_n\n";
    for (const auto& x : b)
      s += fmt::format("{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n", x.surface, x.radius, x.exact_curvature,
                       x.estimated_curvature, x.depth, x.force, x.hertz_force);
    save("force_curvature.csv", s);
  }
  if (!c.empty()) {
    std::string creep = "tissue,model,tau_s,arm_ratio,time_step_s,load_n,time_s,displacement_m,analytic_m\n";
    std::string relax = "tissue,model,tau_s,arm_ratio,time_step_s,held_displacement_m,time_s,force_n,analytic_n\n";
    for (const auto& t : c) {
      for (const auto& x : t.creep)
        creep += fmt::format("{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6e},{:.6e}\n", t.tissue, t.model, t.relaxation_time,
                             t.arm_ratio, t.time_step, t.load, x.time, x.value, x.analytic);
      for (const auto& x : t.relaxation)
        relax += fmt::format("{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6e},{:.6e}\n", t.tissue, t.model, t.relaxation_time,
                             t.arm_ratio, t.time_step, t.held_displacement, x.time, x.value, x.analytic);
    }
    save("creep.csv", creep);
    save("relaxation.csv", relax);
  }
  return written;
}

std::string find_matplotlib_python() {
  for (const char* candidate : {"/usr/bin/python3", "python3"}) {
    const std::string probe = fmt::format("'{}' -c 'import matplotlib' >/dev/null 2>&1", candidate);
    if (std::system(probe.c_str()) == 0) return candidate;
  }
  return {};
}

}  // namespace tactus::app::curves

namespace tactus::app {
namespace {

namespace fs = std::filesystem;

struct CurvesFlags {
  std::string scene;
  std::string output;
  std::vector<std::string> tissues;
  double curvature_depth = 0.0015;
  bool no_plots = false;
  std::string plot_script;
  std::string python;
};

/// scripts/plot_curves.py beside the scene's folder (the source tree), else under the
/// working folder.
std::string default_plot_script(const std::string& scene) {
  const fs::path candidates[] = {fs::path(scene).parent_path() / ".." / "scripts" / "plot_curves.py",
                                 fs::path("scripts") / "plot_curves.py"};
  for (const auto& c : candidates)
    if (fs::exists(c)) return c.lexically_normal().string();
  return {};
}

std::string shell_quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

Action add_curves(CLI::App& app) {
  auto f = std::make_shared<CurvesFlags>();
  app.add_option("scene", f->scene, "Scene file (TOML), e.g. scenes/tissues.toml")->required()->check(CLI::ExistingFile);
  app.add_option("-o,--output", f->output, "Folder for the CSV files and plots")->required();
  app.add_option("--tissue", f->tissues, "Only this pressed body (repeatable); default all");
  app.add_option("--curvature-depth", f->curvature_depth, "Equal depth of the curvature presses [m] (default 0.0015)")
      ->check(CLI::Range(1e-5, 0.008));
  app.add_flag("--no-plots", f->no_plots, "Write the CSV files only");
  app.add_option("--plot-script", f->plot_script, "The plotting script (default scripts/plot_curves.py)");
  app.add_option("--python", f->python, "Python with matplotlib (default /usr/bin/python3, then python3)");
  return [f] {
    const scene::Model model = scene::load_scene(f->scene);
    std::vector<std::string> tissues = f->tissues.empty() ? curves::pressed_tissues(model) : f->tissues;
    if (tissues.empty())
      throw InputError(SourceLocation{model.source, {}, {}, {}},
                       "no pressed tissue: curves need hertz_finger algorithms, each touching one deformable body, "
                       "with a scripted press device");
    const auto a = curves::force_vs_indentation(model, tissues);
    const auto b = curves::force_vs_curvature(model, tissues.front(), f->curvature_depth);
    const auto c = curves::creep_and_relaxation(model, tissues);
    for (const auto& path : curves::write_csv(f->output, a, b, c)) log::info("wrote {}", path.string());
    for (const auto& t : a)
      if (!t.samples.empty())
        log::info("  {}: {} nodes, {} tets, E* {:.4g} Pa, R {:.4g} m; at indentation {:.3g} mm: {:.3g} N (Hertz {:.3g} N), "
                  "penetration {:.3g} mm",
                  t.tissue, t.nodes, t.tets, t.effective_modulus, t.effective_radius, t.samples.back().indentation * 1e3,
                  t.samples.back().force, t.samples.back().hertz_at_indentation, t.samples.back().penetration * 1e3);
    if (f->no_plots) return 0;
    const std::string script = f->plot_script.empty() ? default_plot_script(f->scene) : f->plot_script;
    const std::string python = f->python.empty() ? curves::find_matplotlib_python() : f->python;
    if (script.empty() || python.empty()) {
      log::warn("no plots: {}", script.empty() ? "scripts/plot_curves.py not found (--plot-script)"
                                               : "no python3 with matplotlib (Debian: python3-matplotlib)");
      return 0;
    }
    const std::string command = fmt::format("{} {} {}", shell_quoted(python), shell_quoted(script), shell_quoted(f->output));
    if (std::system(command.c_str()) != 0) throw InputError(fmt::format("plotting failed: {}", command));
    log::info("plots written to {}", f->output);
    return 0;
  };
}

}  // namespace tactus::app
