#pragma once
// A finger of one or more contact spheres pressing into the contact plane, each by the
// finger's force law (penalty, Hertz with the tissue's curvature, or the fingerpad law).
#include <vector>

#include "haptics/algorithms/contact_law.hpp"
#include "haptics/algorithms/on_plane.hpp"

namespace tactus::haptics {

class SpheresOnPlane final : public OnPlane {
 public:
  /// `damping` [N·s/m] on the plane's normal speed.
  SpheresOnPlane(std::vector<ToolSphere> spheres, ContactLaw law, double damping = 0.0)
      : spheres_(std::move(spheres)), law_(std::move(law)), damping_(damping) {}

  [[nodiscard]] std::unique_ptr<AlgorithmState> make_state() const override;
  [[nodiscard]] EditableSurface editable_surface() const override;
  void edit_surface(const SurfaceValues& values, AlgorithmState& state) const override;

 private:
  struct State final : PlaneState {
    double stiffness = 0.0;  ///< the penalty's, as edited
  };
  [[nodiscard]] Rendering against(const LocalContact& plane, const FrameInputs& frame, PlaneState& state,
                                  bool trial) const override;

  std::vector<ToolSphere> spheres_;
  ContactLaw law_;
  double damping_;
};

}  // namespace tactus::haptics
