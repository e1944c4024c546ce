#pragma once
// The interaction loop: the channels, the clock and the statistics around the interaction
// step (runtime/interaction_step.hpp). Each step reads every device's newest tool and the
// newest surfaces, and publishes each device's local contact (and a needle's crossings).
#include <vector>

#include "core/triple_buffer.hpp"
#include "runtime/haptic_loop.hpp"
#include "runtime/interaction_step.hpp"
#include "runtime/loop_stats.hpp"
#include "scene/model.hpp"

namespace tactus::runtime {

class InteractionLoop {
 public:
  /// `channels` are the targets' devices', in the same order.
  InteractionLoop(const scene::Model& model, std::vector<InteractionTarget> targets,
                  std::vector<DeviceChannels*> channels, TripleBuffer<SurfaceSnapshot>& surfaces);

  void step(double t, Nanos deadline, Nanos start, bool real_time);

  [[nodiscard]] const LoopStats& stats() const { return stats_; }
  /// Per device: one body's collision query ("<device>: query per body", seed 003 Table 1's
  /// CD), and the device's whole handling in a step ("<device>: interaction", its IN); then
  /// "refit trees" (the trees' update after a simulation step, its updateGeo).
  [[nodiscard]] const std::vector<PartStats>& parts() const { return parts_; }

 private:
  InteractionModel model_;
  InteractionState state_;
  std::vector<DeviceChannels*> channels_;
  TripleBuffer<SurfaceSnapshot>& surfaces_;
  std::vector<ToolState> tools_;                       ///< per target, sized once
  std::vector<LocalContact*> contacts_;                ///< per target, the buffers being written
  std::vector<haptics::NeedleSurfaces*> needles_;      ///< per target (null: not a needle)
  LoopStats stats_;
  std::vector<PartStats> parts_;
};

}  // namespace tactus::runtime
