#pragma once
// One device's haptic loop step: read the pose, render the contact force from the local
// model, pass it through the safety layer, send it, hand the reaction to the simulation
// and the frame to the recorder. No locks, no allocation, no exceptions after construction.
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "contact/hertz.hpp"
#include "contact/local_model.hpp"
#include "contact/proxy.hpp"
#include "contact/surface_query.hpp"
#include "core/spsc_ring.hpp"
#include "core/triple_buffer.hpp"
#include "haptics/algorithms/multi_surface.hpp"
#include "haptics/algorithms/needle.hpp"
#include "haptics/algorithms/pulse.hpp"
#include "haptics/device.hpp"
#include "haptics/safety.hpp"
#include "runtime/cspace_body.hpp"
#include "runtime/exchange.hpp"
#include "runtime/force_smoothing.hpp"
#include "runtime/passivity_control.hpp"
#include "runtime/loop_stats.hpp"
#include "runtime/recording.hpp"

namespace tactus::runtime {

class LiveParameters;

/// An event raised by a loop (trivially copyable, unlike recording's Event with its text).
struct LoopEvent {
  double t = 0.0;
  EventKind kind = EventKind::note;
  std::uint16_t device = 0;
  double value = 0.0;
  /// rupture: the torn layer's index in the needle's layers; otherwise −1.
  std::int32_t detail = -1;
};

/// What the simulation builds for a device whose local model is a patch.
struct PatchRequest {
  contact::LocalModelKind kind = contact::LocalModelKind::plane;
  contact::PatchCapacity capacity;
  double radius = 0.0;              ///< of the bounding sphere around the tool origin [m]
  std::vector<std::size_t> bodies;  ///< bodies the device's algorithm touches
};

/// Channels between one device's haptic loop and the other loops.
struct DeviceChannels {
  explicit DeviceChannels(std::size_t ring_capacity)
      : tool(ToolState{}), tool_to_simulation(ToolState{}), contact(LocalContact{}), load(ContactLoad{}), needle(haptics::NeedleSurfaces{}),
        frames(ring_capacity), events(1024) {}
  /// Before any loop runs: the simulation publishes a patch of this kind with every step.
  void request_patches(PatchRequest request) {
    patch_request = std::move(request);
    patch = std::make_unique<TripleBuffer<contact::LocalPatch>>(
        contact::LocalPatch(patch_request.kind, patch_request.capacity));
  }
  TripleBuffer<ToolState> tool;                ///< haptic → interaction
  TripleBuffer<ToolState> tool_to_simulation;  ///< haptic → simulation (where to cut the patch)
  TripleBuffer<LocalContact> contact;          ///< interaction → haptic
  TripleBuffer<ContactLoad> load;              ///< haptic → simulation
  TripleBuffer<haptics::NeedleSurfaces> needle; ///< interaction → haptic (needle tools)
  SpscRing<HapticFrame> frames;                ///< haptic → recorder
  SpscRing<LoopEvent> events;                  ///< haptic → recorder
  PatchRequest patch_request;
  std::unique_ptr<TripleBuffer<contact::LocalPatch>> patch;  ///< simulation → haptic; null: plane
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
  /// The local model between simulation steps: the plane of DeviceChannels::contact, or a
  /// patch, which the loop set requests on the device's channels with this kind and
  /// capacity; the haptic loop renders whatever patch its channels carry.
  contact::LocalModelKind local_model = contact::LocalModelKind::plane;
  contact::PatchCapacity patch_capacity;
  /// Time constant of the passive smoothing of force steps at model updates [s]; 0 = off.
  double force_smoothing = 0.0;
  /// Weaken a contact force that would return more energy to the hand than the hand put
  /// into the contact (runtime/passivity_control.hpp).
  bool passivity_control = false;
  /// Spread the tissue's load over the contact disc instead of the contact triangle
  /// (contact/load_spread.hpp); the patch models then dent their nodes the same way.
  bool spread_over_contact_disc = false;
  double damping = 0.0;      ///< normal damping [N·s/m]
  /// Low-pass time constant of the tool velocity estimate used by the damping [s].
  double velocity_filter = 0.002;
  haptics::SafetyConfig safety;
  /// A needle tool (haptics/algorithms/needle.hpp): replaces the spheres' contact.
  std::optional<haptics::NeedleConfig> needle;
  /// The needle's axis in scene coordinates when fixed (a scripted insertion line); else
  /// the device's −z.
  std::optional<Vec3> needle_axis;
  /// A body rendered from a precomputed configuration space: the force at the first sphere's
  /// centre comes from its interpolator and replaces the local model's.
  std::shared_ptr<const CspaceBody> cspace;
  /// Multiple-surface palpation (haptics/algorithms/multi_surface.hpp): replaces the
  /// spheres' contact; its ray hits come on DeviceChannels::needle, one per layer body.
  struct MultiSurface {
    haptics::MultiSurfaceConfig force;
    std::vector<std::size_t> bodies;  ///< the layers, outermost first
  };
  std::optional<MultiSurface> multi_surface;
  /// The pulse (haptics/algorithms/pulse.hpp), added to the contact force while touching.
  std::optional<haptics::PulseForce> pulse;
};

class HapticLoop {
 public:
  HapticLoop(HapticConfig config, std::unique_ptr<haptics::Device> device, DeviceChannels& channels);

  /// One frame at time t. `deadline` and `start` are for the statistics (steady clock,
  /// or virtual nanoseconds in lockstep).
  void step(double t, Nanos deadline, Nanos start, bool real_time);

  /// Safe to call from any thread.
  void request_emergency_stop() { emergency_stop_.store(true, std::memory_order_relaxed); }
  /// Surface edits read at each frame (runtime/live_parameters.hpp); before the loop runs.
  void set_live_parameters(const LiveParameters* live) { live_ = live; }
  [[nodiscard]] bool finished(double t) const { return device_->finished(t); }
  [[nodiscard]] const LoopStats& stats() const { return stats_; }
  /// Time from the pose read returning to the force written: the loop's own latency.
  [[nodiscard]] const LatencyHistogram& device_to_force() const { return device_to_force_; }
  [[nodiscard]] haptics::SafetyCounters safety_counters() const { return safety_.counters(); }
  /// The contact's passivity controller (read after the loop has stopped).
  [[nodiscard]] const PassivityControl& passivity() const { return passivity_; }
  [[nodiscard]] std::uint64_t dropped_frames() const { return dropped_frames_; }
  [[nodiscard]] const haptics::Device& device() const { return *device_; }
  /// The needle's insertion state (ruptures, deviation); null for other tools.
  [[nodiscard]] const haptics::NeedleInsertion* needle() const { return needle_ ? &*needle_ : nullptr; }

 private:
  /// The force of one frame against one local model, and where it acts on the tissue.
  struct Rendered {
    Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
    bool touching = false;
    Vec3 point = Vec3::Zero();        ///< contact point on the surface
    contact::PatchContact on_patch;   ///< patch models only
    double law_force = 0.0;           ///< normal force of the contact law [N]
    double contact_radius = 0.0;      ///< of the contact disc the load is spread over [m]
  };
  void emit(double t, EventKind kind, double value, std::int32_t detail = -1);
  void apply_live_parameters(double t);  // live_parameters.cpp
  Rendered render_plane(const LocalContact& contact, contact::ProxyState& proxy, const Vec3& position,
                        const Quat& orientation, double t, double dt, bool use_interpolator);
  Rendered render_patch(const LocalContact& contact, contact::ProxyState& proxy, const Vec3& position,
                        const Quat& orientation, double dt);
  double law_force(double depth, double mean_curvature) const;
  /// The radius a load is spread over: the contact disc's, or −1 for the contact triangle.
  double disc_radius(double contact_radius) const { return config_.spread_over_contact_disc ? contact_radius : -1.0; }
  // Needle tools (needle_render.cpp).
  Rendered render_needle(const Vec3& position, const Quat& orientation, double t);
  void needle_load(ContactLoad& load, bool touching) const;
  // Multiple-surface palpation and the pulse (multi_surface_render.cpp).
  Rendered render_multi_surface(const Vec3& position, const Quat& orientation, double t);
  void multi_surface_load(ContactLoad& load, bool touching) const;
  Vec3 pulse_force(double t, const Vec3& position, const Quat& orientation, const Vec3& contact_force,
                   bool touching) const;

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
  std::optional<contact::LocalModel> local_;  ///< patch models only
  /// Each touching sphere's contact on the patch (render_patch; sphere-set fingers).
  std::array<contact::PatchContact, contact::LocalModel::kMaxContacts> sphere_contacts_{};
  int sphere_contact_count_ = 0;
  LocalContact shown_contact_;  ///< the plane rendered last frame (to measure an update's step)
  ForceSmoother smoother_;
  PassivityControl passivity_;
  bool proxy_started_ = false;
  Vec3 last_position_ = Vec3::Zero();
  Vec3 velocity_ = Vec3::Zero();
  double last_t_ = -1.0;
  std::optional<haptics::NeedleInsertion> needle_;
  haptics::NeedleOutput needle_out_;
  Vec3 needle_axis_ = Vec3::Zero();
  std::optional<haptics::MultiSurfaceForce> multi_surface_;
  haptics::MultiSurfaceOutput multi_out_;
  bool multi_surface_hits_ = false;  ///< a set of ray hits has arrived
  const LiveParameters* live_ = nullptr;
  std::uint64_t live_version_ = 0;
};

}  // namespace tactus::runtime
