#pragma once
// God-object proxy with friction against a local patch: the proxy slides on the patch's
// deforming triangles, and the patch dents under the coupling force the hand was sent.
#include "contact/proxy.hpp"
#include "haptics/algorithms/proxy_coupling.hpp"
#include "haptics/algorithms/on_patch.hpp"

namespace tactus::haptics {

class ProxyOnPatch final : public OnPatch {
 public:
  ProxyOnPatch(ToolSphere sphere, const contact::ProxyParams& params, contact::LocalModelKind kind,
               contact::PatchCapacity capacity, bool spread_over_disc)
      : OnPatch(kind, capacity, spread_over_disc), sphere_(sphere), params_(params) {}

  [[nodiscard]] std::unique_ptr<AlgorithmState> make_state() const override;
  [[nodiscard]] EditableSurface editable_surface() const override;
  void edit_surface(const SurfaceValues& values, AlgorithmState& state) const override;
  [[nodiscard]] const contact::ProxyParams& params() const { return params_; }

 private:
  struct State final : PatchState {
    using PatchState::PatchState;
    ProxyCoupling coupling;
  };
  void begin(const FrameInputs& frame, PatchState& state) const override;
  void patch_replaced(PatchState& state) const override;
  [[nodiscard]] Rendering against(const FrameInputs& frame, PatchState& state, bool trial) const override;
  void advance(const FrameInputs& frame, const Rendering& rendered, const Reaction& reaction, bool on,
               const contact::PatchContact& on_patch, PatchState& state, ContactLoad& load) const override;

  ToolSphere sphere_;
  contact::ProxyParams params_;
};

}  // namespace tactus::haptics
