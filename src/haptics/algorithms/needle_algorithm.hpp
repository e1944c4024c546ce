#pragma once
// Needle insertion through layers as a force algorithm: the axis from the handle (or the
// scripted insertion line), the layer crossings the interaction loop found along it, the
// insertion stages of haptics/algorithms/needle.hpp, and where the reaction goes: the tip's
// load on the layer it presses, and the shaft's lateral spring along the shaft.
#include <optional>

#include "haptics/algorithms/needle.hpp"
#include "haptics/force_algorithm.hpp"

namespace tactus::haptics {

class NeedleAlgorithm final : public ForceAlgorithm {
 public:
  /// `fixed_axis`: the unit axis of a scripted insertion line; otherwise the handle's −z.
  /// Throws std::invalid_argument as NeedleInsertion does.
  NeedleAlgorithm(NeedleConfig config, std::optional<Vec3> fixed_axis);

  [[nodiscard]] std::unique_ptr<AlgorithmState> make_state() const override;
  [[nodiscard]] Rendering render(const FrameInputs& frame, AlgorithmState& state) const override;
  void react(const FrameInputs& frame, const Rendering& rendered, const Reaction& reaction, AlgorithmState& state,
             ContactLoad& load) const override;

  [[nodiscard]] const NeedleConfig& config() const { return config_; }
  /// The insertion so far (ruptures, deviation) of a state this algorithm made.
  [[nodiscard]] static const NeedleInsertion& insertion(const AlgorithmState& state);

 private:
  struct State final : AlgorithmState {
    explicit State(const NeedleConfig& config) : needle(config) {}
    NeedleInsertion needle;
    NeedleOutput out;
    Vec3 axis = Vec3::Zero();
  };
  NeedleConfig config_;
  std::optional<Vec3> fixed_axis_;
};

}  // namespace tactus::haptics
