#pragma once
// Multiple-surface force algorithm for palpating sub-dermal structures (seed 003 §3.5, after
// Ruspini, Kolarov & Khatib 1997): a collision ray from the proxy towards the device
// position meets each layer's surface (the layers are the algorithm's bodies, outermost
// first); each hit gives a constraint plane through it with the surface's normal there. The
// proxy is held on the outermost enabled plane the ray hit, so the fingers stay on the skin;
// a virtual spring (and damper, along the normal) between proxy and device gives the force:
//
//   depth = max(0, −(n·goal − offset)),  offset = n·hit + radius,  F = max(0, k·depth − b·(n·v)) · n,  proxy = goal + depth·n,
//
// and, with friction, a tangential spring force k·(proxy − (goal + depth·n)) while the proxy
// sticks (|F_t| ≤ μs·k·depth), μk·k·depth when it slides.
//
// The deeper planes take over when a layer is disabled (a torn layer, an interaction state
// that switches it off). The hits come at the interaction rate: each new plane is reached by
// blending linearly from the plane shown at that moment over `blend_time`, so a plane moving
// under the finger is no force step (seed 003 §3.5, with the runtime's smoothing filter on top).
//
// Pure and allocation-free per frame, like the needle (haptics/algorithms/needle.hpp).
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "core/math.hpp"

namespace tactus::haptics {

inline constexpr std::size_t kMaxSurfaceLayers = 8;

/// Where the collision ray first enters one layer's surface.
struct SurfaceLayerHit {
  bool found = false;
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  ///< unit, out of the layer
  std::int32_t triangle = -1;
  Vec3 barycentric = Vec3::Zero();
};

struct SurfaceLayerHits {
  std::array<SurfaceLayerHit, kMaxSurfaceLayers> layers{};
};

struct MultiSurfaceConfig {
  double stiffness = 500.0;  ///< k [N/m], > 0
  double damping = 0.0;      ///< b [N·s/m], ≥ 0
  std::size_t layers = 1;    ///< [1, kMaxSurfaceLayers]
  double blend_time = 0.0;   ///< [s] over which a new plane replaces the shown one; 0 = at once
  /// The tool's sphere radius [m]: each plane is held this far out of its layer, so the
  /// sphere's surface, not its centre, rests on the layer.
  double radius = 0.0;
  /// A plane the device is farther behind than this is not the surface it presses (a far
  /// side face the ray met while moving freely): it holds nothing [m]. Set it above the
  /// depth at which the device's force limit is reached.
  double max_depth = std::numeric_limits<double>::infinity();
  /// A hit whose plane has the proxy farther behind it than this is a surface the proxy is
  /// not on the outside of (the far face of a layer, met by a ray cast backwards from a
  /// released tool): it holds nothing (Ruspini et al.: a proxy is only constrained by the
  /// surfaces it has not crossed). It must cover how far a free tool travels into a layer
  /// between two ray queries [m].
  double behind_tolerance = 0.005;
  /// Coulomb friction on the holding plane (seed 003 §3.4's tissue dragging): the proxy sticks
  /// where it touched while the spring's tangential force stays within static_friction times
  /// the normal force, else slides with kinetic_friction times it trailing behind the device.
  /// The tangential force reaches the hand and, as the contact load, drags the tissue.
  double static_friction = 0.0;   ///< μs ≥ 0
  double kinetic_friction = 0.0;  ///< μk in [0, μs]
};

struct MultiSurfaceOutput {
  Vec3 force = Vec3::Zero();  ///< on the hand [N]
  Vec3 proxy = Vec3::Zero();  ///< the proxy's position [m]
  bool touching = false;
  int layer = -1;             ///< the layer whose plane holds the proxy; −1 free
  double depth = 0.0;         ///< of the device behind that plane [m]
  bool sticking = false;      ///< friction holds the proxy where it is
  std::int32_t triangle = -1; ///< that layer's hit, where the reaction goes on the tissue
  Vec3 barycentric = Vec3::Zero();
};

class MultiSurfaceForce {
 public:
  /// Throws std::invalid_argument for a parameter out of range.
  explicit MultiSurfaceForce(MultiSurfaceConfig config);

  /// New ray hits at time t [s] (a layer not found keeps no plane).
  void set_hits(const SurfaceLayerHits& hits, double t);
  /// Composable: a disabled layer holds nothing and the next one takes over.
  void set_layer_enabled(std::size_t layer, bool enabled);
  [[nodiscard]] bool layer_enabled(std::size_t layer) const { return enabled_[layer]; }

  /// One haptic frame: the device position `goal`, its velocity, the time.
  MultiSurfaceOutput update(const Vec3& goal, const Vec3& goal_velocity, double t);
  /// The same frame's force without changing any state (to measure a model update's step).
  [[nodiscard]] MultiSurfaceOutput evaluate(const Vec3& goal, const Vec3& goal_velocity, double t) const;

  /// The collision ray for the next query: from the proxy along this unit direction (towards
  /// the device while pressing, else along the last motion; initially −z).
  [[nodiscard]] const Vec3& ray_origin() const { return proxy_; }
  [[nodiscard]] const Vec3& ray_direction() const { return direction_; }
  [[nodiscard]] const MultiSurfaceConfig& config() const { return config_; }

 private:
  struct Plane {
    Vec3 normal = Vec3::UnitZ();
    double offset = 0.0;
  };
  struct LayerPlanes {
    bool valid = false;
    Plane from, to;
    double start = 0.0;
    SurfaceLayerHit hit;
  };
  [[nodiscard]] Plane shown(const LayerPlanes& l, double t) const;

  MultiSurfaceConfig config_;
  std::array<LayerPlanes, kMaxSurfaceLayers> planes_{};
  std::array<bool, kMaxSurfaceLayers> enabled_{};
  Vec3 proxy_ = Vec3::Zero();
  Vec3 direction_ = Vec3(0, 0, -1);
  bool anchored_ = false;  ///< in contact with friction: proxy_ is the friction anchor
  int anchor_layer_ = -1;
  bool started_ = false;  ///< proxy_ holds a rendered position
};

}  // namespace tactus::haptics
