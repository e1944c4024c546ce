#pragma once
// A finger of one or more contact spheres against a local patch: each touching sphere
// presses by the finger's force law and dents the patch under its own share of the force
// sent, and the tissue takes each share where that sphere touches.
#include <array>
#include <vector>

#include "haptics/algorithms/contact_law.hpp"
#include "haptics/algorithms/on_patch.hpp"

namespace tactus::haptics {

class SpheresOnPatch final : public OnPatch {
 public:
  SpheresOnPatch(std::vector<ToolSphere> spheres, ContactLaw law, double damping, contact::LocalModelKind kind,
                 contact::PatchCapacity capacity, bool spread_over_disc)
      : OnPatch(kind, capacity, spread_over_disc), spheres_(std::move(spheres)), law_(std::move(law)),
        damping_(damping) {}

  [[nodiscard]] std::unique_ptr<AlgorithmState> make_state() const override;
  [[nodiscard]] EditableSurface editable_surface() const override;
  void edit_surface(const SurfaceValues& values, AlgorithmState& state) const override;

 private:
  struct State final : PatchState {
    using PatchState::PatchState;
    double stiffness = 0.0;  ///< the penalty's, as edited
    /// Each touching sphere's contact on the patch, this frame.
    std::array<contact::PatchContact, contact::LocalModel::kMaxContacts> contacts{};
    int contact_count = 0;
  };
  [[nodiscard]] Rendering against(const FrameInputs& frame, PatchState& state, bool trial) const override;
  void advance(const FrameInputs& frame, const Rendering& rendered, const Reaction& reaction, bool on,
               const contact::PatchContact& on_patch, PatchState& state, ContactLoad& load) const override;

  std::vector<ToolSphere> spheres_;
  ContactLaw law_;
  double damping_;
};

}  // namespace tactus::haptics
