#pragma once
// Fingertips as rigid capsules (seed 002 §V: the thumb and the index of a two-finger
// grasp), and the geometric queries their contact models need: closest points on
// segments, point–capsule and capsule–capsule signed distances, segment–triangle closest
// points, and continuous collision of a particle against a capsule moving between two
// poses. See docs/grasp.md.
//
// Every query is noexcept and allocation-free (the haptic loop calls them); only
// validate() throws, for a bad shape. Units SI.
#include "core/math.hpp"

namespace tactus::contact {

/// A rigid placement: world = position + orientation · local.
struct Pose {
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();  ///< unit

  [[nodiscard]] Vec3 to_world(const Vec3& local) const { return position + orientation * local; }
  [[nodiscard]] Vec3 to_local(const Vec3& world) const { return orientation.conjugate() * (world - position); }
};

/// Finite position and orientation, the orientation not zero (a device's pose checked before use).
[[nodiscard]] inline bool finite_pose(const Pose& p) {
  return p.position.allFinite() && p.orientation.coeffs().allFinite() && p.orientation.norm() > 0.0;
}

/// A fingertip in its own frame: the capsule around the segment base → tip.
struct CapsuleShape {
  Vec3 base = Vec3::Zero();              ///< axis end toward the hand, m
  Vec3 tip = Vec3(0.0, 0.0, 0.012);      ///< axis end at the fingertip, m
  double radius = 0.008;                 ///< m
  /// The palmar side (where the pad is), unit and across the axis. Only the two-finger
  /// grasp uses it: the pad is taken as flat, the plane with this normal touching the
  /// capsule (seed 002 §V-D: "the contact surface of both fingers planar").
  Vec3 pad_normal = Vec3(0.0, -1.0, 0.0);
};

/// Throws InputError naming `who` unless base and tip are finite, the radius positive and
/// finite, and the pad normal finite and not along the axis (its axial part is ignored).
void validate(const CapsuleShape& shape, const char* who);

/// A capsule placed in the world.
struct Capsule {
  Vec3 base = Vec3::Zero();
  Vec3 tip = Vec3::Zero();
  double radius = 0.0;
};

[[nodiscard]] Capsule posed(const CapsuleShape& shape, const Pose& pose) noexcept;

/// The unit pad normal of `shape` in the world: its part across the axis, normalised.
[[nodiscard]] Vec3 pad_normal(const CapsuleShape& shape, const Pose& pose) noexcept;

struct SegmentPoint {
  double t = 0.0;  ///< in [0, 1] from a to b
  Vec3 point = Vec3::Zero();
};

/// The point of segment ab closest to p (a point segment gives a).
[[nodiscard]] SegmentPoint closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) noexcept;

struct SegmentPair {
  double s = 0.0;  ///< on the first segment, [0, 1]
  double t = 0.0;  ///< on the second, [0, 1]
  Vec3 on_first = Vec3::Zero();
  Vec3 on_second = Vec3::Zero();
  double distance = 0.0;
};

/// Closest points of segments p0p1 and q0q1 (Ericson, Real-Time Collision Detection
/// §5.1.9). Parallel segments have many closest pairs: this returns the one in the middle
/// of their overlap, so the answer moves continuously as they slide along each other.
[[nodiscard]] SegmentPair closest_points_segments(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                                  const Vec3& q1) noexcept;

struct SegmentTrianglePair {
  double t = 0.0;                   ///< on the segment, [0, 1]
  Vec3 on_segment = Vec3::Zero();
  Vec3 on_triangle = Vec3::Zero();
  Vec3 barycentric = Vec3::Zero();  ///< of on_triangle, weights of a, b, c
  double distance = 0.0;            ///< 0 when the segment pierces the triangle
};

/// Closest points of segment p0p1 and triangle abc: the piercing point if the segment
/// crosses the face, otherwise the best of the two end points against the face and the
/// segment against the three edges (both sets convex, so one of these pairs is closest).
[[nodiscard]] SegmentTrianglePair closest_points_segment_triangle(const Vec3& p0, const Vec3& p1, const Vec3& a,
                                                                  const Vec3& b, const Vec3& c) noexcept;

struct CapsulePoint {
  double signed_distance = 0.0;  ///< from p to the capsule surface; negative inside, m
  Vec3 surface_point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();   ///< unit outward normal at surface_point (toward p when outside)
  double axis_t = 0.0;           ///< where on the axis, [0, 1] base → tip
};

/// p against the capsule. A point on the axis itself has no unique normal: it gets one
/// across the axis (deterministic), so the answer stays finite.
[[nodiscard]] CapsulePoint point_capsule(const Vec3& p, const Capsule& capsule) noexcept;

struct CapsulePair {
  double signed_distance = 0.0;  ///< gap between the surfaces; minus the penetration when they overlap, m
  Vec3 on_first = Vec3::Zero();  ///< surface point of the first capsule, along the normal
  Vec3 on_second = Vec3::Zero(); ///< surface point of the second, against the normal
  Vec3 normal = Vec3::UnitZ();   ///< unit, from the first capsule toward the second
  double s = 0.0;                ///< axis parameter of the first
  double t = 0.0;                ///< axis parameter of the second
};

/// Capsule against capsule: the axes' closest points, pushed out by the radii.
[[nodiscard]] CapsulePair capsule_capsule(const Capsule& first, const Capsule& second) noexcept;

struct ParticleSweep {
  bool hit = false;
  double time = 1.0;         ///< of impact, in [0, 1]; 1 when there is none
  Vec3 particle = Vec3::Zero();  ///< where the particle is then
  Vec3 normal = Vec3::UnitZ();   ///< the capsule's outward normal there
  double signed_distance = 0.0;  ///< at `time` (within the tolerance of 0 for a converged hit)
  int iterations = 0;
  /// False when max_iterations ran out before the gap closed or the motion ended (a long
  /// graze): the sweep then reports a hit at the last safe time, so nothing passes through.
  bool converged = true;
};

struct SweepOptions {
  double tolerance = 1e-6;  ///< the gap that counts as touching, m
  int max_iterations = 64;
};

/// Continuous collision of a particle moving p0 → p1 against a capsule moving pose0 →
/// pose1 (position interpolated linearly, orientation by slerp), both over t ∈ [0, 1]. By
/// conservative advancement: the gap's rate of change is bounded by
///   B = |p1 − p0| + |c1 − c0| + θ·L
/// (θ the rotation angle, L the farthest axis point from the pose origin), so the gap g
/// at t guarantees no contact before t + g/B. A particle inside at t = 0 is a hit at 0.
[[nodiscard]] ParticleSweep sweep_particle_capsule(const Vec3& p0, const Vec3& p1, const CapsuleShape& shape,
                                                   const Pose& pose0, const Pose& pose1,
                                                   const SweepOptions& options = {}) noexcept;

}  // namespace tactus::contact
