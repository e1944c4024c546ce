#include "runtime/simulation_step.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "compile/bodies.hpp"
#include "contact/closest_point.hpp"
#include "contact/fingertip.hpp"

namespace tactus::runtime {
namespace {

constexpr std::size_t kSharesPerContact = 64;  ///< vertices one contact's load spreads over, at most

const physics::Body& stepped(const SimulationModel::Body& mb, const SimulationState::Body& sb) {
  return sb.edited ? *sb.edited : *mb.physics;
}

/// The surface vertices' shares of a contact load, on the body's current shape.
std::span<const contact::LoadShare> spread(const SimulationModel& model, SimulationState& state, std::size_t b,
                                           const ContactLoad& load) {
  const SimulationModel::Body& mb = model.bodies[b];
  SimulationState::Body& sb = state.bodies[b];
  const auto& triangles = model.scene->bodies[b].surface.triangles;
  if (load.triangle < 0 || static_cast<std::size_t>(load.triangle) >= triangles.size()) return {};
  sb.surface.resize(mb.surface_to_node.size());
  for (std::size_t v = 0; v < sb.surface.size(); ++v)
    sb.surface[v] = sb.state.x.segment<3>(3 * static_cast<Eigen::Index>(mb.surface_to_node[v]));
  if (load.part_count <= 0) {
    const int count = contact::spread_load(sb.surface, triangles, mb.surface_area, load.triangle, load.barycentric,
                                           load.contact_radius, std::span(state.shares.data(), kSharesPerContact));
    return {state.shares.data(), static_cast<std::size_t>(count)};
  }
  // A sphere-set finger: each sphere's part spread over its own disc, weighted by its share;
  // each gets an equal slice of the buffer.
  const int parts = std::min(load.part_count, ContactLoad::kMaxParts);
  const std::size_t slice = std::min(kSharesPerContact, state.shares.size() / static_cast<std::size_t>(parts));
  std::size_t used = 0;
  for (int i = 0; i < parts; ++i) {
    const ContactLoad::Part& part = load.parts[static_cast<std::size_t>(i)];
    if (part.triangle < 0 || static_cast<std::size_t>(part.triangle) >= triangles.size()) continue;
    const std::span<contact::LoadShare> out(state.shares.data() + used, slice);
    const int count = contact::spread_load(sb.surface, triangles, mb.surface_area, part.triangle, part.barycentric,
                                           part.contact_radius, out);
    for (int k = 0; k < count; ++k) out[static_cast<std::size_t>(k)].share *= part.share;
    used += static_cast<std::size_t>(count);
  }
  return {state.shares.data(), used};
}

/// Adds a contact load on an embedded surface to its host's external forces.
void carry_to_host(const SimulationModel& model, SimulationState& state, std::size_t b,
                   std::span<const contact::LoadShare> shares, const Vec3& force) {
  const scene::Body& body = model.scene->bodies[b];
  if (!model.bodies[*body.host].physics) return;
  SimulationState::Body& sb = state.bodies[b];
  std::fill(sb.carried_forces.begin(), sb.carried_forces.end(), Vec3::Zero());
  for (const contact::LoadShare& s : shares) sb.carried_forces[static_cast<std::size_t>(s.vertex)] += s.share * force;
  body.host_mapping->apply_transpose(sb.carried_forces, state.bodies[*body.host].f_ext);
}

/// A needle shaft's push shared by the tissue nodes near it (seed 003 §3.3's proximity
/// search of behaviour-mesh nodes near the needle's ray).
void push_along_shaft(const SimulationModel& model, SimulationState& state, const ContactLoad& load,
                      const SimulationInputs& in, std::span<PartStats> parts) {
  const PartTimer search(in.clock);
  if (load.body < 0 || static_cast<std::size_t>(load.body) >= model.bodies.size()) return;
  std::size_t index = static_cast<std::size_t>(load.body);
  if (model.scene->bodies[index].host) index = *model.scene->bodies[index].host;
  const SimulationModel::Body& mb = model.bodies[index];
  SimulationState::Body& sb = state.bodies[index];
  if (!mb.physics || !(mb.shaft_reach > 0.0) || !load.shaft_force.allFinite()) return;
  const Vec3 a = load.shaft_from, axis = load.shaft_to - load.shaft_from;
  const double length2 = axis.squaredNorm();
  // Weights fall linearly from 1 on the shaft to 0 at the reach; they share the force.
  const auto weight = [&](Eigen::Index n) {
    const Vec3 p = sb.state.x.segment<3>(3 * n);
    const double s = length2 > 0.0 ? std::clamp((p - a).dot(axis) / length2, 0.0, 1.0) : 0.0;
    const double d = (p - (a + s * axis)).norm();
    return d < mb.shaft_reach ? 1.0 - d / mb.shaft_reach : 0.0;
  };
  const Eigen::Index nodes = sb.state.x.size() / 3;
  double total = 0.0;
  for (Eigen::Index n = 0; n < nodes; ++n) total += weight(n);
  if (total > 0.0)
    for (Eigen::Index n = 0; n < nodes; ++n)
      if (const double w = weight(n); w > 0.0) sb.f_ext.segment<3>(3 * n) += (w / total) * load.shaft_force;
  search.record(parts, shaft_node_search);
}

/// How far the load's material point has moved along unit `direction` since the simulation
/// published the surface its force was rendered on, to `surface` (the step starts from it)
/// [m]; 0 where the load names no published point or the body keeps no patch surface.
double drift_since_published(const std::vector<Vec3>& surface, const std::vector<mesh::Triangle>& triangles,
                             const ContactLoad& load, const Vec3& direction) {
  if (!load.published_point.allFinite() || load.triangle < 0 || static_cast<std::size_t>(load.triangle) >= triangles.size())
    return 0.0;
  const mesh::Triangle& corners = triangles[static_cast<std::size_t>(load.triangle)];
  for (const mesh::Index v : corners)
    if (v < 0 || static_cast<std::size_t>(v) >= surface.size()) return 0.0;
  return (mesh::point_on(surface, corners, load.barycentric) - load.published_point).dot(direction);
}

/// A hold along a plane (ContactLoad::hold_plane_normal): two unit directions spanning the
/// plane, the first along the load's force where it has a part in the plane; none for any
/// other load, or a normal that is not a finite nonzero vector.
std::optional<std::array<Vec3, 2>> hold_plane_directions(const ContactLoad& load) {
  const double length = load.hold_plane_normal.norm();
  if (!(length > 0.0) || !std::isfinite(length) || !load.force.allFinite()) return std::nullopt;
  const Vec3 n = load.hold_plane_normal / length;
  const Vec3 in_plane = load.force - n * n.dot(load.force);
  const double norm = in_plane.norm();
  const Vec3 first = norm > 1e-12 * std::max(1.0, load.force.norm()) ? Vec3(in_plane / norm) : Vec3(n.unitOrthogonal());
  return std::array<Vec3, 2>{first, n.cross(first)};
}

/// Scene loads and prescribed motions at the end of the period, then each device's push
/// spread over the vertices around its contact point.
void apply_loads(const SimulationModel& model, SimulationState& state, const SimulationInputs& in,
                 std::span<PartStats> parts) {
  const double t_end = static_cast<double>(state.step) / model.scene->rates.simulation;  // simulated time reached
  auto fraction = [t_end](double ramp_time) { return compile::ramp(t_end, ramp_time); };
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    if (!model.bodies[b].physics) continue;
    const scene::Body& body = model.scene->bodies[b];
    compile::assemble_loads(body, fraction, state.bodies[b].f_ext);
    compile::place_prescribed(body, model.bodies[b].rest, fraction, state.bodies[b].state.x);
  }
  for (SimulationState::Device& d : state.devices) d.applied = ContactLoad{}, d.applied_shares.clear();
  for (SimulationState::Body& sb : state.bodies) sb.springs.clear();
  for (std::size_t device = 0; device < in.loads.size() && device < state.devices.size(); ++device) {
    SimulationState::Device& d = state.devices[device];
    d.spring = -1, d.spring_count = 0;
    const ContactLoad& load = in.loads[device];
    if (load.shaft) push_along_shaft(model, state, load, in, parts);
    if (!load.active || load.body < 0 || static_cast<std::size_t>(load.body) >= model.bodies.size()) continue;
    const std::size_t b = static_cast<std::size_t>(load.body);
    SimulationState::Body& sb = state.bodies[b];
    if (model.scene->bodies[b].host) {
      // A fascia sheet or a vessel wall: its host's tetrahedra take the load.
      carry_to_host(model, state, b, spread(model, state, b, load), load.force);
      continue;
    }
    if (!model.bodies[b].physics) continue;
    const std::span<const contact::LoadShare> shares = spread(model, state, b, load);
    const double push = load.force.norm();
    const std::optional<std::array<Vec3, 2>> plane = hold_plane_directions(load);
    const std::size_t wanted = plane ? 2 : 1;
    if ((push > 0.0 || plane) && sb.springs.size() + wanted <= physics::kMaxContactSprings) {
      // Coupled into the step: the push eases as the tissue gives way under it.
      d.nodes.clear();
      for (const contact::LoadShare& s : shares)
        d.nodes.push_back({model.bodies[b].surface_to_node[static_cast<std::size_t>(s.vertex)], s.share});
      d.body = b;
      d.spring = static_cast<int>(sb.springs.size());
      d.spring_count = static_cast<int>(wanted);
      // The push where the surface the step starts from stands, not where the haptic loop's
      // patch had moved the contact point to, nor where the surface that patch was
      // published from stood: in real time the simulation may have stepped since, and a
      // push taken as it was rendered went on pushing a point that had already moved.
      const double stiffness = std::max(0.0, load.stiffness);
      const bool bilateral = load.bilateral || plane.has_value();
      const Vec3 along_force = push > 0.0 ? Vec3(load.force / push) : Vec3::Zero();
      const auto& triangles = model.scene->bodies[b].surface.triangles;
      const auto add_spring = [&](const Vec3& direction, double start, double surface_offset) {
        const double drift = drift_since_published(sb.surface, triangles, load, direction);
        const double offset = stiffness * (surface_offset - drift);
        const double at_surface = std::isfinite(offset) ? start + offset : start;
        sb.springs.push_back({d.nodes, direction, at_surface, stiffness,
                              bilateral ? at_surface : std::max(0.0, at_surface), bilateral});
      };
      if (plane) {
        // surface_offset is measured along the force, which lies along the first direction.
        for (const Vec3& direction : *plane)
          add_spring(direction, load.force.dot(direction), load.surface_offset * direction.dot(along_force));
      } else {
        add_spring(along_force, push, load.surface_offset);
      }
    } else {
      for (const contact::LoadShare& s : shares)
        sb.f_ext.segment<3>(3 * static_cast<Eigen::Index>(model.bodies[b].surface_to_node[static_cast<std::size_t>(s.vertex)])) +=
            s.share * load.force;
    }
    if (model.patches[device]) d.applied = load, d.applied_shares.assign(shares.begin(), shares.end());
  }
}

void apply_live_materials(const SimulationModel& model, SimulationState& state, const SimulationInputs& in) {
  if (!in.materials || !in.scene_materials) return;
  const LiveParameters::Materials& m = *in.materials;
  if (m.version == state.materials_version || in.t < m.from) return;
  state.materials_version = m.version;
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    SimulationState::Body& sb = state.bodies[b];
    if (!sb.live) continue;
    const LiveParameters::Material& edit = m.body[b];
    sb.live->set(edit.young_modulus / in.scene_materials->body[b].young_modulus,
                 edit.damping_set ? edit.damping : -1.0);
  }
}

/// Cspace bodies take the interpolated shape at the tool of the first device without a
/// patch that reports one (devices with a patch hand theirs to the patches instead); a
/// two-point space at its two tools.
void shape_cspace_bodies(const SimulationModel& model, SimulationState& state, std::span<const ToolState> tools) {
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    if (!model.bodies[b].cspace) continue;
    if (model.bodies[b].cspace->pair()) {
      std::array<const Vec3*, 2> at{};
      for (std::size_t k = 0; k < 2; ++k) {
        const std::size_t device = model.scene->tools[model.bodies[b].cspace->pair_tools()[k]].devices.front();
        if (device < tools.size() && tools[device].valid) at[k] = &tools[device].position;
      }
      model.bodies[b].cspace->positions(at[0], at[1], state.bodies[b].state.x);
      continue;
    }
    for (std::size_t device = 0; device < tools.size() && device < model.patches.size(); ++device) {
      if (model.patches[device] || !tools[device].valid) continue;
      model.bodies[b].cspace->positions(tools[device].position, tools[device].orientation, state.bodies[b].state.x);
      break;
    }
  }
}

/// Embedded surfaces follow their hosts' new node positions.
void carry_embedded(const SimulationModel& model, SimulationState& state) {
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    const scene::Body& body = model.scene->bodies[b];
    if (!body.host) continue;
    SimulationState::Body& sb = state.bodies[b];
    body.host_mapping->apply(state.bodies[*body.host].state.x, sb.carried_positions);
    for (std::size_t v = 0; v < sb.carried_positions.size(); ++v)
      sb.state.x.segment<3>(3 * static_cast<Eigen::Index>(v)) = sb.carried_positions[v];
  }
}

void write_surfaces(const SimulationModel& model, const SimulationState& state, double t, SurfaceSnapshot& s) {
  s.t = t;
  s.step = state.step;
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    auto& p = s.positions[b];
    for (std::size_t v = 0; v < p.size(); ++v)
      p[v] = state.bodies[b].state.x.segment<3>(3 * static_cast<Eigen::Index>(model.bodies[b].surface_to_node[v]));
  }
}

void write_patches(const SimulationModel& model, SimulationState& state, double t, std::span<const ToolState> tools,
                   std::span<contact::LocalPatch* const> patches) {
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    // Only the bodies a patch may be cut from.
    const bool wanted = std::any_of(state.devices.begin(), state.devices.end(),
                                    [&](const SimulationState::Device& d) { return !d.builders.empty() && d.builders[b]; });
    if (!wanted) continue;
    const SimulationModel::Body& mb = model.bodies[b];
    SimulationState::Body& sb = state.bodies[b];
    sb.surface.resize(mb.surface_to_node.size());
    sb.surface_before.resize(mb.surface_to_node.size());
    const bool moved = sb.x_before.size() == sb.state.x.size();
    for (std::size_t v = 0; v < sb.surface.size(); ++v) {
      const auto n = 3 * static_cast<Eigen::Index>(mb.surface_to_node[v]);
      sb.surface[v] = sb.state.x.segment<3>(n);
      sb.surface_before[v] = moved ? Vec3(sb.x_before.segment<3>(n)) : sb.surface[v];
    }
  }
  for (std::size_t device = 0; device < model.patches.size() && device < patches.size(); ++device) {
    if (!model.patches[device] || !patches[device]) continue;
    const PatchRequest& request = *model.patches[device];
    SimulationState::Device& d = state.devices[device];
    const ToolState& tool = tools[device];
    contact::LocalPatch& out = *patches[device];
    out.valid = false;
    out.time = t;
    out.free_count = out.node_count = out.triangle_count = 0;
    // The body whose surface (its triangles, as PatchBuilder::select tests them) comes
    // nearest the tool, within the patch's sphere. Its vertices would not do: on a coarse
    // mesh a face's centre lies far from every corner, the patch appeared only deep in the
    // face, and the first load's dent pushed the corner out of reach again (on/off at 50 Hz).
    std::size_t best_body = model.bodies.size();
    double best = request.radius;
    if (tool.valid)
      for (std::size_t b = 0; b < model.bodies.size(); ++b) {
        if (!d.builders[b]) continue;
        const contact::SurfacePoint nearest = contact::closest_point_on_surface(
            tool.position, state.bodies[b].surface, model.scene->bodies[b].surface.triangles);
        if (nearest.triangle >= 0 && nearest.distance <= best) best = nearest.distance, best_body = b;
      }
    if (best_body == model.bodies.size()) continue;
    const SimulationModel::Body& mb = model.bodies[best_body];
    const SimulationState::Body& sb = state.bodies[best_body];
    const scene::Body& body = model.scene->bodies[best_body];
    contact::PatchBuilder::Inputs patch_in;
    patch_in.kind = request.kind;
    patch_in.body = static_cast<std::int32_t>(best_body);
    patch_in.time = t;
    patch_in.center = tool.position;
    patch_in.radius = request.radius;
    patch_in.surface = sb.surface;
    patch_in.surface_previous = sb.surface_before;
    patch_in.step_period = sb.span > 0.0 ? sb.span : model.period;
    patch_in.vertex_area = mb.surface_area;
    if (d.applied.active && d.applied.body == patch_in.body) {
      patch_in.load_shares = d.applied_shares;
      patch_in.load_force = d.applied.force;
    }
    patch_in.rigid = !mb.physics;
    if (mb.physics) {
      patch_in.physics_body = &stepped(mb, sb);
      patch_in.physics_state = &sb.state;
    }
    patch_in.surface_to_node = mb.surface_to_node;
    if (body.material) {
      const scene::Material& m = model.scene->materials[*body.material];
      patch_in.material = {m.young_modulus, m.poisson_ratio, m.density};
    }
    patch_in.own_stiffness = body.kind == scene::BodyKind::cloth;  // a fabric: nothing under it
    patch_in.frame_time = 1.0 / model.scene->rates.haptic;
    d.builders[best_body]->build(patch_in, out);
  }
}

}  // namespace

SimulationModel make_simulation_model(const scene::Model& scene, std::vector<std::optional<PatchRequest>> patches,
                                      const compile::CspaceBodies& cspaces) {
  SimulationModel model;
  model.scene = &scene;
  model.period = 1.0 / scene.rates.simulation;
  model.patches = std::move(patches);
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const scene::Body& b = scene.bodies[i];
    SimulationModel::Body mb;
    const auto& nodes = b.simulation_vertices();
    mb.rest.resize(static_cast<Eigen::Index>(3 * nodes.size()));
    for (std::size_t n = 0; n < nodes.size(); ++n) mb.rest.segment<3>(static_cast<Eigen::Index>(3 * n)) = nodes[n];
    if (b.cspace) {
      mb.cspace = compile::cspace_body(scene, i, cspaces);
    } else if (b.kind == scene::BodyKind::embedded) {
      model.embedded = true;
    } else if (b.kind != scene::BodyKind::rigid) {
      mb.physics = compile::make_physics_body(scene, i);
      mb.substeps = std::max(1, static_cast<int>(std::ceil(model.period / b.time_step - 1e-9)));
    }
    if (b.volumetric()) {
      mb.surface_to_node = b.surface_to_volume;
    } else {
      mb.surface_to_node.resize(b.surface.vertices.size());
      for (std::size_t n = 0; n < mb.surface_to_node.size(); ++n) mb.surface_to_node[n] = static_cast<mesh::Index>(n);
    }
    mb.surface_area = contact::vertex_areas(b.surface.vertices, b.surface.triangles);
    if (b.volume && !b.volume->tets.empty()) {
      double edges = 0.0;
      for (const auto& t : b.volume->tets)
        for (std::size_t p = 0; p < 4; ++p)
          for (std::size_t q = p + 1; q < 4; ++q) edges += (b.volume->vertices[t[p]] - b.volume->vertices[t[q]]).norm();
      mb.shaft_reach = 0.75 * edges / (6.0 * static_cast<double>(b.volume->tets.size()));
    }
    model.bodies.push_back(std::move(mb));
  }
  return model;
}

SimulationState make_simulation_state(const SimulationModel& model, const LiveParameters* live_materials) {
  SimulationState state;
  for (std::size_t index = 0; index < model.bodies.size(); ++index) {
    const SimulationModel::Body& mb = model.bodies[index];
    const scene::Body& b = model.scene->bodies[index];
    SimulationState::Body sb;
    if (mb.physics) {
      sb.state = physics::make_state(*mb.physics);
      if (live_materials && live_materials->material_editable(index)) {
        VecX damping = scene_mass_damping(*model.scene, index, mb.physics->model->lumped_mass());
        sb.live = std::make_shared<LiveMaterialModel>(mb.physics->model, std::move(damping));
        sb.edited = *mb.physics;
        sb.edited->model = sb.live;
        sb.state.model_scratch = sb.live->make_scratch();  // the wrapper's, holding the scene model's
      }
      physics::analyse_ahead(stepped(mb, sb), sb.state, model.period / mb.substeps);
    } else {
      sb.state.x = mb.rest;
    }
    if (b.kind == scene::BodyKind::embedded) {
      sb.carried_forces.assign(b.surface.vertices.size(), Vec3::Zero());
      sb.carried_positions.assign(b.surface.vertices.size(), Vec3::Zero());
    }
    sb.f_ext = VecX::Zero(mb.rest.size());
    sb.springs.reserve(physics::kMaxContactSprings);
    state.bodies.push_back(std::move(sb));
  }
  state.devices.resize(model.patches.size());
  for (std::size_t device = 0; device < model.patches.size(); ++device) {
    SimulationState::Device& d = state.devices[device];
    d.nodes.reserve(state.shares.size());
    if (!model.patches[device]) continue;
    const PatchRequest& request = *model.patches[device];
    d.builders.resize(model.bodies.size());
    for (const std::size_t b : request.bodies)
      if (b < model.bodies.size())
        d.builders[b] = std::make_unique<contact::PatchBuilder>(model.scene->bodies[b].surface.vertices.size(),
                                                                model.scene->bodies[b].surface.triangles,
                                                                request.capacity);
  }
  return state;
}

SurfaceSnapshot rest_surfaces(const SimulationModel& model) {
  SurfaceSnapshot s;
  for (const SimulationModel::Body& mb : model.bodies) {
    std::vector<Vec3> p(mb.surface_to_node.size());
    for (std::size_t v = 0; v < p.size(); ++v) p[v] = mb.rest.segment<3>(3 * static_cast<Eigen::Index>(mb.surface_to_node[v]));
    s.positions.push_back(std::move(p));
  }
  return s;
}

NodeSnapshot rest_nodes(const SimulationModel& model) {
  NodeSnapshot s;
  for (const SimulationModel::Body& mb : model.bodies) {
    s.x.push_back(mb.rest);
    s.v.push_back(VecX::Zero(mb.rest.size()));
    s.contact.push_back(VecX::Zero(mb.rest.size()));
  }
  return s;
}

void write_nodes(const SimulationModel& model, const SimulationState& state, double t, NodeSnapshot& s) {
  s.t = t;
  s.step = state.step;
  for (std::size_t b = 0; b < model.bodies.size() && b < s.x.size(); ++b) {
    const physics::BodyState& bs = state.bodies[b].state;
    // Same sizes as the rest state: plain copies, no allocation.
    if (bs.x.size() == s.x[b].size()) s.x[b] = bs.x;
    if (bs.v.size() == s.v[b].size()) s.v[b] = bs.v;
    else s.v[b].setZero();
    VecX& contact = s.contact[b];
    contact.setZero();
    for (const physics::ContactSpring& c : state.bodies[b].springs)
      for (const physics::NodeShare& n : c.nodes)
        if (n.node >= 0 && 3 * static_cast<Eigen::Index>(n.node) + 2 < contact.size())
          contact.segment<3>(3 * static_cast<Eigen::Index>(n.node)) += n.share * c.force * c.direction;
  }
}

/// The nodes of body `b` inside a grasping pad (ContactLoad::Pad) move out of it, to the
/// nearer of its capsule's surface and the pinch's plane, and lose the velocity into it: the
/// pads are rigid to the fabric between them. Without it only the held point kept to the
/// pinch, and the sheet beside it passed through the pads (up to 7 mm into the thumb when
/// the pads opened).
void keep_out_of_pads(const SimulationModel& model, std::span<const ContactLoad> loads, std::size_t b,
                      const physics::Body& body, physics::BodyState& s) {
  const auto& triangles = model.scene->bodies[b].surface.triangles;
  const auto& surface_to_node = model.bodies[b].surface_to_node;
  for (const ContactLoad& load : loads) {
    if (!load.active || !load.pad.active || load.body != static_cast<std::int32_t>(b)) continue;
    const ContactLoad::Pad& pad = load.pad;
    if (!(pad.radius > 0.0) || !std::isfinite(pad.radius) || !pad.base.allFinite() || !pad.tip.allFinite() ||
        !pad.plane_point.allFinite() || !pad.toward_partner.allFinite())
      continue;
    // The held point's corners follow the hold's springs, which the step has solved.
    std::array<mesh::Index, 3> held{-1, -1, -1};
    if (load.triangle >= 0 && static_cast<std::size_t>(load.triangle) < triangles.size())
      for (int k = 0; k < 3; ++k) {
        const mesh::Index v = triangles[static_cast<std::size_t>(load.triangle)][k];
        if (v >= 0 && static_cast<std::size_t>(v) < surface_to_node.size())
          held[static_cast<std::size_t>(k)] = surface_to_node[static_cast<std::size_t>(v)];
      }
    const Eigen::Index nodes = s.x.size() / 3;
    for (Eigen::Index i = 0; i < nodes; ++i) {
      if (!body.fixed_dofs.empty() && body.fixed_dofs[static_cast<std::size_t>(3 * i)]) continue;
      if (std::find(held.begin(), held.end(), static_cast<mesh::Index>(i)) != held.end()) continue;
      auto x = s.x.segment<3>(3 * i);
      const Vec3 p = x;
      const double to_plane = pad.toward_partner.dot(pad.plane_point - p);  // > 0 on the pad's side
      if (!(to_plane > 0.0)) continue;
      const Vec3 axis_point = contact::closest_point_on_segment(p, pad.base, pad.tip).point;
      const Vec3 out = p - axis_point;
      const double from_axis = out.norm();
      const double to_surface = pad.radius - from_axis;
      if (!(to_surface > 0.0)) continue;
      const bool onto_plane = to_plane < to_surface || from_axis == 0.0;
      const Vec3 normal = onto_plane ? pad.toward_partner : Vec3(out / from_axis);
      x = p + (onto_plane ? to_plane : to_surface) * normal;
      auto v = s.v.segment<3>(3 * i);
      const double into = normal.dot(Vec3(v));
      if (into < 0.0) v -= into * normal;
    }
  }
}

int advance_bodies(const SimulationModel& model, SimulationState& state, const SimulationInputs& in,
                   std::span<PartStats> parts) {
  apply_live_materials(model, state, in);
  // The time since the last step: one period but after missed periods in real time (a
  // lockstep run never misses one, and its steps stay exactly one period long).
  const double gap = in.t - state.t;
  state.t = in.t;
  if (state.step == 0) return 0;  // the first step publishes the rest shapes
  const double span = gap > 1.5 * model.period ? std::min(gap, model.scene->rates.catch_up * model.period) : model.period;
  if (span > model.period) ++state.late_steps;
  const PartTimer loads(in.clock, in.start);
  apply_loads(model, state, in, parts);
  const PartTimer integration(in.clock, loads.record(parts, contact_loads));
  const bool patches = std::any_of(model.patches.begin(), model.patches.end(), [](const auto& p) { return p.has_value(); });
  int iterations = 0;
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    const SimulationModel::Body& mb = model.bodies[b];
    if (!mb.physics) continue;
    SimulationState::Body& sb = state.bodies[b];
    const physics::Body& body = stepped(mb, sb);
    if (patches) sb.x_before = sb.state.x;
    // An implicit step stays stable over a longer span; an explicit one does not.
    sb.span = body.settings.integrator == physics::Integrator::implicit_euler ? span : model.period;
    const double dt = sb.span / mb.substeps;
    for (int k = 0; k < mb.substeps; ++k) {
      physics::step(body, sb.state, dt, sb.f_ext, sb.springs);
      for (physics::ContactSpring& c : sb.springs) c.force = c.force_end;
      iterations += sb.state.last_linear_iterations;
    }
    keep_out_of_pads(model, in.loads, b, body, sb.state);
    if (!sb.state.x.allFinite())
      throw std::runtime_error(fmt::format("body '{}' diverged at t = {} s (NaN or infinite positions); reduce "
                                           "its time_step, soften the contact or use implicit_euler",
                                           model.scene->bodies[b].name,
                                           static_cast<double>(state.step) / model.scene->rates.simulation));
  }
  // The patches are built around the push the tissue took at the end of the step.
  for (SimulationState::Device& d : state.devices)
    if (d.spring >= 0 && !d.builders.empty()) {
      d.applied.force.setZero();
      for (int k = 0; k < d.spring_count; ++k) {
        const physics::ContactSpring& c = state.bodies[d.body].springs[static_cast<std::size_t>(d.spring + k)];
        d.applied.force += c.force * c.direction;
      }
    }
  integration.record(parts, integrate);
  return iterations;
}

void publish_shapes(const SimulationModel& model, SimulationState& state, const SimulationInputs& in,
                    std::span<const ToolState> tools, const SimulationOutputs& out) {
  shape_cspace_bodies(model, state, tools);
  const PartTimer embedded(in.clock);
  carry_embedded(model, state);
  // Only a scene with embedded layers reports that part.
  const PartTimer publish(in.clock, embedded.record(model.embedded ? out.parts : std::span<PartStats>{}, embedded_surfaces));
  for (SurfaceSnapshot* s : out.surfaces) write_surfaces(model, state, in.t, *s);
  const PartTimer local(in.clock, publish.record(out.parts, publish_surfaces));
  if (std::any_of(out.patches.begin(), out.patches.end(), [](const auto* p) { return p != nullptr; })) {
    write_patches(model, state, in.t, tools, out.patches);
    local.record(out.parts, local_models);
  }
  ++state.step;
}

}  // namespace tactus::runtime
