#pragma once
// The V-proxy (seed 002 §V-C, contact states IV–VII): a god-object for one capsule finger
// on a thin fabric given as current vertex positions and triangles. The proxy is the
// finger's capsule moved by a translation only (it keeps the device's orientation); it
// never passes through the fabric and stays on the finger's own side of it (the thumb
// touches the front, where the triangle normals point; the index the back). A coupling
// spring of the combined finger–fabric stiffness k^K gives F^d = k^K·(x^p − x^d) on the
// finger. Friction: the proxy sticks while |F^T| ≤ μ_s·F^N; otherwise it moves by
//   F − μ_k·F^N·ẋ/|ẋ| = m·ẍ + b·ẋ   (F the spring's pull on the proxy, along the fabric),
// stepped with the spring and the damping implicit, and sticks again once its pull falls
// to μ_k·F^N. Fabric that slides under the proxy past μ_s·F^N drags it with μ_k·F^N
// (the proxy slips on it). The fabric gets −F^d on the three vertices of the touched triangle
// (barycentric). See docs/grasp.md.
//
// The fabric is given as plain arrays, with a caller's list of candidate triangles near the
// finger (no spatial search here). update() allocates nothing and throws nothing.
#include <array>
#include <cstdint>
#include <span>

#include "contact/fingertip.hpp"
#include "contact/proxy.hpp"
#include "core/math.hpp"
#include "mesh/tri_mesh.hpp"

namespace tactus::contact {

struct FabricProxyParams {
  CapsuleShape finger;           ///< the fingertip, in its own frame
  int side = +1;                 ///< +1: touches the front (thumb); −1: the back (index)
  double stiffness = 1000.0;     ///< k^K, finger and fabric in series, N/m
  double static_friction = 0.5;  ///< μ_s
  double kinetic_friction = 0.4; ///< μ_k ≤ μ_s
  /// The proxy's own mass and damping while it slides (the seed's m and b). With the
  /// spring and the damping implicit the step is stable for any dt; these values give
  /// ζ = b/(2·√(k^K·m)) ≈ 0.56 with the default k^K, and add only b·v to the sliding force
  /// (2.5 mN at 5 mm/s).
  double mass = 2e-4;      ///< kg
  double damping = 0.5;    ///< N·s/m
  /// A gap this small counts as touching (sweeps, the side test, leaving the surface), m.
  double tolerance = 1e-7;
};

/// Throws InputError naming the parameter that is out of range.
void validate(const FabricProxyParams& params);

struct FabricProxyState {
  Vec3 position = Vec3::Zero();  ///< the proxy: where the finger's pose origin would be, m
  Vec3 velocity = Vec3::Zero();  ///< while sliding, m/s
  bool in_contact = false;
  FrictionState friction = FrictionState::none;
  /// The fabric's material point under the proxy after the last update, so that a proxy
  /// resting on moving fabric is carried with it.
  std::int32_t triangle = -1;
  Vec3 barycentric = Vec3::Zero();
  Vec3 surface_point = Vec3::Zero();
};

/// A free proxy at the finger's position.
[[nodiscard]] FabricProxyState make_fabric_proxy_state(const Vec3& finger_position);

struct FabricProxyResult {
  bool in_contact = false;
  FrictionState friction = FrictionState::none;
  Vec3 force = Vec3::Zero();           ///< on the finger, k^K·(x^p − x^d), N
  double normal_force = 0.0;           ///< F^N, N
  double tangential_force = 0.0;       ///< |F^T|, N
  double depth = 0.0;                  ///< of the device behind the contact plane, m
  Vec3 proxy = Vec3::Zero();           ///< x^p after the update
  Vec3 contact_point = Vec3::Zero();   ///< on the fabric, where the proxy's capsule touches
  Vec3 contact_normal = Vec3::Zero();  ///< unit, from the fabric toward the finger
  std::int32_t triangle = -1;
  Vec3 barycentric = Vec3::Zero();
  /// −force spread over the touched triangle's vertices; they sum to −force.
  std::array<std::int32_t, 3> vertices{-1, -1, -1};
  std::array<Vec3, 3> vertex_loads{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  bool input_rejected = false;  ///< non-finite pose or state, or dt ≤ 0: held, no force
};

class FabricProxy {
 public:
  /// Throws InputError (see validate).
  explicit FabricProxy(const FabricProxyParams& params);

  [[nodiscard]] const FabricProxyParams& params() const { return params_; }

  /// One haptic step: the finger at `finger`, the fabric at `positions` with `triangles`,
  /// of which only those listed in `candidates` are looked at (indices into `triangles`;
  /// ones out of range, or with vertices out of range, are skipped).
  [[nodiscard]] FabricProxyResult update(FabricProxyState& state, const Pose& finger,
                                         std::span<const Vec3> positions,
                                         std::span<const mesh::Triangle> triangles,
                                         std::span<const std::int32_t> candidates, double dt) const noexcept;

 private:
  FabricProxyParams params_;
};

}  // namespace tactus::contact
