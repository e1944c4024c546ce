#pragma once
// The last stage before a force reaches a person's hand. One ForceSafety per device, called
// once per haptic frame on the haptic thread: no allocation, no locks, no exceptions.
//
// Whatever comes in, what goes out is finite, within max_force / max_torque, and changes
// gradually at contact changes and simulation stalls:
//  - non-finite force or torque → both replaced by zero;
//  - magnitude clamped to the limit, direction kept;
//  - contact onset: the output blends from the force sent last (zero after a finished
//    release) to the contact force over ramp_time;
//  - contact release: the output blends from the last contact force to the incoming
//    (free-space, usually zero) force over ramp_time;
//  so the force sent is continuous at every contact change, however often the flag flips;
//  - watchdog (simulation silent for more than watchdog_timeout, or the device not alive):
//    the output fades to zero over fade_time, and ramps back in over ramp_time when fresh;
//  - emergency stop: zero from that frame on, latched until reset_emergency_stop().
#include <cstdint>

#include "core/math.hpp"

namespace tactus::haptics {

struct SafetyConfig {
  double max_force = 10.0;         ///< [N]
  double max_torque = 1.0;         ///< [N·m]
  double ramp_time = 0.005;        ///< [s] contact ramp in / out, recovery after a stall
  double fade_time = 0.05;         ///< [s] fade out while the watchdog holds
  double watchdog_timeout = 0.1;   ///< [s] simulation silence that trips the watchdog
};

struct SafetyInput {
  Vec3 force = Vec3::Zero();   ///< [N], device coordinates
  Vec3 torque = Vec3::Zero();  ///< [N·m]
  bool contact = false;
  double last_simulation_update = 0.0;  ///< [s] time the simulation last published
  bool device_alive = true;
  bool emergency_stop = false;
};

/// Bits of SafetyOutput::flags.
inline constexpr std::uint8_t kSafetyClamped = 1;        ///< force or torque was above its limit
inline constexpr std::uint8_t kSafetyNonFinite = 2;      ///< a NaN or Inf was replaced by zero
inline constexpr std::uint8_t kSafetyRamping = 4;        ///< a ramp in or out is in progress
inline constexpr std::uint8_t kSafetyWatchdog = 8;       ///< simulation stalled or device not alive
inline constexpr std::uint8_t kSafetyEmergencyStop = 16; ///< emergency stop latched

struct SafetyOutput {
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();
  std::uint8_t flags = 0;
};

/// Events since construction: frames for clamped / non_finite, episodes for the rest.
struct SafetyCounters {
  std::uint64_t clamped = 0;          ///< frames with force or torque clamped
  std::uint64_t non_finite = 0;       ///< frames with a non-finite input (or time)
  std::uint64_t ramp_in = 0;          ///< ramps in started: contact onsets and recoveries
  std::uint64_t ramp_out = 0;         ///< contact releases
  std::uint64_t watchdog_trips = 0;   ///< simulation stalls (one per stall)
  std::uint64_t device_stalls = 0;    ///< device-not-alive episodes
  std::uint64_t emergency_stops = 0;  ///< times the emergency stop latched
};

class ForceSafety {
 public:
  /// Throws InputError for a limit that is not positive and finite or a negative time.
  explicit ForceSafety(const SafetyConfig& config);

  /// The force and torque to send at time t [s] (non-decreasing between calls).
  SafetyOutput apply(const SafetyInput& input, double t);

  void reset_emergency_stop();
  [[nodiscard]] bool emergency_stopped() const { return emergency_latched_; }
  [[nodiscard]] SafetyCounters counters() const { return counters_; }
  [[nodiscard]] const SafetyConfig& config() const { return config_; }

 private:
  SafetyConfig config_;
  SafetyCounters counters_;
  double force_limit_;   ///< max_force a few ulps under, so rounding never exceeds it
  double torque_limit_;

  bool started_ = false;
  double last_t_ = 0.0;
  bool contact_ = false;
  double onset_t_ = 0.0;
  Vec3 onset_force_ = Vec3::Zero();     ///< the contact stage's output the frame before onset
  Vec3 onset_torque_ = Vec3::Zero();
  bool releasing_ = false;
  double release_t_ = 0.0;
  Vec3 release_force_ = Vec3::Zero();
  Vec3 release_torque_ = Vec3::Zero();
  Vec3 contact_force_ = Vec3::Zero();   ///< last output of the contact stage
  Vec3 contact_torque_ = Vec3::Zero();
  double availability_ = 1.0;  ///< watchdog gain: 1 fresh, falls to 0 while stalled
  bool sim_stalled_ = false;
  bool device_stalled_ = false;
  bool emergency_latched_ = false;
};

}  // namespace tactus::haptics
