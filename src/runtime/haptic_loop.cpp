#include "runtime/haptic_loop.hpp"

#include <algorithm>
#include <limits>
#include <utility>

namespace tactus::runtime {

HapticLoop::HapticLoop(HapticConfig config, std::unique_ptr<haptics::Device> device,
                       DeviceChannels& channels)
    : config_(std::move(config)), device_(std::move(device)), channels_(channels),
      safety_(config_.safety), planes_(config_.plane_blend) {
  stats_.rate = config_.rate;
}

void HapticLoop::emit(double t, EventKind kind, double value) {
  channels_.events.try_push(LoopEvent{t, kind, config_.device, value});
}

void HapticLoop::step(double t, Nanos deadline, Nanos start, bool real_time) {
  const haptics::DevicePose pose = device_->read(t);
  const Nanos pose_read = now_ns();
  const Vec3 position = config_.map.to_scene(pose.position);
  const Quat orientation = config_.map.to_scene(pose.orientation);

  // Tool velocity for the contact damping: a first-order low-pass of finite differences,
  // since device positions are quantized and the raw difference is noisy at 1 kHz.
  const double dt = last_t_ >= 0.0 && t > last_t_ ? t - last_t_ : 1.0 / config_.rate;
  if (last_t_ >= 0.0 && t > last_t_) {
    const Vec3 raw = (position - last_position_) / dt;
    velocity_ += dt / (config_.velocity_filter + dt) * (raw - velocity_);
  }
  last_position_ = position;
  last_t_ = t;

  const bool fresh = channels_.contact.update();
  const LocalContact& contact = channels_.contact.read();

  Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
  bool touching = false;
  if (config_.proxy && !config_.spheres.empty()) {
    // God-object: the proxy slides on the local contact plane (blended towards each new one
    // over plane_blend, when that is set).
    const Vec3 arm = orientation * config_.spheres.front().offset;
    const Vec3 goal = position + arm;
    if (!proxy_started_) {
      proxy_state_ = contact::make_proxy_state(goal);
      proxy_started_ = true;
    }
    if (fresh && contact.valid) planes_.set_target({contact.normal, contact.normal.dot(contact.point)}, t);
    contact::ProxyResult r;
    if (contact.valid && planes_.has_plane()) {
      const contact::ConstraintPlane plane = planes_.at(t);
      r = contact::update_proxy(*config_.proxy, proxy_state_, goal, velocity_, dt,
                                contact::HalfSpaceQuery(plane.normal, plane.offset));
    } else {
      r = contact::update_proxy(*config_.proxy, proxy_state_, goal, velocity_, dt, no_surface_);
    }
    touching = r.in_contact;
    force = r.force;
    torque = arm.cross(force);
  } else if (contact.valid) {
    // Penetration of each contact sphere into the local contact plane.
    const double normal_speed = contact.normal.dot(velocity_);
    for (const HapticConfig::Sphere& sphere : config_.spheres) {
      const Vec3 arm = orientation * sphere.offset;
      const double depth = sphere.radius - contact.normal.dot(position + arm - contact.point);
      if (!(depth > 0.0)) continue;
      touching = true;
      const double elastic = config_.hertz       ? config_.hertz->evaluate(depth, contact.mean_curvature).force
                             : config_.fingerpad ? config_.fingerpad->force(depth)
                                                 : config_.stiffness * depth;
      const double fn = std::max(0.0, elastic - config_.damping * normal_speed);
      force += fn * contact.normal;
      torque += arm.cross(fn * contact.normal);
    }
  }

  haptics::SafetyInput in;
  in.force = config_.map.force_to_device(force);
  in.torque = config_.map.force_to_device(torque);
  in.contact = touching;
  in.last_simulation_update = contact.surface_time;
  in.device_alive = device_->alive();
  in.emergency_stop = emergency_stop_.load(std::memory_order_relaxed);
  const haptics::SafetyOutput out = safety_.apply(in, t);
  device_->write(out.force, out.torque);
  device_to_force_.record(now_ns() - pose_read);

  // The tissue feels what the hand feels: the reaction of the force actually sent.
  ContactLoad& load = channels_.load.write_buffer();
  load.active = touching && contact.valid;
  load.body = contact.body;
  load.triangle = contact.triangle;
  load.barycentric = contact.barycentric;
  load.force = -(config_.map.rotation * out.force);
  channels_.load.publish();

  ToolState& tool = channels_.tool.write_buffer();
  tool.position = position;
  tool.valid = true;
  channels_.tool.publish();

  if (touching != in_contact_) {
    emit(t, touching ? EventKind::contact_begin : EventKind::contact_end, out.force.norm());
    in_contact_ = touching;
  }
  const std::uint8_t rising = out.flags & static_cast<std::uint8_t>(~last_flags_);
  if (rising & haptics::kSafetyClamped) emit(t, EventKind::force_clamped, in.force.norm());
  if (rising & haptics::kSafetyNonFinite) emit(t, EventKind::non_finite_force, 0.0);
  if (rising & haptics::kSafetyWatchdog) emit(t, device_->alive() ? EventKind::watchdog_trip : EventKind::device_stall, 0.0);
  if (rising & haptics::kSafetyEmergencyStop) emit(t, EventKind::emergency_stop, 0.0);
  last_flags_ = out.flags;

  const Nanos compute = now_ns() - start;
  HapticFrame frame;
  frame.frame = frame_++;
  frame.t = t;
  frame.device = config_.device;
  frame.contact = touching ? 1 : 0;
  frame.flags = out.flags;
  frame.buttons = pose.buttons;
  frame.position = pose.position;
  frame.orientation = pose.orientation;
  frame.force = out.force;
  frame.torque = out.torque;
  frame.proxy = contact.valid ? contact.point : Vec3::Zero();
  frame.compute_ns = static_cast<std::uint32_t>(std::clamp<Nanos>(compute, 0, std::numeric_limits<std::uint32_t>::max()));
  frame.late_ns = real_time ? static_cast<std::int32_t>(std::clamp<Nanos>(start - deadline, std::numeric_limits<std::int32_t>::min(),
                                                                         std::numeric_limits<std::int32_t>::max()))
                            : 0;
  if (!channels_.frames.try_push(frame)) ++dropped_frames_;
  stats_.record(deadline, start, compute, real_time);
}

}  // namespace tactus::runtime
