#include "runtime/interaction_loop.hpp"

#include <stdexcept>

namespace tactus::runtime {

InteractionLoop::InteractionLoop(const scene::Model& model, std::vector<InteractionTarget> targets,
                                 std::vector<DeviceChannels*> channels, TripleBuffer<SurfaceSnapshot>& surfaces)
    : model_(make_interaction_model(model, std::move(targets))),
      state_(make_interaction_state(model_)),
      channels_(std::move(channels)),
      surfaces_(surfaces),
      tools_(model_.targets.size()),
      contacts_(model_.targets.size(), nullptr),
      needles_(model_.targets.size(), nullptr) {
  if (channels_.size() != model_.targets.size())
    throw std::invalid_argument("interaction loop: one channel set per target");
  stats_.name = "interaction";
  stats_.rate = model.rates.interaction;
  for (const InteractionTarget& target : model_.targets) {
    parts_.push_back({target.device + ": query per body", {}});
    parts_.push_back({target.device + ": interaction", {}});
  }
  parts_.push_back({"refit trees", {}});
}

void InteractionLoop::step(double /*t*/, Nanos deadline, Nanos start, bool real_time) {
  surfaces_.update();
  for (std::size_t k = 0; k < channels_.size(); ++k) {
    channels_[k]->tool.update();
    tools_[k] = channels_[k]->tool.read();
    contacts_[k] = &channels_[k]->contact.write_buffer();
    needles_[k] = model_.targets[k].needle_length > 0.0 ? &channels_[k]->needle.write_buffer() : nullptr;
  }
  InteractionInputs in;
  in.surfaces = &surfaces_.read();
  in.tools = tools_;
  in.clock = now_ns;
  interaction_step(model_, state_, in, {contacts_, needles_, parts_});
  for (std::size_t k = 0; k < channels_.size(); ++k) {
    if (needles_[k]) channels_[k]->needle.publish();
    channels_[k]->contact.publish();
  }
  stats_.record(deadline, start, now_ns() - start, real_time);
}

}  // namespace tactus::runtime
