#pragma once
// One device's haptic loop: read the pose and the other loops' newest values, run the haptic
// step, hand the reaction to the simulation and the frame to the recorder. No locks, no
// allocation, no exceptions after construction.
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "contact/local_model.hpp"
#include "core/spsc_ring.hpp"
#include "core/triple_buffer.hpp"
#include "haptics/algorithms/needle.hpp"
#include "haptics/device.hpp"
#include "haptics/haptic_step.hpp"
#include "runtime/exchange.hpp"
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

/// Channels between one device's haptic loop and the other loops.
struct DeviceChannels {
  explicit DeviceChannels(std::size_t ring_capacity)
      : tool(ToolState{}), tool_to_simulation(ToolState{}), finger(haptics::PeerFinger{}), contact(LocalContact{}), load(ContactLoad{}), needle(haptics::NeedleSurfaces{}),
        frames(ring_capacity), events(1024) {}
  /// Before any loop runs: the simulation publishes a patch of this kind with every step.
  void request_patches(PatchRequest request) {
    patch_request = std::move(request);
    patch = std::make_unique<QuadBuffer<contact::LocalPatch>>(
        contact::LocalPatch(patch_request.kind, patch_request.capacity));
  }
  TripleBuffer<ToolState> tool;                ///< haptic → interaction
  TripleBuffer<ToolState> tool_to_simulation;  ///< haptic → simulation (where to cut the patch)
  /// haptic → the partner finger's haptic loop (its one reader; HapticModel::partner)
  TripleBuffer<haptics::PeerFinger> finger;
  TripleBuffer<LocalContact> contact;          ///< interaction → haptic
  TripleBuffer<ContactLoad> load;              ///< haptic → simulation
  TripleBuffer<haptics::NeedleSurfaces> needle; ///< interaction → haptic (needle tools)
  SpscRing<HapticFrame> frames;                ///< haptic → recorder
  SpscRing<LoopEvent> events;                  ///< haptic → recorder
  PatchRequest patch_request;
  /// simulation → haptic; null: plane. Four slots: the haptic loop's local model refers to the
  /// newest in place and may read the one before in the frame it switches (LocalModel).
  std::unique_ptr<QuadBuffer<contact::LocalPatch>> patch;
};

/// One device's haptic loop: its device, its channels and its timing around the pure
/// haptic step (haptics/haptic_step.hpp), which renders the force.
class HapticLoop {
 public:
  /// Throws InputError or std::invalid_argument for a model the step cannot run.
  HapticLoop(haptics::HapticModel model, std::unique_ptr<haptics::Device> device, DeviceChannels& channels);

  /// One frame at time t. `deadline` and `start` are for the statistics (steady clock,
  /// or virtual nanoseconds in lockstep).
  void step(double t, Nanos deadline, Nanos start, bool real_time);

  /// Safe to call from any thread.
  void request_emergency_stop() { emergency_stop_.store(true, std::memory_order_relaxed); }
  /// Surface edits read at each frame (runtime/live_parameters.hpp); before the loop runs.
  void set_live_parameters(const LiveParameters* live) { live_ = live; }
  /// The partner finger's channel, read at each frame (its only reader); before the loop runs.
  void set_partner(TripleBuffer<haptics::PeerFinger>* partner) { peer_ = partner; }
  [[nodiscard]] const haptics::HapticModel& model() const { return model_; }
  [[nodiscard]] bool finished(double t) const { return device_->finished(t); }
  [[nodiscard]] const LoopStats& stats() const { return stats_; }
  /// Time from the pose read returning to the force written: the loop's own latency.
  [[nodiscard]] const LatencyHistogram& device_to_force() const { return device_to_force_; }
  [[nodiscard]] haptics::SafetyCounters safety_counters() const { return state_.safety.counters(); }
  /// The contact's passivity controller (read after the loop has stopped).
  [[nodiscard]] const haptics::PassivityControl& passivity() const { return state_.passivity; }
  [[nodiscard]] std::uint64_t dropped_frames() const { return dropped_frames_; }
  /// How far the tool strayed from the centre of the patch it was rendered on: the largest
  /// distance as a fraction of the patch's radius, and the frames beyond the radius (0 and 0
  /// without patches).
  [[nodiscard]] const PatchReach& patch_reach() const { return patch_reach_; }
  [[nodiscard]] const haptics::Device& device() const { return *device_; }
  /// The needle's insertion state (ruptures, deviation); null for other tools.
  [[nodiscard]] const haptics::NeedleInsertion* needle() const;

 private:
  /// Writes to the device and stamps the latency.
  struct DeviceSink final : haptics::ForceSink {
    HapticLoop* loop = nullptr;
    Nanos pose_read = 0;
    void write(const Vec3& force, const Vec3& torque) override;
  };
  void emit(double t, const haptics::HapticEvent& event);

  haptics::HapticModel model_;
  haptics::HapticState state_;
  haptics::HapticOutputs out_;
  std::unique_ptr<haptics::Device> device_;
  DeviceChannels& channels_;
  DeviceSink sink_;
  LoopStats stats_;
  LatencyHistogram device_to_force_;
  std::uint64_t frame_ = 0;
  std::uint64_t dropped_frames_ = 0;
  std::atomic<bool> emergency_stop_{false};
  bool follows_tool_ = false;  ///< the simulation needs the tool's position
  PatchReach patch_reach_{};
  const LiveParameters* live_ = nullptr;
  haptics::SurfaceEdit edit_;
  TripleBuffer<haptics::PeerFinger>* peer_ = nullptr;
};

}  // namespace tactus::runtime
