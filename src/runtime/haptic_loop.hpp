#pragma once
// One device's haptic loop step: read the pose, render the contact force from the local
// model, pass it through the safety layer, send it, hand the reaction to the simulation
// and the frame to the recorder. No locks, no allocation, no exceptions after construction.
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "contact/hertz.hpp"
#include "contact/proxy.hpp"
#include "contact/surface_query.hpp"
#include "core/spsc_ring.hpp"
#include "core/triple_buffer.hpp"
#include "haptics/device.hpp"
#include "haptics/safety.hpp"
#include "runtime/exchange.hpp"
#include "runtime/loop_stats.hpp"
#include "runtime/recording.hpp"

namespace tactus::runtime {

/// An event raised by a loop (trivially copyable, unlike recording's Event with its text).
struct LoopEvent {
  double t = 0.0;
  EventKind kind = EventKind::note;
  std::uint16_t device = 0;
  double value = 0.0;
};

/// Channels between one device's haptic loop and the other loops.
struct DeviceChannels {
  explicit DeviceChannels(std::size_t ring_capacity)
      : tool(ToolState{}), contact(LocalContact{}), load(ContactLoad{}),
        frames(ring_capacity), events(1024) {}
  TripleBuffer<ToolState> tool;        ///< haptic → interaction
  TripleBuffer<LocalContact> contact;  ///< interaction → haptic
  TripleBuffer<ContactLoad> load;      ///< haptic → simulation
  SpscRing<HapticFrame> frames;        ///< haptic → recorder
  SpscRing<LoopEvent> events;          ///< haptic → recorder
};

struct HapticConfig {
  std::uint16_t device = 0;  ///< index into Model::devices
  double rate = 1000.0;      ///< [Hz]
  haptics::WorkspaceMap map;
  /// Contact spheres in the tool frame; empty = a tool that renders no force.
  struct Sphere {
    Vec3 offset = Vec3::Zero();  ///< [m]
    double radius = 0.0;         ///< [m]
  };
  std::vector<Sphere> spheres;
  /// Penalty stiffness of the plane contact when no other law below is set [N/m].
  double stiffness = 500.0;
  /// Pawluk & Howe fingerpad law (fingerpad); replaces `stiffness` when set.
  std::optional<contact::FingerpadLaw> fingerpad;
  /// Hertz contact with the tissue's curvature (hertz_finger); replaces `law` when set.
  std::optional<contact::HertzContact> hertz;
  /// God-object proxy with friction against the local contact plane (proxy); replaces
  /// `law` when set, and renders the first sphere.
  std::optional<contact::ProxyParams> proxy;
  /// The proxy's plane moves to each new local model over this time, so a simulation update
  /// is not felt as a force step (seed 003 §3.5) [s].
  double plane_blend = 0.0;
  double damping = 0.0;      ///< normal damping [N·s/m]
  /// Low-pass time constant of the tool velocity estimate used by the damping [s].
  double velocity_filter = 0.002;
  haptics::SafetyConfig safety;
};

class HapticLoop {
 public:
  HapticLoop(HapticConfig config, std::unique_ptr<haptics::Device> device, DeviceChannels& channels);

  /// One frame at time t. `deadline` and `start` are for the statistics (steady clock,
  /// or virtual nanoseconds in lockstep).
  void step(double t, Nanos deadline, Nanos start, bool real_time);

  /// Safe to call from any thread.
  void request_emergency_stop() { emergency_stop_.store(true, std::memory_order_relaxed); }
  [[nodiscard]] bool finished(double t) const { return device_->finished(t); }
  [[nodiscard]] const LoopStats& stats() const { return stats_; }
  /// Time from the pose read returning to the force written: the loop's own latency.
  [[nodiscard]] const LatencyHistogram& device_to_force() const { return device_to_force_; }
  [[nodiscard]] haptics::SafetyCounters safety_counters() const { return safety_.counters(); }
  [[nodiscard]] std::uint64_t dropped_frames() const { return dropped_frames_; }
  [[nodiscard]] const haptics::Device& device() const { return *device_; }

 private:
  void emit(double t, EventKind kind, double value);

  HapticConfig config_;
  std::unique_ptr<haptics::Device> device_;
  DeviceChannels& channels_;
  haptics::ForceSafety safety_;
  LoopStats stats_;
  LatencyHistogram device_to_force_;
  std::uint64_t frame_ = 0;
  std::uint64_t dropped_frames_ = 0;
  bool in_contact_ = false;
  std::atomic<bool> emergency_stop_{false};
  std::uint8_t last_flags_ = 0;
  contact::ProxyState proxy_state_;
  contact::PlaneInterpolator planes_;
  contact::BruteForceSurfaceQuery no_surface_{{}, {}};
  bool proxy_started_ = false;
  Vec3 last_position_ = Vec3::Zero();
  Vec3 velocity_ = Vec3::Zero();
  double last_t_ = -1.0;
};

}  // namespace tactus::runtime
