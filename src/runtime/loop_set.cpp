#include "runtime/loop_set.hpp"

#include "compile/device_setup.hpp"
#include "runtime/devices.hpp"
#include "runtime/live_parameters.hpp"

namespace tactus::runtime {
namespace {

constexpr std::size_t kFrameRingCapacity = 1 << 15;

}  // namespace

Loops build_loops(const scene::Model& m, const SessionOptions& o) {
  Loops loops;
  std::vector<InteractionTarget> targets;
  std::vector<DeviceChannels*> target_channels;
  // Loaded once: an on-line space's solver threads serve the haptic and simulation loops alike.
  loops.cspaces = compile::load_cspace_bodies(m);
  const compile::CspaceBodies& cspaces = loops.cspaces;
  // Built once: every device touches (and the viewer paints) the same objects.
  loops.touchables = o.touchables ? *o.touchables : compile::load_touchables(m);
  for (std::size_t i = 0; i < m.devices.size(); ++i) {
    compile::DeviceSetup setup = compile::setup_device(m, i, cspaces, &loops.touchables);
    if (o.customize_haptics) o.customize_haptics(m, i, setup.model);
    std::unique_ptr<haptics::Device> device;
    if (const auto it = o.replay.find(m.devices[i].name); it != o.replay.end())
      device = std::make_unique<haptics::ReplayDevice>(it->second.poses, compile::device_limits(m.devices[i]), it->second.source);
    else if (o.device_override)
      device = o.device_override(m, i);
    if (!device) device = make_device(m, i, static_cast<unsigned>(i));
    loops.channels.push_back(std::make_unique<DeviceChannels>(kFrameRingCapacity));
    DeviceChannels& ch = *loops.channels.back();
    if (setup.renders && setup.local_model != contact::LocalModelKind::plane)
      ch.request_patches({setup.local_model, setup.patch_capacity, setup.patch_radius, setup.bodies});
    if (setup.renders) {
      targets.push_back({m.devices[i].name, setup.bodies, setup.reach, setup.curvature_rings, setup.needle_length});
      target_channels.push_back(&ch);
    }
    if (o.live) o.live->describe_device(i, setup.model, m.devices[i].max_stiffness);
    loops.haptic.push_back(std::make_unique<HapticLoop>(std::move(setup.model), std::move(device), ch));
    if (o.live) loops.haptic.back()->set_live_parameters(o.live);
  }
  if (o.live) o.live->devices_described();
  // Two-finger algorithms read their partner's frames; each finger has one partner (the scene
  // pairs them both ways), so each channel has one reader.
  for (auto& h : loops.haptic)
    if (const auto partner = h->model().partner) h->set_partner(&loops.channels[*partner]->finger);
  // The simulation publishes into a buffer pre-sized with the rest surfaces.
  loops.simulation = std::make_unique<SimulationLoop>(m, loops.channel_ptrs(), cspaces, o.live);
  loops.surfaces = std::make_unique<TripleBuffer<SurfaceSnapshot>>(loops.simulation->initial_snapshot());
  loops.simulation->add_output(*loops.surfaces);
  if (o.visual) loops.simulation->add_output(o.visual->surface_buffer(loops.simulation->initial_snapshot()));
  loops.interaction = std::make_unique<InteractionLoop>(m, std::move(targets), std::move(target_channels), *loops.surfaces);
  if (o.vtk) {
    loops.nodes = std::make_unique<TripleBuffer<NodeSnapshot>>(loops.simulation->initial_nodes());
    loops.simulation->add_node_output(*loops.nodes);
    std::vector<const physics::Body*> bodies;
    for (std::size_t b = 0; b < m.bodies.size(); ++b) bodies.push_back(loops.simulation->body(b));
    loops.vtk = std::make_unique<VtkSeries>(m, *o.vtk, o.vtk_rate, std::move(bodies));
  }
  return loops;
}

}  // namespace tactus::runtime
