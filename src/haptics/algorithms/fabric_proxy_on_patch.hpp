#pragma once
// A fingertip on a fabric (seed 002 §V-C, contact states IV–VII): the V-proxy
// (contact/fabric_proxy.hpp) against a local patch of the fabric that deforms at the haptic
// rate between simulation steps (the fabric's own linearized springs, border at constant
// velocity, seed §IV). The proxy keeps to its finger's side of the thin sheet: the thumb
// touches the front, the index the back.
#include <vector>

#include "contact/fabric_proxy.hpp"
#include "haptics/algorithms/on_patch.hpp"

namespace tactus::haptics {

class FabricProxyOnPatch final : public OnPatch {
 public:
  /// Throws InputError for parameters out of range (contact::validate).
  FabricProxyOnPatch(const contact::FabricProxyParams& params, contact::LocalModelKind kind,
                     contact::PatchCapacity capacity, bool spread_over_disc);

  [[nodiscard]] std::unique_ptr<AlgorithmState> make_state() const override;
  [[nodiscard]] const contact::FabricProxyParams& params() const { return proxy_.params(); }

 private:
  struct State final : PatchState {
    State(contact::LocalModelKind kind, const contact::PatchCapacity& capacity);
    contact::FabricProxyState proxy;
    bool started = false;
    std::vector<std::int32_t> candidates;  ///< 0, 1, ... over the patch's triangles
    std::int32_t surface_triangle = -1;    ///< the body's triangle the proxy rests on, across an update
  };
  void begin(const FrameInputs& frame, PatchState& state) const override;
  void patch_replacing(PatchState& state) const override;
  void patch_replaced(PatchState& state) const override;
  [[nodiscard]] Rendering against(const FrameInputs& frame, PatchState& state, bool trial) const override;
  void advance(const FrameInputs& frame, const Rendering& rendered, const Reaction& reaction, bool on,
               const contact::PatchContact& on_patch, PatchState& state, ContactLoad& load) const override;

  contact::FabricProxy proxy_;
};

}  // namespace tactus::haptics
