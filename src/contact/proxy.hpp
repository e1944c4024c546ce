#pragma once
// God-object / proxy haptic rendering with friction (Zilles & Salisbury 1995; Ruspini,
// Kolarov & Khatib 1997; seed 002 §V-C). A sphere of radius r (0: a point god-object)
// follows the device position (the goal) but never passes through the surface: each update
// moves it by swept-sphere continuous collision and slides it on the constraint planes it
// meets; a virtual coupling spring-damper between proxy and device gives the force, and a
// friction cone decides whether the proxy sticks or slips. See docs/proxy.md.
//
// update_proxy is a pure step over (params, state, inputs): no allocation, no exceptions,
// no clocks, so it runs in the haptic loop and in lockstep tests alike.
#include <array>
#include <cstdint>

#include "contact/surface_query.hpp"
#include "core/math.hpp"

namespace tactus::contact {

/// The plane {x : normal·x = offset}; its front is where normal·x > offset.
struct ConstraintPlane {
  Vec3 normal = Vec3::UnitZ();  ///< unit
  double offset = 0.0;          ///< [m]
  [[nodiscard]] double signed_distance(const Vec3& x) const { return normal.dot(x) - offset; }
};

/// Planes a proxy update collects while it slides; the closest point to the goal on them is
/// always on the intersection of at most three.
inline constexpr int kMaxProxyPlanes = 6;

enum class FrictionState : std::uint8_t {
  none,   ///< not in contact
  stick,  ///< held by static friction: tangential coupling force inside the cone μs·Fn
  slip,   ///< sliding on the surface (kinetic friction μk, or no friction)
};

struct ProxyParams {
  double radius = 0.0;            ///< r [m]; 0 is a point god-object
  double skin = 1e-6;             ///< [m] clearance kept above r, so rounding never puts the proxy inside
  double stiffness = 500.0;       ///< k [N/m] of the virtual coupling
  double damping = 0.0;           ///< b [N·s/m] of the virtual coupling
  double static_friction = 0.0;   ///< μs
  double kinetic_friction = 0.0;  ///< μk, at most μs
  /// b_p [N·s/m] of the proxy's own motion while slipping (seed 002 §V-C, massless): the
  /// proxy approaches the kinetic cone at speed (|Ft| − μk·Fn)/b_p; 0 reaches it at once.
  double slip_damping = 0.0;
  int max_iterations = 10;        ///< sweeps per slide (an update slides at most twice)
  /// Every surface the proxy meets is closed and outward oriented: a proxy found behind its
  /// closest point (inside) after the surface moved is pushed out through that point.
  /// With open surfaces (sheets) set false: only overlaps and remembered sides are used.
  bool closed_surfaces = true;
};

/// Throws InputError naming the parameter when one is out of range.
void validate_proxy_params(const ProxyParams& params);

struct ProxyState {
  Vec3 position = Vec3::Zero();  ///< the proxy's centre [m]
  /// Planes touching the unconstrained (frictionless) solution of the last update, in the
  /// proxy's configuration space (offset by r + skin from the surface).
  std::array<ConstraintPlane, kMaxProxyPlanes> planes{};
  int plane_count = 0;
  bool in_contact = false;
  FrictionState friction = FrictionState::none;
  /// Where static friction holds the proxy: its centre, and the material point of the surface
  /// it is attached to (triangle, barycentric, position then), so that the anchor moves with a
  /// deforming surface.
  Vec3 stick_anchor = Vec3::Zero();
  std::int32_t anchor_triangle = -1;
  Vec3 anchor_barycentric = Vec3::Zero();
  Vec3 anchor_surface_point = Vec3::Zero();
  /// The triangle closest to the proxy after the last update and the side of it the proxy
  /// was on (+1 front, −1 back; 0 unknown): a surface that moves across the proxy between
  /// updates is detected by the side changing.
  std::int32_t side_triangle = -1;
  std::int8_t side = 0;
  /// The surface was replaced by a newer model since the last update (a local patch from the
  /// next simulation step): the proxy's jump onto it is the models' difference, not motion,
  /// so the next update's damping sees none of it.
  bool surface_replaced = false;
};

/// A free proxy at `position`; if that is inside the surface, the first update pushes it out.
[[nodiscard]] ProxyState make_proxy_state(const Vec3& position);

struct ProxyResult {
  Vec3 force = Vec3::Zero();     ///< [N] on the device: k·(proxy − goal) + b·(v_proxy − v_goal) in contact
  Vec3 position = Vec3::Zero();  ///< the proxy's centre after the update
  bool in_contact = false;
  FrictionState friction = FrictionState::none;
  double depth = 0.0;  ///< [m] distance from the goal to the frictionless proxy (0 when free)
  Vec3 contact_point = Vec3::Zero();   ///< surface point closest to the proxy (in contact)
  Vec3 contact_normal = Vec3::Zero();  ///< unit, from the contact point toward the proxy
  std::int32_t triangle = -1;
  Vec3 barycentric = Vec3::Zero();
  bool pushed_out = false;       ///< the surface had moved into the proxy since the last update
  bool input_rejected = false;   ///< non-finite goal, velocity, position or dt: proxy held, no force
  int sweeps = 0;                ///< sphere sweeps spent
};

/// One haptic update: push out (surface moved), slide toward the goal, friction, coupling force.
/// `params` must have passed validate_proxy_params; `goal_velocity` is the device velocity.
[[nodiscard]] ProxyResult update_proxy(const ProxyParams& params, ProxyState& state, const Vec3& goal,
                                       const Vec3& goal_velocity, double dt, const SurfaceQuery& surface);

/// The closest point to `goal` in front of every plane (min |x − goal|² s.t. n_i·x ≥ d_i):
/// the Zilles–Salisbury Lagrange solution on the best intersection of at most three planes.
/// False when no point satisfies them all (within `tolerance`).
[[nodiscard]] bool closest_point_on_planes(const Vec3& goal, const ConstraintPlane* planes, int count,
                                           double tolerance, Vec3& out);

// --- Blending constraint planes between surface updates (seed 003 §3.5) ---------------------

/// The plane whose signed distance is (1 − s)·from + s·to, renormalised: it turns about the
/// line where the two planes meet (translates when they are parallel). s is clamped to [0, 1].
[[nodiscard]] ConstraintPlane blend_planes(const ConstraintPlane& from, const ConstraintPlane& to, double s);

/// Renders a contact plane that arrives at the slow simulation rate without force steps:
/// each new plane is reached by blending from the plane shown at that moment over
/// `blend_time` seconds.
class PlaneInterpolator {
 public:
  /// Throws InputError when blend_time is negative or not finite.
  explicit PlaneInterpolator(double blend_time);

  /// A new plane at time `now` [s]. The first one is shown at once.
  void set_target(const ConstraintPlane& plane, double now);
  /// The plane to render at time `now`.
  [[nodiscard]] ConstraintPlane at(double now) const;
  [[nodiscard]] bool has_plane() const { return has_plane_; }

 private:
  double blend_time_;
  ConstraintPlane from_, to_;
  double start_ = 0.0;
  bool has_plane_ = false;
};

}  // namespace tactus::contact
