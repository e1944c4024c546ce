#include "haptics/safety.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tactus::haptics {
namespace {

// Clamped forces land this far (relative) under the limit, so the rounding of later
// blends and gains can never push a force over it.
constexpr double kLimitMargin = 1e-12;

void require(bool ok, const char* key, double value, const char* what) {
  if (!ok) throw InputError(fmt::format("force safety: {} must be {}, got {}", key, what, value));
}

/// Scales v onto the sphere of radius `limit` when it is longer; returns whether it was
/// longer than `max_norm`. Works on 1e300 components too: the norm is taken after dividing by
/// the largest component, so it cannot overflow.
bool clamp_magnitude(Vec3& v, double max_norm, double limit) {
  const double largest = v.cwiseAbs().maxCoeff();
  if (!(largest > 0.5 * limit)) return false;  // then |v| ≤ √3/2 · limit
  const Vec3 unit_box = v / largest;             // components in [−1, 1], norm in [1, √3]
  const double length = unit_box.norm();
  if (largest <= limit / length) return false;
  v = unit_box * (limit / length);
  return largest > max_norm / length;
}

// Ramps count as done this close to their end, so that a ramp of exactly N frames does not
// leave a 0.9999999 tail frame behind through rounding of the frame times.
constexpr double kRampSnap = 1e-9;

/// Snaps a gain to exactly 0 or 1 when it is within kRampSnap of it.
double snap(double gain) {
  if (gain >= 1.0 - kRampSnap) return 1.0;
  if (gain <= kRampSnap) return 0.0;
  return gain;
}

/// Fraction of a ramp of `span` seconds done after `elapsed` seconds; a zero span is done.
double ramp_fraction(double elapsed, double span) {
  return span > 0.0 ? snap(std::clamp(elapsed / span, 0.0, 1.0)) : 1.0;
}

}  // namespace

ForceSafety::ForceSafety(const SafetyConfig& config)
    : config_(config),
      force_limit_(config.max_force * (1.0 - kLimitMargin)),
      torque_limit_(config.max_torque * (1.0 - kLimitMargin)) {
  require(std::isfinite(config.max_force) && config.max_force > 0.0, "max_force", config.max_force, "positive");
  require(std::isfinite(config.max_torque) && config.max_torque >= 0.0, "max_torque", config.max_torque,
          "finite and not negative");
  require(std::isfinite(config.ramp_time) && config.ramp_time >= 0.0, "ramp_time", config.ramp_time,
          "finite and not negative");
  require(std::isfinite(config.fade_time) && config.fade_time >= 0.0, "fade_time", config.fade_time,
          "finite and not negative");
  require(std::isfinite(config.watchdog_timeout) && config.watchdog_timeout > 0.0, "watchdog_timeout",
          config.watchdog_timeout, "positive");
}

void ForceSafety::reset_emergency_stop() {
  if (!emergency_latched_) return;
  emergency_latched_ = false;
  availability_ = 0.0;  // come back with a ramp, not a step
  ++counters_.ramp_in;
}

SafetyOutput ForceSafety::apply(const SafetyInput& in, double t) {
  SafetyOutput out;
  if (in.emergency_stop && !emergency_latched_) {
    emergency_latched_ = true;
    ++counters_.emergency_stops;
  }
  if (!std::isfinite(t)) {
    // No time, no ramps: send nothing this frame and leave the state as it was.
    ++counters_.non_finite;
    out.flags = kSafetyNonFinite | (emergency_latched_ ? kSafetyEmergencyStop : 0);
    return out;
  }
  const double dt = started_ ? std::max(t - last_t_, 0.0) : 0.0;
  last_t_ = started_ ? std::max(last_t_, t) : t;
  started_ = true;

  // 1. Finite and within limits.
  Vec3 force = in.force;
  Vec3 torque = in.torque;
  if (!force.allFinite() || !torque.allFinite()) {
    force.setZero();
    torque.setZero();
    out.flags |= kSafetyNonFinite;
    ++counters_.non_finite;
  }
  const bool force_clamped = clamp_magnitude(force, config_.max_force, force_limit_);
  const bool torque_clamped = clamp_magnitude(torque, config_.max_torque, torque_limit_);
  if (force_clamped || torque_clamped) {
    out.flags |= kSafetyClamped;
    ++counters_.clamped;
  }

  // 2. Contact changes: ramp in at onset, blend out from the last contact force at release.
  if (in.contact && !contact_) {
    // From the force sent last, not from zero: a contact that comes back while its release
    // is still blending out goes on from where the hand is, instead of dropping the force.
    onset_t_ = t;
    onset_force_ = contact_force_;
    onset_torque_ = contact_torque_;
    releasing_ = false;
    ++counters_.ramp_in;
  } else if (!in.contact && contact_) {
    releasing_ = true;
    release_t_ = t;
    release_force_ = contact_force_;
    release_torque_ = contact_torque_;
    ++counters_.ramp_out;
  }
  contact_ = in.contact;
  if (contact_) {
    const double gain = ramp_fraction(t - onset_t_, config_.ramp_time);
    force = (1.0 - gain) * onset_force_ + gain * force;
    torque = (1.0 - gain) * onset_torque_ + gain * torque;
    if (gain < 1.0) out.flags |= kSafetyRamping;
  } else if (releasing_) {
    const double s = ramp_fraction(t - release_t_, config_.ramp_time);
    force = (1.0 - s) * release_force_ + s * force;
    torque = (1.0 - s) * release_torque_ + s * torque;
    releasing_ = s < 1.0;
    if (releasing_) out.flags |= kSafetyRamping;
  }
  contact_force_ = force;
  contact_torque_ = torque;

  // 3. Watchdog: fade out while the simulation or the device is silent, ramp back after.
  // Written so that a missing (non-finite) timestamp counts as stale.
  const bool sim_stalled = !std::isfinite(in.last_simulation_update) ||
                           !(t - in.last_simulation_update <= config_.watchdog_timeout);
  const bool device_stalled = !in.device_alive;
  const bool was_faulted = sim_stalled_ || device_stalled_;
  if (sim_stalled && !sim_stalled_) ++counters_.watchdog_trips;
  if (device_stalled && !device_stalled_) ++counters_.device_stalls;
  sim_stalled_ = sim_stalled;
  device_stalled_ = device_stalled;
  if (sim_stalled || device_stalled) {
    availability_ = config_.fade_time > 0.0 ? snap(std::max(availability_ - dt / config_.fade_time, 0.0)) : 0.0;
    out.flags |= kSafetyWatchdog;
  } else {
    if (was_faulted && availability_ < 1.0) ++counters_.ramp_in;
    availability_ = config_.ramp_time > 0.0 ? snap(std::min(availability_ + dt / config_.ramp_time, 1.0)) : 1.0;
    if (availability_ < 1.0) out.flags |= kSafetyRamping;
  }

  // 4. Emergency stop wins over everything until reset.
  if (emergency_latched_) {
    out.flags |= kSafetyEmergencyStop;
    return out;
  }
  out.force = availability_ * force;
  out.torque = availability_ * torque;
  return out;
}

}  // namespace tactus::haptics
