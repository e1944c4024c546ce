#pragma once
// What the two proxy algorithms (on the contact plane, on a local patch) share: the
// coupling's parameters as a user edits them, and the proxy, started where the tool first is.
#include "contact/proxy.hpp"
#include "haptics/algorithms/contact_law.hpp"
#include "haptics/force_algorithm.hpp"

namespace tactus::haptics {

struct ProxyCoupling {
  contact::ProxyParams params;  ///< the scene's, as edited
  contact::ProxyState proxy;
  bool started = false;

  /// At the first frame: the proxy where the tool's sphere is.
  void start(const FrameInputs& f, const ToolSphere& sphere) {
    if (started) return;
    proxy = contact::make_proxy_state(f.position + f.orientation * sphere.offset);
    started = true;
  }
  void edit(const SurfaceValues& v) {
    params.stiffness = v.stiffness;
    params.static_friction = v.static_friction;
    params.kinetic_friction = v.kinetic_friction;
  }
};

/// A proxy's coupling as the viewer's panel edits it: stiffness and friction.
[[nodiscard]] inline EditableSurface proxy_surface(const contact::ProxyParams& p) {
  return {EditableSurface::Kind::proxy, {p.stiffness, p.static_friction, p.kinetic_friction}};
}

}  // namespace tactus::haptics
