#pragma once
// The god-object proxy among many rigid objects (seed 000 §4: a room of touchable things),
// queried at the haptic rate on each object's chosen impostor level (objects.hpp: how the
// levels are chosen and switched), with the surface material of each object's haptic property
// images (seed 001, second chapter). The proxy moves against the union of the objects' levels
// (and the interaction loop's contact plane of the deformable bodies, where there are any),
// its coupling's stiffness, friction and damping those painted where it touched last frame; a
// roughness texture tilts and lifts the force (force shading: F_n·(n − ∇h) + k·h·n, with h the
// texture height of the property image's view). Across a level switch of the touched object
// the force blends from the old level's (the proxy moved against the old surface on a copy)
// to the new one's.
//
// The proxy is carried across a switch, not nested: a finer level may lie outside a coarser
// one (Loop subdivision moves vertices; decimation cuts corners), and a proxy left behind the
// new surface is pushed out through its closest point by the proxy's closed-surface rule.
#include <memory>
#include <span>
#include <vector>

#include "contact/proxy.hpp"
#include "haptics/algorithms/contact_law.hpp"
#include "haptics/algorithms/objects.hpp"
#include "haptics/algorithms/proxy_coupling.hpp"
#include "haptics/force_algorithm.hpp"

namespace tactus::haptics {

class ProxyOnObjects final : public ForceAlgorithm {
 public:
  /// Throws InputError for an object without levels or switch thresholds out of order.
  ProxyOnObjects(ToolSphere sphere, const contact::ProxyParams& params, std::vector<TouchableObject> objects,
                 const ObjectsSettings& settings);

  [[nodiscard]] std::unique_ptr<AlgorithmState> make_state() const override;
  [[nodiscard]] Rendering render(const FrameInputs& frame, AlgorithmState& state) const override;
  void react(const FrameInputs& frame, const Rendering& rendered, const Reaction& reaction, AlgorithmState& state,
             ContactLoad& load) const override;
  [[nodiscard]] EditableSurface editable_surface() const override { return proxy_surface(params_); }
  void edit_surface(const SurfaceValues& values, AlgorithmState& state) const override;

  /// The level each object renders at and their summed cost, as of the last frame (for tests
  /// and the viewer's debug view; read on the haptic thread or in lockstep only).
  [[nodiscard]] static std::span<const std::size_t> levels_in_use(const AlgorithmState& state);
  [[nodiscard]] static double cost_in_use(const AlgorithmState& state);

 private:
  struct State;

  ToolSphere sphere_;
  contact::ProxyParams params_;
  LevelChooser chooser_;
};

}  // namespace tactus::haptics
