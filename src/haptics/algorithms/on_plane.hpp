#pragma once
// The base of the algorithms that touch the contact plane the interaction loop builds through
// the closest surface point (seed 003 §3.5). A new plane is a model update: with smoothing on,
// the force of the plane shown last frame and of the new one are both measured at this frame.
#include "haptics/force_algorithm.hpp"

namespace tactus::haptics {

class OnPlane : public ForceAlgorithm {
 public:
  [[nodiscard]] Rendering render(const FrameInputs& frame, AlgorithmState& state) const final;

 protected:
  struct PlaneState : AlgorithmState {
    LocalContact shown;  ///< the plane rendered last frame
  };
  /// Before anything renders this frame (the proxy starts where the tool first is).
  virtual void begin(const FrameInputs& /*frame*/, PlaneState& /*state*/) const {}
  /// The force against `plane` (which may be invalid: no surface within reach). A `trial`
  /// measures without changing the state.
  [[nodiscard]] virtual Rendering against(const LocalContact& plane, const FrameInputs& frame, PlaneState& state,
                                          bool trial) const = 0;
};

}  // namespace tactus::haptics
