#pragma once
// The two-finger grasp (seed 002 §V-D, contact states VIII and IX): fabric squeezed between
// the thumb's and the index's pads. Each pad is taken as flat: the plane touching its
// capsule on the palmar side (CapsuleShape::pad_normal). A shared frame is built from the
// two pad planes (the line where they meet and its perpendicular bisector, see SharedFrame);
// the fabric particles caught between the pads are held at their projections onto the
// shared contact plane, stored in that frame when the grasp starts, so they move with the
// fingers. A nonlinear spring pulls each particle toward its target; the pads squeeze each
// other through the fabric with the fingerpad law. While the total tangential load stays
// within μ_s times the squeeze the targets stay put; beyond it they slide together so that
// the load is μ_k times the squeeze. See docs/grasp.md.
//
// update() allocates nothing (the held list has a capacity fixed at construction) and
// throws nothing.
#include <cstdint>
#include <numbers>
#include <span>
#include <vector>

#include "contact/fingertip.hpp"
#include "contact/hertz.hpp"
#include "contact/proxy.hpp"
#include "core/math.hpp"

namespace tactus::contact {

/// The grasp's frame of reference. e3 is the unit normal of the shared contact plane,
/// pointing from the thumb toward the index: the bisector n_t − n_i of the pad normals (n_t
/// the thumb's pad normal, n_i the index's, each pointing at the other finger), so the plane
///   (n_t − n_i)·x = o_t − o_i   (o the offsets of the pad planes n·x = o)
/// is where the two pads are equally far, and contains the line where they meet. e1 runs
/// along that line, e1 = (n_t × n_i)/|n_t × n_i|, and e2 = e3 × e1 is the direction of its
/// perpendicular bisector in the contact plane. The origin is the midpoint of the two pad
/// centres (each axis centre moved out by the radius along the pad normal), projected onto
/// the contact plane: between the fingers, rather than on the line, which runs off to
/// infinity as the pads turn parallel, and continuous in the fingers' poses.
/// Parallel pads (|n_t × n_i| below the threshold) meet nowhere: e1 is then the thumb's axis
/// projected onto the contact plane (the index's if the thumb's is along e3, any direction
/// across e3 if both are). (e1, e2, e3) is right-handed and orthonormal.
struct SharedFrame {
  Vec3 origin = Vec3::Zero();
  Mat3 axes = Mat3::Identity();  ///< columns e1, e2, e3
  bool parallel = false;         ///< built by the parallel-pad rule
  double pad_sine = 0.0;         ///< |n_t × n_i|, the sine of the angle between the pad planes

  [[nodiscard]] Vec3 normal() const { return axes.col(2); }
  [[nodiscard]] Vec3 to_world(const Vec2& in_plane) const {
    return origin + in_plane.x() * axes.col(0) + in_plane.y() * axes.col(1);
  }
  [[nodiscard]] Vec3 to_local(const Vec3& world) const { return axes.transpose() * (world - origin); }
};

/// The shared frame of the two fingers; pads count as parallel when |n_t × n_i| <
/// `parallel_sine`.
[[nodiscard]] SharedFrame shared_frame(const CapsuleShape& thumb, const Pose& thumb_pose, const CapsuleShape& index,
                                       const Pose& index_pose, double parallel_sine) noexcept;

struct GraspParams {
  CapsuleShape thumb;
  CapsuleShape index;
  FingerpadParameters squeeze_law;  ///< pad on pad through the fabric (eq. 1)
  /// The spring that pulls the held particles toward their targets, F(d) of eq. 1's form on
  /// the distance d. The held particles share it: each gets F(d_j)/N (N of them held), so
  /// that the fabric moved as a whole by d pulls back with F(d) whatever the mesh density.
  FingerpadParameters hold_law;
  double fabric_thickness = 0.5e-3;  ///< the pads squeeze once closer than this, m
  /// A particle is caught when it is within this distance of both capsules (or inside
  /// them), m.
  double capture_distance = 1e-3;
  /// Effective coefficients of the whole pinch. A sheet held between two pads rubs on both,
  /// so with a pad–fabric coefficient μ the pinch holds 2μ times the squeeze: pass 2μ.
  double static_friction = 1.0;
  double kinetic_friction = 0.8;
  /// Pads closer to parallel than this use the parallel rule (rad); once in it, a grasp
  /// leaves it only beyond 1.5 times this, so the frame does not flip back and forth.
  double parallel_angle = 10.0 * std::numbers::pi / 180.0;
  std::size_t max_particles = 256;  ///< the held list's capacity; more caught ones are ignored
};

struct HeldParticle {
  std::int32_t index = -1;        ///< into the caller's positions
  Vec2 anchor = Vec2::Zero();     ///< target in the shared frame (e1, e2), m
  Vec3 target = Vec3::Zero();     ///< the same in the world, this step
  Vec3 force = Vec3::Zero();      ///< on the particle, N
};

struct GraspState {
  bool active = false;
  FrictionState friction = FrictionState::none;
  SharedFrame frame;  ///< of the last step
  std::vector<HeldParticle> held;  ///< capacity reserved by Grasp::make_state
};

struct GraspResult {
  bool active = false;
  FrictionState friction = FrictionState::none;
  SharedFrame frame;
  double squeeze_depth = 0.0;        ///< fabric thickness minus the capsules' gap, m
  double squeeze_force = 0.0;        ///< F^N of the pads on each other, N
  Vec3 squeeze_normal = Vec3::UnitZ();  ///< unit, thumb toward index, of the capsules' closest points
  double tangential_load = 0.0;      ///< |Σ tangential particle forces|, N
  Vec3 force_on_thumb = Vec3::Zero();  ///< N
  Vec3 force_on_index = Vec3::Zero();  ///< N
  std::span<const HeldParticle> held;  ///< into the state; valid until its next update
  int ignored = 0;  ///< caught particles left out because the held list was full
  bool input_rejected = false;
};

class Grasp {
 public:
  /// Throws InputError naming the parameter that is out of range.
  explicit Grasp(const GraspParams& params);

  [[nodiscard]] const GraspParams& params() const { return params_; }
  /// A state with the held list's capacity reserved.
  [[nodiscard]] GraspState make_state() const;

  /// One step. `candidates` lists the particles near the fingers (indices into
  /// `positions`; out of range ones are skipped). The grasp holds while the pads squeeze
  /// (depth > 0) and at least one particle is caught; otherwise it lets go and the state
  /// is cleared. Particles leave the held list when they are no longer caught and join it,
  /// held where they are, when they become caught.
  [[nodiscard]] GraspResult update(GraspState& state, const Pose& thumb, const Pose& index,
                                   std::span<const Vec3> positions,
                                   std::span<const std::int32_t> candidates) const noexcept;

 private:
  GraspParams params_;
  FingerpadLaw squeeze_;
  FingerpadLaw hold_;
};

/// The grasp on a fabric meshed coarser than the pads' contact (the fabric scene's 5 mm
/// against a lens of pad overlap a few millimetres wide, where Grasp would catch its nodes one
/// at a time): one material point of the fabric, the one between the pads when the grasp
/// starts, stands for the particles between them (seed 002 §V-D). It is held at its
/// projection onto the shared contact plane, stored in the shared frame so it moves with the
/// fingers, by a linear spring; the tangential part of the spring's pull stays within
/// μ_s·F^N while the grasp sticks, and beyond it the anchor slides so the pull is μ_k·F^N;
/// across the plane it is bounded by F^N (a pad pushes no harder than the squeeze), so the
/// whole hold fades with the squeeze as the pads open.
/// The pads squeeze each other with the squeeze law; each takes half the reaction of the
/// hold. update() allocates nothing and throws nothing.
struct PointGraspState {
  bool active = false;
  FrictionState friction = FrictionState::none;
  Vec2 anchor = Vec2::Zero();  ///< the held point's target in the shared frame (e1, e2), m
  SharedFrame frame;           ///< of the last step
};

struct PointGraspResult {
  bool active = false;
  FrictionState friction = FrictionState::none;
  SharedFrame frame;
  double squeeze_depth = 0.0;  ///< fabric thickness minus the capsules' gap, m
  double squeeze_force = 0.0;  ///< F^N, N
  Vec3 target = Vec3::Zero();  ///< where the held point is pulled, m
  Vec3 hold = Vec3::Zero();    ///< the spring's force on the fabric, N
  Vec3 force_on_thumb = Vec3::Zero();  ///< N
  Vec3 force_on_index = Vec3::Zero();  ///< N
  bool input_rejected = false;
};

class PointGrasp {
 public:
  /// `params` as for Grasp (its shapes, squeeze law, thickness, friction and frame rule; the
  /// hold law, capture distance and capacity play no part); `hold_stiffness` of the spring,
  /// N/m. Throws InputError naming what is out of range.
  PointGrasp(const GraspParams& params, double hold_stiffness);

  [[nodiscard]] const GraspParams& params() const { return grasp_.params(); }
  [[nodiscard]] double hold_stiffness() const { return hold_stiffness_; }

  /// One step with the held material point at `point`. An inactive grasp starts when
  /// `may_start` (the caller knows the fabric lies between the pads) and the pads squeeze
  /// (depth > 0), holding the point where it projects onto the contact plane; an active one
  /// lets go when the pads open (depth ≤ 0) or the point is not finite (lost).
  [[nodiscard]] PointGraspResult update(PointGraspState& state, const Pose& thumb, const Pose& index,
                                        const Vec3& point, bool may_start) const noexcept;
  /// Holds `to` instead of `from` with the same pull along the plane: the target moves by
  /// the in-plane part of to − from. A slipping pinch passes over new material: the caller
  /// moves the hold to the point now between the pads, so that it stays there.
  static void move_hold(PointGraspState& state, const Vec3& from, const Vec3& to) noexcept;

 private:
  Grasp grasp_;  ///< validates the shared parameters
  FingerpadLaw squeeze_;
  double hold_stiffness_;
};

}  // namespace tactus::contact
