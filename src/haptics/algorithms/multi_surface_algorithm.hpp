#pragma once
// Multiple-surface palpation (seed 003 §3.5) as a force algorithm: the ray hits the
// interaction loop found per layer become constraint planes, blended and smoothed at updates,
// and the load goes to the layer the proxy rests on.
#include <vector>

#include "haptics/algorithms/contact_law.hpp"
#include "haptics/algorithms/multi_surface.hpp"
#include "haptics/force_algorithm.hpp"

namespace tactus::haptics {

class MultiSurfaceAlgorithm final : public ForceAlgorithm {
 public:
  /// `bodies`: the layers' scene bodies, outermost first (one per config.layers).
  /// Throws std::invalid_argument as MultiSurfaceForce does.
  MultiSurfaceAlgorithm(MultiSurfaceConfig config, std::vector<std::size_t> bodies, Vec3 offset);

  [[nodiscard]] std::unique_ptr<AlgorithmState> make_state() const override;
  [[nodiscard]] Rendering render(const FrameInputs& frame, AlgorithmState& state) const override;
  void react(const FrameInputs& frame, const Rendering& rendered, const Reaction& reaction, AlgorithmState& state,
             ContactLoad& load) const override;

  [[nodiscard]] const MultiSurfaceConfig& config() const { return config_; }
  [[nodiscard]] const std::vector<std::size_t>& bodies() const { return bodies_; }

 private:
  struct State final : AlgorithmState {
    explicit State(const MultiSurfaceConfig& config) : force(config) {}
    MultiSurfaceForce force;
    MultiSurfaceOutput out;
    bool has_hits = false;  ///< a set of ray hits has arrived
  };
  MultiSurfaceConfig config_;
  std::vector<std::size_t> bodies_;
  Vec3 offset_;  ///< the finger sphere's centre in the tool frame [m]
};

}  // namespace tactus::haptics
