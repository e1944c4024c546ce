#include "runtime/simulation_loop.hpp"

#include <algorithm>
#include <limits>

#include "runtime/live_parameters.hpp"

namespace tactus::runtime {
namespace {

std::vector<std::optional<PatchRequest>> patch_requests(const std::vector<DeviceChannels*>& devices) {
  std::vector<std::optional<PatchRequest>> requests;
  for (const DeviceChannels* d : devices) {
    if (d->patch) requests.emplace_back(d->patch_request);
    else requests.emplace_back();
  }
  return requests;
}

}  // namespace

SimulationLoop::SimulationLoop(const scene::Model& model, std::vector<DeviceChannels*> devices,
                               const compile::CspaceBodies& cspaces, const LiveParameters* live)
    : model_(make_simulation_model(model, patch_requests(devices), cspaces)),
      state_(make_simulation_state(model_, live)),
      devices_(std::move(devices)),
      live_(live),
      loads_(devices_.size()),
      tools_(devices_.size()),
      patches_(devices_.size(), nullptr),
      steps_ring_(1 << 14) {
  stats_.name = "simulation";
  stats_.rate = model.rates.simulation;
  parts_ = {{"contact loads", {}}, {"integrate", {}}, {"publish surfaces", {}}, {"local models", {}},
            {"embedded surfaces", {}}, {"shaft node search", {}}};
}

const VecX* SimulationLoop::positions(std::size_t body) const {
  return body < state_.bodies.size() ? &state_.bodies[body].state.x : nullptr;
}

void SimulationLoop::step(double t, Nanos deadline, Nanos start, bool real_time) {
  SimulationInputs in;
  in.t = t;
  in.clock = now_ns;
  in.start = start;
  LiveParameters::Materials materials;
  if (live_) {
    materials = live_->materials();
    in.materials = &materials;
    in.scene_materials = &live_->scene_materials();
  }
  if (state_.step > 0)
    for (std::size_t d = 0; d < devices_.size(); ++d) {
      devices_[d]->load.update();
      loads_[d] = devices_[d]->load.read();
    }
  in.loads = loads_;
  const int iterations = advance_bodies(model_, state_, in, parts_);

  // The tools as late as they come: the patches are cut around them.
  for (std::size_t d = 0; d < devices_.size(); ++d) {
    devices_[d]->tool_to_simulation.update();
    tools_[d] = devices_[d]->tool_to_simulation.read();
    patches_[d] = devices_[d]->patch ? &devices_[d]->patch->write_buffer() : nullptr;
  }
  surfaces_.resize(outputs_.size());  // outputs are added before the loop runs: sized once
  for (std::size_t o = 0; o < outputs_.size(); ++o) surfaces_[o] = &outputs_[o]->write_buffer();
  const std::uint64_t step = state_.step;
  publish_shapes(model_, state_, in, tools_, {surfaces_, patches_, parts_});
  for (auto* out : outputs_) out->publish();
  for (auto* out : node_outputs_) {
    write_nodes(model_, state_, t, out->write_buffer());
    out->write_buffer().step = step;
    out->publish();
  }
  for (DeviceChannels* d : devices_)
    if (d->patch) d->patch->publish();

  const Nanos compute = now_ns() - start;
  stats_.record(deadline, start, compute, real_time);
  SimulationStep rec;
  rec.step = step;
  rec.t = t;
  rec.compute_ns = static_cast<std::uint32_t>(std::clamp<Nanos>(compute, 0, std::numeric_limits<std::uint32_t>::max()));
  rec.solver_iterations = static_cast<std::uint32_t>(iterations);
  rec.late_ns = real_time ? static_cast<std::int32_t>(std::clamp<Nanos>(start - deadline, 0, std::numeric_limits<std::int32_t>::max())) : 0;
  if (!steps_ring_.try_push(rec)) ++dropped_steps_;
}

}  // namespace tactus::runtime
