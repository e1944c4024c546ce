#pragma once
// God-object proxy with friction (Zilles–Salisbury, Ruspini; contact/proxy.hpp) against the
// contact plane: the proxy stays on the plane, and the hand feels the coupling spring.
#include "contact/proxy.hpp"
#include "haptics/algorithms/proxy_coupling.hpp"
#include "contact/surface_query.hpp"
#include "haptics/algorithms/on_plane.hpp"

namespace tactus::haptics {

class ProxyOnPlane final : public OnPlane {
 public:
  /// `params` must have passed contact::validate_proxy_params.
  ProxyOnPlane(ToolSphere sphere, const contact::ProxyParams& params) : sphere_(sphere), params_(params) {}

  [[nodiscard]] std::unique_ptr<AlgorithmState> make_state() const override;
  [[nodiscard]] EditableSurface editable_surface() const override;
  void edit_surface(const SurfaceValues& values, AlgorithmState& state) const override;
  [[nodiscard]] const contact::ProxyParams& params() const { return params_; }

 private:
  struct State final : PlaneState {
    ProxyCoupling coupling;
    contact::BruteForceSurfaceQuery no_surface{{}, {}};
  };
  void begin(const FrameInputs& frame, PlaneState& state) const override;
  [[nodiscard]] Rendering against(const LocalContact& plane, const FrameInputs& frame, PlaneState& state,
                                  bool trial) const override;

  ToolSphere sphere_;
  contact::ProxyParams params_;
};

}  // namespace tactus::haptics
