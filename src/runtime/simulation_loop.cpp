#include "runtime/simulation_loop.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "contact/closest_point.hpp"
#include "compile/bodies.hpp"
#include "compile/cspace_body.hpp"

namespace tactus::runtime {

SimulationLoop::SimulationLoop(const scene::Model& model, std::vector<DeviceChannels*> devices,
                               const compile::CspaceBodies& cspaces)
    : model_(model), devices_(std::move(devices)), steps_ring_(1 << 14) {
  stats_.name = "simulation";
  stats_.rate = model.rates.simulation;
  parts_ = {{"contact loads", {}}, {"integrate", {}}, {"publish surfaces", {}}, {"local models", {}},
            {"embedded surfaces", {}}, {"shaft node search", {}}};
  const double period = 1.0 / model.rates.simulation;
  for (std::size_t i = 0; i < model.bodies.size(); ++i) {
    const scene::Body& b = model.bodies[i];
    SimBody sb;
    sb.index = i;
    const auto& nodes = b.simulation_vertices();
    sb.rest.resize(static_cast<Eigen::Index>(3 * nodes.size()));
    for (std::size_t n = 0; n < nodes.size(); ++n) sb.rest.segment<3>(static_cast<Eigen::Index>(3 * n)) = nodes[n];
    if (b.cspace) {
      sb.cspace = compile::cspace_body(model, i, cspaces);
      sb.state.x = sb.rest;
    } else if (b.kind == scene::BodyKind::embedded) {
      embedded_ = true;
      sb.state.x = sb.rest;
      sb.carried_forces.assign(b.surface.vertices.size(), Vec3::Zero());
      sb.carried_positions.assign(b.surface.vertices.size(), Vec3::Zero());
    } else if (b.kind != scene::BodyKind::rigid) {
      sb.body = compile::make_physics_body(model, i);
      sb.state = physics::make_state(*sb.body);
      // Substeps of at most the body's time step make one simulation period.
      sb.substeps = std::max(1, static_cast<int>(std::ceil(period / b.time_step - 1e-9)));
    } else {
      sb.state.x = sb.rest;
    }
    sb.f_ext = VecX::Zero(sb.rest.size());
    if (b.volumetric()) {
      sb.surface_to_node = b.surface_to_volume;
    } else {
      sb.surface_to_node.resize(b.surface.vertices.size());
      for (std::size_t n = 0; n < sb.surface_to_node.size(); ++n) sb.surface_to_node[n] = static_cast<mesh::Index>(n);
    }
    sb.surface_area = contact::vertex_areas(b.surface.vertices, b.surface.triangles);
    if (b.volume && !b.volume->tets.empty()) {
      double edges = 0.0;
      for (const auto& t : b.volume->tets)
        for (std::size_t p = 0; p < 4; ++p)
          for (std::size_t q = p + 1; q < 4; ++q) edges += (b.volume->vertices[t[p]] - b.volume->vertices[t[q]]).norm();
      sb.shaft_reach = 0.75 * edges / (6.0 * static_cast<double>(b.volume->tets.size()));
    }
    bodies_.push_back(std::move(sb));
  }
  pushes_.resize(devices_.size());
  for (DevicePush& p : pushes_) p.nodes.reserve(shares_.size());
  for (SimBody& sb : bodies_) sb.springs.reserve(physics::kMaxContactSprings);
  for (DeviceChannels* d : devices_) {
    if (!d->patch) continue;
    PatchSource source;
    source.channels = d;
    source.builders.resize(model.bodies.size());
    for (const std::size_t b : d->patch_request.bodies)
      if (b < model.bodies.size())
        source.builders[b] = std::make_unique<contact::PatchBuilder>(model.bodies[b].surface.vertices.size(),
                                                                     model.bodies[b].surface.triangles,
                                                                     d->patch_request.capacity);
    patch_sources_.push_back(std::move(source));
  }
}

std::span<const contact::LoadShare> SimulationLoop::spread(SimBody& sb, const ContactLoad& load) {
  const auto& triangles = model_.bodies[sb.index].surface.triangles;
  if (load.triangle < 0 || static_cast<std::size_t>(load.triangle) >= triangles.size()) return {};
  sb.surface.resize(sb.surface_to_node.size());
  for (std::size_t v = 0; v < sb.surface.size(); ++v)
    sb.surface[v] = sb.state.x.segment<3>(3 * static_cast<Eigen::Index>(sb.surface_to_node[v]));
  if (load.part_count <= 0) {
    const int count = contact::spread_load(sb.surface, triangles, sb.surface_area, load.triangle, load.barycentric,
                                           load.contact_radius, std::span(shares_.data(), kSharesPerContact));
    return {shares_.data(), static_cast<std::size_t>(count)};
  }
  // A sphere-set finger: each sphere's part spread over its own disc, weighted by its share;
  // each gets an equal slice of the buffer.
  const int parts = std::min(load.part_count, ContactLoad::kMaxParts);
  const std::size_t slice = std::min(kSharesPerContact, shares_.size() / static_cast<std::size_t>(parts));
  std::size_t used = 0;
  for (int i = 0; i < parts; ++i) {
    const ContactLoad::Part& part = load.parts[static_cast<std::size_t>(i)];
    if (part.triangle < 0 || static_cast<std::size_t>(part.triangle) >= triangles.size()) continue;
    const std::span<contact::LoadShare> out(shares_.data() + used, slice);
    const int count = contact::spread_load(sb.surface, triangles, sb.surface_area, part.triangle, part.barycentric,
                                           part.contact_radius, out);
    for (int k = 0; k < count; ++k) out[static_cast<std::size_t>(k)].share *= part.share;
    used += static_cast<std::size_t>(count);
  }
  return {shares_.data(), used};
}

SurfaceSnapshot SimulationLoop::initial_snapshot() const {
  SurfaceSnapshot s;
  for (const SimBody& sb : bodies_) {
    std::vector<Vec3> p(sb.surface_to_node.size());
    for (std::size_t v = 0; v < p.size(); ++v) p[v] = sb.rest.segment<3>(3 * static_cast<Eigen::Index>(sb.surface_to_node[v]));
    s.positions.push_back(std::move(p));
  }
  return s;
}

const VecX* SimulationLoop::positions(std::size_t body) const {
  for (const SimBody& sb : bodies_)
    if (sb.index == body) return &sb.state.x;
  return nullptr;
}

void SimulationLoop::update_cspace_shapes() {
  // The shape at the newest tool position of the first device that reports one (devices with
  // a patch hand theirs to publish_patches instead).
  for (SimBody& sb : bodies_) {
    if (!sb.cspace) continue;
    for (DeviceChannels* d : devices_) {
      if (d->patch) continue;
      d->tool_to_simulation.update();
      const ToolState& tool = d->tool_to_simulation.read();
      if (!tool.valid) continue;
      sb.cspace->positions(tool.position, sb.state.x);
      break;
    }
  }
}

void SimulationLoop::update_embedded_shapes() {
  for (SimBody& sb : bodies_) {
    const scene::Body& b = model_.bodies[sb.index];
    if (!b.host) continue;
    b.host_mapping->apply(bodies_[*b.host].state.x, sb.carried_positions);
    for (std::size_t v = 0; v < sb.carried_positions.size(); ++v)
      sb.state.x.segment<3>(3 * static_cast<Eigen::Index>(v)) = sb.carried_positions[v];
  }
}

void SimulationLoop::carry_to_host(SimBody& sb, std::span<const contact::LoadShare> shares, const Vec3& force) {
  const scene::Body& b = model_.bodies[sb.index];
  SimBody& host = bodies_[*b.host];
  if (!host.body) return;
  std::fill(sb.carried_forces.begin(), sb.carried_forces.end(), Vec3::Zero());
  for (const contact::LoadShare& s : shares) sb.carried_forces[static_cast<std::size_t>(s.vertex)] += s.share * force;
  b.host_mapping->apply_transpose(sb.carried_forces, host.f_ext);
}

void SimulationLoop::push_along_shaft(const ContactLoad& load) {
  const Nanos start = now_ns();
  if (load.body < 0 || static_cast<std::size_t>(load.body) >= bodies_.size()) return;
  std::size_t index = static_cast<std::size_t>(load.body);
  if (model_.bodies[index].host) index = *model_.bodies[index].host;
  SimBody& sb = bodies_[index];
  if (!sb.body || !(sb.shaft_reach > 0.0) || !load.shaft_force.allFinite()) return;
  const Vec3 a = load.shaft_from, axis = load.shaft_to - load.shaft_from;
  const double length2 = axis.squaredNorm();
  // Weights fall linearly from 1 on the shaft to 0 at the reach; they share the force.
  const auto weight = [&](Eigen::Index n) {
    const Vec3 p = sb.state.x.segment<3>(3 * n);
    const double s = length2 > 0.0 ? std::clamp((p - a).dot(axis) / length2, 0.0, 1.0) : 0.0;
    const double d = (p - (a + s * axis)).norm();
    return d < sb.shaft_reach ? 1.0 - d / sb.shaft_reach : 0.0;
  };
  const Eigen::Index nodes = sb.state.x.size() / 3;
  double total = 0.0;
  for (Eigen::Index n = 0; n < nodes; ++n) total += weight(n);
  if (total > 0.0)
    for (Eigen::Index n = 0; n < nodes; ++n)
      if (const double w = weight(n); w > 0.0) sb.f_ext.segment<3>(3 * n) += (w / total) * load.shaft_force;
  parts_[5].time.record(now_ns() - start);
}

void SimulationLoop::publish(double t) {
  for (auto* out : outputs_) {
    SurfaceSnapshot& s = out->write_buffer();
    s.t = t;
    s.step = step_;
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
      const SimBody& sb = bodies_[b];
      auto& p = s.positions[b];
      for (std::size_t v = 0; v < p.size(); ++v)
        p[v] = sb.state.x.segment<3>(3 * static_cast<Eigen::Index>(sb.surface_to_node[v]));
    }
    out->publish();
  }
}

void SimulationLoop::publish_patches(double t) {
  const double period = 1.0 / stats_.rate;
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    // Only the bodies a patch may be cut from: publish() has copied every surface already.
    const bool wanted = std::any_of(patch_sources_.begin(), patch_sources_.end(),
                                    [&](const PatchSource& source) { return source.builders[b] != nullptr; });
    if (!wanted) continue;
    SimBody& sb = bodies_[b];
    sb.surface.resize(sb.surface_to_node.size());
    sb.surface_before.resize(sb.surface_to_node.size());
    const bool moved = sb.x_before.size() == sb.state.x.size();
    for (std::size_t v = 0; v < sb.surface.size(); ++v) {
      const auto n = 3 * static_cast<Eigen::Index>(sb.surface_to_node[v]);
      sb.surface[v] = sb.state.x.segment<3>(n);
      sb.surface_before[v] = moved ? Vec3(sb.x_before.segment<3>(n)) : sb.surface[v];
    }
  }
  for (PatchSource& source : patch_sources_) {
    DeviceChannels& d = *source.channels;
    d.tool_to_simulation.update();
    const ToolState& tool = d.tool_to_simulation.read();
    contact::LocalPatch& out = d.patch->write_buffer();
    out.valid = false;
    out.time = t;
    out.free_count = out.node_count = out.triangle_count = 0;
    // The body whose surface (its triangles, as PatchBuilder::select tests them) comes
    // nearest the tool, within the patch's sphere. Its vertices would not do: on a coarse
    // mesh a face's centre lies far from every corner, the patch appeared only deep in the
    // face, and the first load's dent pushed the corner out of reach again (on/off at 50 Hz).
    std::size_t best_body = bodies_.size();
    double best = d.patch_request.radius;
    if (tool.valid)
      for (std::size_t b = 0; b < bodies_.size(); ++b) {
        if (!source.builders[b]) continue;
        const contact::SurfacePoint nearest = contact::closest_point_on_surface(
            tool.position, bodies_[b].surface, model_.bodies[bodies_[b].index].surface.triangles);
        if (nearest.triangle >= 0 && nearest.distance <= best) best = nearest.distance, best_body = b;
      }
    if (best_body < bodies_.size()) {
      const SimBody& sb = bodies_[best_body];
      const scene::Body& body = model_.bodies[sb.index];
      contact::PatchBuilder::Inputs in;
      in.kind = d.patch_request.kind;
      in.body = static_cast<std::int32_t>(best_body);
      in.time = t;
      in.center = tool.position;
      in.radius = d.patch_request.radius;
      in.surface = sb.surface;
      in.surface_previous = sb.surface_before;
      in.step_period = period;
      in.vertex_area = sb.surface_area;
      if (source.applied.active && source.applied.body == in.body) {
        in.load_shares = source.applied_shares;
        in.load_force = source.applied.force;
      }
      in.rigid = !sb.body;
      if (sb.body) {
        in.physics_body = &*sb.body;
        in.physics_state = &sb.state;
      }
      in.surface_to_node = sb.surface_to_node;
      if (body.material) {
        const scene::Material& m = model_.materials[*body.material];
        in.material = {m.young_modulus, m.poisson_ratio, m.density};
      }
      in.frame_time = 1.0 / model_.rates.haptic;
      source.builders[best_body]->build(in, out);
    }
    d.patch->publish();
  }
}

void SimulationLoop::step(double t, Nanos deadline, Nanos start, bool real_time) {
  const double period = 1.0 / stats_.rate;
  int iterations = 0;
  if (live_) apply_live_parameters(t);
  if (step_ > 0) {
    // Scene loads and prescribed motions at the end of the period, then the newest contact
    // reaction of every device spread over the vertices around its contact point.
    const double t_end = static_cast<double>(step_) / stats_.rate;  // simulated time reached
    auto fraction = [t_end](double ramp_time) { return compile::ramp(t_end, ramp_time); };
    for (SimBody& sb : bodies_) {
      if (!sb.body) continue;
      const scene::Body& b = model_.bodies[sb.index];
      compile::assemble_loads(b, fraction, sb.f_ext);
      compile::place_prescribed(b, sb.rest, fraction, sb.state.x);
    }
    for (PatchSource& source : patch_sources_) source.applied = ContactLoad{}, source.applied_shares.clear();
    for (SimBody& sb : bodies_) sb.springs.clear();
    for (std::size_t device = 0; device < devices_.size(); ++device) {
      DeviceChannels* d = devices_[device];
      pushes_[device].spring = -1;
      d->load.update();
      const ContactLoad& load = d->load.read();
      if (load.shaft) push_along_shaft(load);
      if (!load.active || load.body < 0 || static_cast<std::size_t>(load.body) >= bodies_.size()) continue;
      SimBody& sb = bodies_[static_cast<std::size_t>(load.body)];
      if (model_.bodies[sb.index].host) {
        // A fascia sheet or a vessel wall: its host's tetrahedra take the load.
        carry_to_host(sb, spread(sb, load), load.force);
        continue;
      }
      if (!sb.body) continue;
      const std::span<const contact::LoadShare> shares = spread(sb, load);
      const double push = load.force.norm();
      if (push > 0.0 && sb.springs.size() < physics::kMaxContactSprings) {
        // Coupled into the step: the push eases as the tissue gives way under it.
        DevicePush& p = pushes_[device];
        p.nodes.clear();
        for (const contact::LoadShare& s : shares)
          p.nodes.push_back({sb.surface_to_node[static_cast<std::size_t>(s.vertex)], s.share});
        p.body = static_cast<std::size_t>(load.body);
        p.spring = static_cast<int>(sb.springs.size());
        // The push where the published surface stands (the step starts from it), not where
        // the haptic loop's patch had moved the contact point to.
        const double stiffness = std::max(0.0, load.stiffness);
        const double offset = stiffness * load.surface_offset;
        const double at_surface = std::isfinite(offset) ? push + offset : push;
        sb.springs.push_back({p.nodes, load.force / push, at_surface, stiffness, std::max(0.0, at_surface)});
      } else {
        for (const contact::LoadShare& s : shares)
          sb.f_ext.segment<3>(3 * static_cast<Eigen::Index>(sb.surface_to_node[static_cast<std::size_t>(s.vertex)])) +=
              s.share * load.force;
      }
      for (PatchSource& source : patch_sources_)
        if (source.channels == d) source.applied = load, source.applied_shares.assign(shares.begin(), shares.end());
    }
    const Nanos loads_done = now_ns();
    parts_[0].time.record(loads_done - start);

    for (SimBody& sb : bodies_) {
      if (!sb.body) continue;
      if (!patch_sources_.empty()) sb.x_before = sb.state.x;
      const double dt = period / sb.substeps;
      for (int k = 0; k < sb.substeps; ++k) {
        physics::step(*sb.body, sb.state, dt, sb.f_ext, sb.springs);
        for (physics::ContactSpring& c : sb.springs) c.force = c.force_end;
        iterations += sb.state.last_linear_iterations;
      }
      if (!sb.state.x.allFinite())
        throw std::runtime_error(fmt::format("body '{}' diverged at t = {} s (NaN or infinite positions); reduce "
                                             "its time_step, soften the contact or use implicit_euler",
                                             model_.bodies[sb.index].name, t_end));
    }
    // The patches are built around the push the tissue took at the end of the step.
    for (PatchSource& source : patch_sources_)
      for (std::size_t device = 0; device < devices_.size(); ++device)
        if (devices_[device] == source.channels && pushes_[device].spring >= 0) {
          const physics::ContactSpring& c =
              bodies_[pushes_[device].body].springs[static_cast<std::size_t>(pushes_[device].spring)];
          source.applied.force = c.force * c.direction;
        }
    const Nanos integrated = now_ns();
    parts_[1].time.record(integrated - loads_done);
  }
  update_cspace_shapes();
  const Nanos before_embedded = now_ns();
  update_embedded_shapes();
  const Nanos before_publish = now_ns();
  if (embedded_) parts_[4].time.record(before_publish - before_embedded);  // else the part stays unused
  publish(t);
  const Nanos end = now_ns();
  parts_[2].time.record(end - before_publish);
  if (!patch_sources_.empty()) {
    publish_patches(t);
    parts_[3].time.record(now_ns() - end);
  }
  ++step_;

  const Nanos compute = now_ns() - start;
  stats_.record(deadline, start, compute, real_time);
  SimulationStep rec;
  rec.step = step_ - 1;
  rec.t = t;
  rec.compute_ns = static_cast<std::uint32_t>(std::clamp<Nanos>(compute, 0, std::numeric_limits<std::uint32_t>::max()));
  rec.solver_iterations = static_cast<std::uint32_t>(iterations);
  rec.late_ns = real_time ? static_cast<std::int32_t>(std::clamp<Nanos>(start - deadline, 0, std::numeric_limits<std::int32_t>::max())) : 0;
  if (!steps_ring_.try_push(rec)) ++dropped_steps_;
}

}  // namespace tactus::runtime
