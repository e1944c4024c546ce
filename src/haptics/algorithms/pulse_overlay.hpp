#pragma once
// The pulse (haptics/algorithms/pulse.hpp) as an overlay: while the tool's contact touches,
// the beat of the vessel beneath is added to the contact force.
#include "haptics/algorithms/pulse.hpp"
#include "haptics/force_algorithm.hpp"

namespace tactus::haptics {

class PulseOverlay final : public ForceAlgorithm {
 public:
  /// `offset`: the finger sphere's centre in the tool frame [m].
  PulseOverlay(PulseForce pulse, Vec3 offset) : pulse_(std::move(pulse)), offset_(offset) {}

  [[nodiscard]] Stage stage() const override { return Stage::overlay; }
  [[nodiscard]] std::unique_ptr<AlgorithmState> make_state() const override {
    return std::make_unique<AlgorithmState>();
  }
  [[nodiscard]] Rendering render(const FrameInputs& frame, AlgorithmState& state) const override;
  [[nodiscard]] const PulseForce& pulse() const { return pulse_; }

 private:
  PulseForce pulse_;
  Vec3 offset_;
};

}  // namespace tactus::haptics
