#include "runtime/haptic_loop.hpp"

#include <algorithm>
#include <limits>
#include <utility>

namespace tactus::runtime {

HapticLoop::HapticLoop(HapticConfig config, std::unique_ptr<haptics::Device> device,
                       DeviceChannels& channels)
    : config_(std::move(config)), device_(std::move(device)), channels_(channels),
      safety_(config_.safety), planes_(config_.plane_blend), smoother_(config_.force_smoothing),
      passivity_(config_.passivity_control) {
  stats_.rate = config_.rate;
  // Sized from the channel's own request, so a patch copied out of it never reallocates.
  if (channels_.patch) local_.emplace(channels_.patch_request.kind, channels_.patch_request.capacity);
  if (config_.needle) needle_.emplace(*config_.needle);
  if (config_.multi_surface) multi_surface_.emplace(config_.multi_surface->force);
}

void HapticLoop::emit(double t, EventKind kind, double value, std::int32_t detail) {
  channels_.events.try_push(LoopEvent{t, kind, config_.device, value, detail});
}

double HapticLoop::law_force(double depth, double mean_curvature) const {
  return config_.hertz       ? config_.hertz->evaluate(depth, mean_curvature).force
         : config_.fingerpad ? config_.fingerpad->force(depth)
                             : config_.stiffness * depth;
}

HapticLoop::Rendered HapticLoop::render_plane(const LocalContact& contact, contact::ProxyState& proxy,
                                              const Vec3& position, const Quat& orientation, double t, double dt,
                                              bool use_interpolator) {
  Rendered out;
  out.point = contact.point;
  if (config_.proxy && !config_.spheres.empty()) {
    // God-object: the proxy slides on the local contact plane (blended towards each new one
    // over plane_blend, when that is set).
    const Vec3 arm = orientation * config_.spheres.front().offset;
    const Vec3 goal = position + arm;
    contact::ProxyResult r;
    const bool has_plane = use_interpolator ? planes_.has_plane() : true;
    if (contact.valid && has_plane) {
      const contact::ConstraintPlane plane =
          use_interpolator ? planes_.at(t) : contact::ConstraintPlane{contact.normal, contact.normal.dot(contact.point)};
      r = contact::update_proxy(*config_.proxy, proxy, goal, velocity_, dt,
                                contact::HalfSpaceQuery(plane.normal, plane.offset));
    } else {
      r = contact::update_proxy(*config_.proxy, proxy, goal, velocity_, dt, no_surface_);
    }
    out.touching = r.in_contact;
    out.force = r.force;
    out.torque = arm.cross(out.force);
    out.contact_radius = contact::sphere_contact_radius(config_.proxy->radius, r.depth);
  } else if (contact.valid) {
    // Penetration of each contact sphere into the local contact plane.
    const double normal_speed = contact.normal.dot(velocity_);
    for (const HapticConfig::Sphere& sphere : config_.spheres) {
      const Vec3 arm = orientation * sphere.offset;
      const double depth = sphere.radius - contact.normal.dot(position + arm - contact.point);
      if (!(depth > 0.0)) continue;
      out.touching = true;
      out.contact_radius = std::max(out.contact_radius, contact::sphere_contact_radius(sphere.radius, depth));
      const double fn = std::max(0.0, law_force(depth, contact.mean_curvature) - config_.damping * normal_speed);
      out.force += fn * contact.normal;
      out.torque += arm.cross(fn * contact.normal);
    }
  }
  return out;
}

HapticLoop::Rendered HapticLoop::render_patch(const LocalContact& contact, contact::ProxyState& proxy,
                                              const Vec3& position, const Quat& orientation, double dt) {
  Rendered out;
  const contact::SurfaceQuery& surface = local_->valid() ? local_->surface() : no_surface_;
  if (config_.proxy && !config_.spheres.empty()) {
    const Vec3 arm = orientation * config_.spheres.front().offset;
    const contact::ProxyResult r = contact::update_proxy(*config_.proxy, proxy, position + arm, velocity_, dt, surface);
    out.touching = r.in_contact;
    out.force = r.force;
    out.torque = arm.cross(out.force);
    if (r.in_contact && r.triangle >= 0) {
      out.point = r.contact_point;
      out.contact_radius = contact::sphere_contact_radius(config_.proxy->radius, r.depth);
      // The proxy may rest on several faces at once (in a dent): the coupling force, not the
      // closest face's normal, is the direction the tissue is pushed.
      const double magnitude = r.force.norm();
      const Vec3 direction = magnitude > 0.0 ? Vec3(r.force / magnitude) : r.contact_normal;
      out.law_force = magnitude;
      out.on_patch = {r.triangle, r.barycentric, direction, out.law_force, config_.proxy->stiffness, disc_radius(out.contact_radius)};
    }
    return out;
  }
  sphere_contact_count_ = 0;
  if (!local_->valid()) return out;
  // Every sphere against the patch's current triangles: each sphere's own contact dents the
  // patch, and goes to the simulation with its share of the load (step()); the deepest one's
  // is the frame's contact point.
  double deepest = 0.0;
  for (const HapticConfig::Sphere& sphere : config_.spheres) {
    const Vec3 arm = orientation * sphere.offset;
    const Vec3 centre = position + arm;
    const contact::ClosestSurfacePoint p = surface.closest_point(centre);
    if (!p.found) continue;
    const double signed_distance = p.behind ? -p.distance : p.distance;
    const double depth = sphere.radius - signed_distance;
    if (!(depth > 0.0)) continue;
    const Vec3 normal = !p.behind && p.distance > 1e-12 ? Vec3((centre - p.point) / p.distance) : p.normal;
    const double elastic = law_force(depth, contact.mean_curvature);
    const double fn = std::max(0.0, elastic - config_.damping * normal.dot(velocity_));
    out.touching = true;
    out.force += fn * normal;
    out.torque += arm.cross(fn * normal);
    out.law_force += fn;
    constexpr double kProbe = 1e-6;  // [m]: the law's slope by a forward difference
    const double slope = std::max(0.0, (law_force(depth + kProbe, contact.mean_curvature) - elastic) / kProbe);
    if (sphere_contact_count_ < contact::LocalModel::kMaxContacts)
      sphere_contacts_[static_cast<std::size_t>(sphere_contact_count_++)] = {
          p.triangle, p.barycentric, normal, fn, slope, disc_radius(contact::sphere_contact_radius(sphere.radius, depth))};
    if (depth > deepest) {
      deepest = depth;
      out.point = p.point;
      out.contact_radius = contact::sphere_contact_radius(sphere.radius, depth);
      out.on_patch = {p.triangle, p.barycentric, normal, 0.0, slope, disc_radius(out.contact_radius)};
    }
  }
  out.on_patch.force = out.law_force;
  return out;
}

void HapticLoop::step(double t, Nanos deadline, Nanos start, bool real_time) {
  if (live_) apply_live_parameters(t);
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
  if (config_.proxy && !proxy_started_ && !config_.spheres.empty()) {
    proxy_state_ = contact::make_proxy_state(position + orientation * config_.spheres.front().offset);
    proxy_started_ = true;
  }

  Rendered rendered;
  double surface_time = contact.surface_time;
  if (needle_) {
    rendered = render_needle(position, orientation, t);
  } else if (multi_surface_) {
    rendered = render_multi_surface(position, orientation, t);
  } else if (config_.cspace) {
    const Vec3 arm = config_.spheres.empty() ? Vec3::Zero() : Vec3(orientation * config_.spheres.front().offset);
    const CspaceForce f = config_.cspace->force(position + arm, t);
    rendered.force = f.force;
    rendered.torque = arm.cross(f.force);
    rendered.touching = f.touching;
    rendered.point = position + arm;
  } else if (local_) {
    // A patch model: deformed between simulation steps at this rate.
    const bool fresh_patch = channels_.patch->update();
    if (fresh_patch) {
      // The step is smoothed only from one model to the next, not from none at start.
      const bool smooth = smoother_.enabled() && local_->valid();
      Vec3 before = Vec3::Zero();
      if (smooth) {
        local_->extrapolate(t);
        contact::ProxyState trial = proxy_state_;
        before = render_patch(contact, trial, position, orientation, dt).force;
      }
      local_->reset(channels_.patch->read(), t);
      // The proxy remembers triangles by index, and indices name other triangles in a new patch.
      proxy_state_.side_triangle = -1;
      proxy_state_.side = 0;
      proxy_state_.anchor_triangle = -1;
      rendered = render_patch(contact, proxy_state_, position, orientation, dt);
      if (smooth) smoother_.model_changed(before, rendered.force);
    } else {
      local_->extrapolate(t);
      rendered = render_patch(contact, proxy_state_, position, orientation, dt);
    }
    surface_time = local_->patch().time;
  } else {
    if (config_.proxy && fresh && contact.valid) planes_.set_target({contact.normal, contact.normal.dot(contact.point)}, t);
    if (fresh && smoother_.enabled() && shown_contact_.valid) {
      contact::ProxyState trial = proxy_state_;
      const Vec3 before = render_plane(shown_contact_, trial, position, orientation, t, dt, false).force;
      rendered = render_plane(contact, proxy_state_, position, orientation, t, dt, config_.plane_blend > 0.0);
      smoother_.model_changed(before, rendered.force);
    } else {
      rendered = render_plane(contact, proxy_state_, position, orientation, t, dt, config_.plane_blend > 0.0);
    }
    shown_contact_ = contact;
  }
  const bool touching = rendered.touching;
  const Vec3 force =
      passivity_.apply(smoother_.apply(rendered.force, position, velocity_, dt), touching, position, velocity_, dt);
  const Vec3 torque = rendered.torque;

  haptics::SafetyInput in;
  // The pulse joins the contact force after the smoothing: its beats are no model update.
  const Vec3 pulse = pulse_force(t, position, orientation, force, touching);
  in.force = config_.map.force_to_device(force + pulse);
  in.torque = config_.map.force_to_device(torque);
  in.contact = touching;
  in.last_simulation_update = surface_time;
  in.device_alive = device_->alive();
  in.emergency_stop = emergency_stop_.load(std::memory_order_relaxed);
  const haptics::SafetyOutput out = safety_.apply(in, t);
  device_->write(out.force, out.torque);
  device_to_force_.record(now_ns() - pose_read);

  // The tissue feels what the hand feels: the reaction of the force actually sent, less the
  // pulse (the vessel beneath pushes that), scaled as the safety layer scaled the total.
  const double in_norm = in.force.norm();
  const double kept = in_norm > 0.0 ? std::min(1.0, out.force.norm() / in_norm) : 0.0;
  const Vec3 sent = config_.map.rotation * out.force - kept * pulse;
  passivity_.record_sent(sent);
  ContactLoad& load = channels_.load.write_buffer();
  load.part_count = 0;
  if (needle_) {
    needle_load(load, touching);
  } else if (multi_surface_) {
    multi_surface_load(load, touching);
  } else if (local_) {
    const contact::LocalPatch& patch = local_->patch();
    contact::PatchContact on_patch = rendered.on_patch;
    const bool on = touching && patch.valid && on_patch.triangle >= 0 && on_patch.triangle < patch.triangle_count;
    load.active = on;
    load.body = patch.body;
    load.triangle = on ? patch.surface_triangle[static_cast<std::size_t>(on_patch.triangle)] : -1;
    load.barycentric = on_patch.barycentric;
    // The patch moves under the force sent (ramped, clamped), its law's slope scaled alike.
    if (on) {
      const double sent_normal = std::max(0.0, sent.dot(on_patch.normal));
      if (rendered.law_force > 0.0) on_patch.stiffness *= std::min(1.0, sent_normal / rendered.law_force);
      on_patch.force = sent_normal;
    } else {
      on_patch.triangle = -1;
    }
    if (on && !config_.proxy && sphere_contact_count_ > 1) {
      // A sphere-set finger: each touching sphere dents the patch under its own force, all
      // scaled as the safety layer scaled the total.
      const double rendered_norm = rendered.force.norm();
      const double scale = rendered_norm > 0.0 ? std::clamp(sent.norm() / rendered_norm, 0.0, 1.0) : 0.0;
      for (int i = 0; i < sphere_contact_count_; ++i) {
        sphere_contacts_[static_cast<std::size_t>(i)].force *= scale;
        sphere_contacts_[static_cast<std::size_t>(i)].stiffness *= scale;
      }
      local_->advance({sphere_contacts_.data(), static_cast<std::size_t>(sphere_contact_count_)}, dt);
      // The tissue takes each sphere's force where that sphere touches, in proportion.
      double total = 0.0;
      for (int i = 0; i < sphere_contact_count_; ++i) total += sphere_contacts_[static_cast<std::size_t>(i)].force;
      for (int i = 0; i < sphere_contact_count_ && i < ContactLoad::kMaxParts && total > 0.0; ++i) {
        const contact::PatchContact& c = sphere_contacts_[static_cast<std::size_t>(i)];
        if (c.triangle < 0 || c.triangle >= patch.triangle_count || !(c.force > 0.0)) continue;
        load.parts[static_cast<std::size_t>(load.part_count++)] = {
            patch.surface_triangle[static_cast<std::size_t>(c.triangle)], c.barycentric, c.force / total,
            c.contact_radius};
      }
    } else {
      local_->advance(on_patch, dt);
    }
    // The proxy rests on the surface, so it rides with the contact point: the implicit force
    // solve in advance() settled the force counting on exactly that motion. Left behind, a
    // patch springing back would pass through the proxy.
    if (on && config_.proxy) proxy_state_.position += local_->contact_motion();
  } else {
    load.active = touching && contact.valid && !config_.cspace;  // a space takes no loads
    load.body = contact.body;
    load.triangle = contact.triangle;
    load.barycentric = contact.barycentric;
  }
  load.force = -sent;
  load.shaft = false;
  if (needle_ && touching && needle_out_.shaft && load.body >= 0) {
    // The lateral spring's reaction goes along the shaft; the point load keeps the rest.
    const Vec3 lateral = kept * needle_out_.lateral_force;
    load.shaft = true;
    load.shaft_from = needle_out_.shaft_from;
    load.shaft_to = position;
    load.shaft_force = -lateral;
    load.force += lateral;
  }
  load.contact_radius = config_.spread_over_contact_disc ? rendered.contact_radius : -1.0;
  channels_.load.publish();

  ToolState& tool = channels_.tool.write_buffer();
  tool.position = position;
  tool.axis = needle_axis_;
  tool.valid = true;
  channels_.tool.publish();
  if (local_ || config_.cspace) {
    ToolState& to_simulation = channels_.tool_to_simulation.write_buffer();
    to_simulation.position = position;
    to_simulation.valid = true;
    channels_.tool_to_simulation.publish();
  }

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
  frame.proxy = local_ ? (touching ? rendered.point : Vec3::Zero()) : (contact.valid ? contact.point : Vec3::Zero());
  frame.compute_ns = static_cast<std::uint32_t>(std::clamp<Nanos>(compute, 0, std::numeric_limits<std::uint32_t>::max()));
  frame.late_ns = real_time ? static_cast<std::int32_t>(std::clamp<Nanos>(start - deadline, std::numeric_limits<std::int32_t>::min(),
                                                                         std::numeric_limits<std::int32_t>::max()))
                            : 0;
  if (!channels_.frames.try_push(frame)) ++dropped_frames_;
  stats_.record(deadline, start, compute, real_time);
}

}  // namespace tactus::runtime
