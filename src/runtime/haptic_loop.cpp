#include "runtime/haptic_loop.hpp"

#include <algorithm>
#include <limits>
#include <utility>

#include "haptics/algorithms/needle_algorithm.hpp"
#include "runtime/live_parameters.hpp"

namespace tactus::runtime {
namespace {

EventKind event_kind(haptics::HapticEvent::Kind kind) {
  using K = haptics::HapticEvent::Kind;
  switch (kind) {
    case K::contact_begin: return EventKind::contact_begin;
    case K::contact_end: return EventKind::contact_end;
    case K::force_clamped: return EventKind::force_clamped;
    case K::non_finite_force: return EventKind::non_finite_force;
    case K::watchdog_trip: return EventKind::watchdog_trip;
    case K::device_stall: return EventKind::device_stall;
    case K::emergency_stop: return EventKind::emergency_stop;
    case K::rupture: return EventKind::rupture;
    case K::contact_state: return EventKind::contact_state;
    case K::level_switch: return EventKind::level_switch;
    case K::level_cost: return EventKind::level_cost;
  }
  return EventKind::note;
}

}  // namespace

HapticLoop::HapticLoop(haptics::HapticModel model, std::unique_ptr<haptics::Device> device, DeviceChannels& channels)
    : model_(std::move(model)), state_(model_), device_(std::move(device)), channels_(channels) {
  stats_.rate = model_.rate;
  sink_.loop = this;
  const haptics::ForceAlgorithm* contact = model_.contact();
  follows_tool_ = contact && contact->simulation_follows_tool();
}

const haptics::NeedleInsertion* HapticLoop::needle() const {
  std::size_t i = 0;
  return model_.find<haptics::NeedleAlgorithm>(&i) ? &haptics::NeedleAlgorithm::insertion(*state_.algorithms[i]) : nullptr;
}

void HapticLoop::DeviceSink::write(const Vec3& force, const Vec3& torque) {
  loop->device_->write(force, torque);
  loop->device_to_force_.record(now_ns() - pose_read);
}

void HapticLoop::emit(double t, const haptics::HapticEvent& e) {
  channels_.events.try_push(LoopEvent{t, event_kind(e.kind), model_.device, e.value, e.detail});
}

void HapticLoop::step(double t, Nanos deadline, Nanos start, bool real_time) {
  haptics::HapticInputs in;
  if (live_) {
    if (live_->emergency_stop_requested()) request_emergency_stop();
    if (model_.device < LiveParameters::kMaxDevices) {
      const LiveParameters::Surface s = live_->surface(model_.device);
      edit_.version = s.version;
      edit_.from = s.from;
      edit_.values = {s.stiffness, s.static_friction, s.kinetic_friction};
      edit_.max_stiffness = live_->max_stiffness(model_.device);
      in.edit = &edit_;
    }
  }
  in.t = t;
  in.pose = device_->read(t);
  sink_.pose_read = now_ns();
  in.contact_fresh = channels_.contact.update();
  in.contact = &channels_.contact.read();
  if (channels_.patch) {
    in.patch_fresh = channels_.patch->update();
    in.patch = &channels_.patch->read();
    in.patch_previous = &channels_.patch->previous();
  }
  in.surfaces_fresh = channels_.needle.update();
  in.surfaces = &channels_.needle.read();
  if (peer_) {
    peer_->update();
    in.peer = &peer_->read();
  }
  in.device_alive = device_->alive();
  in.emergency_stop = emergency_stop_.load(std::memory_order_relaxed);
  out_.load = &channels_.load.write_buffer();
  haptics::haptic_step(model_, state_, in, sink_, out_);
  channels_.load.publish();
  ToolState& tool = channels_.tool.write_buffer();
  tool.position = out_.position;
  tool.axis = out_.tool_axis;
  tool.valid = true;
  channels_.tool.publish();
  channels_.finger.write_buffer() = out_.finger;
  channels_.finger.publish();
  if (channels_.patch && in.patch->valid && in.patch->radius > 0.0) {
    const double fraction = (out_.position - in.patch->center).norm() / in.patch->radius;
    patch_reach_.max_fraction = std::max(patch_reach_.max_fraction, fraction);
    if (fraction > 1.0) ++patch_reach_.frames_outside;
  }
  if (follows_tool_) {
    ToolState& to_simulation = channels_.tool_to_simulation.write_buffer();
    to_simulation.position = out_.position;
    to_simulation.orientation = out_.orientation;
    to_simulation.valid = true;
    channels_.tool_to_simulation.publish();
  }
  for (int i = 0; i < out_.event_count; ++i) emit(t, out_.events[static_cast<std::size_t>(i)]);

  const Nanos compute = now_ns() - start;
  HapticFrame frame;
  frame.frame = frame_++;
  frame.t = t;
  frame.device = model_.device;
  frame.contact = out_.touching ? 1 : 0;
  frame.flags = out_.sent.flags;
  frame.buttons = in.pose.buttons;
  frame.position = in.pose.position;
  frame.orientation = in.pose.orientation;
  frame.force = out_.sent.force;
  frame.torque = out_.sent.torque;
  frame.proxy = out_.frame_point;
  frame.compute_ns = static_cast<std::uint32_t>(std::clamp<Nanos>(compute, 0, std::numeric_limits<std::uint32_t>::max()));
  frame.late_ns = real_time ? static_cast<std::int32_t>(std::clamp<Nanos>(start - deadline, std::numeric_limits<std::int32_t>::min(),
                                                                         std::numeric_limits<std::int32_t>::max()))
                            : 0;
  if (!channels_.frames.try_push(frame)) ++dropped_frames_;
  stats_.record(deadline, start, compute, real_time);
}

}  // namespace tactus::runtime
