#pragma once
// What a device's haptic step exchanges with the slower loops about the tissue: the local
// contact plane the interaction loop found, and the reaction the tissue takes from the
// force the hand was sent. Fixed-size, so the haptic loop never allocates.
#include <array>
#include <cstdint>
#include <limits>

#include "core/math.hpp"

namespace tactus::haptics {

/// The local model of one device's contact region (seed 003 §3.5: a constraint plane
/// through the closest surface point), rebuilt by the interaction loop.
struct LocalContact {
  bool valid = false;             ///< a surface is within reach of the tool
  std::int32_t body = -1;         ///< index into Model::bodies
  std::int32_t triangle = -1;     ///< surface triangle of `point`
  Vec3 point = Vec3::Zero();      ///< plane point on the surface [m]
  Vec3 normal = Vec3::UnitZ();    ///< plane normal, pointing out of the tissue
  Vec3 barycentric = Vec3::Zero();
  /// Mean curvature of the tissue at `point` [1/m], positive where convex (seed 000 §3.2);
  /// estimated only for algorithms that use it, else 0.
  double mean_curvature = 0.0;
  /// When the simulation published the surface it was built from (loop time) [s]: the
  /// safety watchdog's measure of a stalled simulation.
  double surface_time = 0.0;
};

/// The reaction of one device's contact on the tissue, applied by the next simulation step.
struct ContactLoad {
  bool active = false;
  std::int32_t body = -1;
  std::int32_t triangle = -1;
  Vec3 barycentric = Vec3::Zero();
  Vec3 force = Vec3::Zero();  ///< on the tissue, scene coordinates [N]
  /// How fast `force` falls for each metre the tissue under the contact gives way along it
  /// (the contact law's slope, as sent) [N/m]: the simulation couples the push implicitly
  /// (physics::ContactSpring). 0: a constant push.
  double stiffness = 0.0;
  /// How far the contact point had moved along `force` from the surface the simulation last
  /// published when `force` was rendered (a local patch deforms between steps) [m]: where
  /// that surface stands, the push is stiffness·surface_offset more.
  double surface_offset = 0.0;
  /// Where that published surface had the contact's material point [m]; NaN where no patch
  /// gave one. In real time the simulation may have stepped again before it reads `force`:
  /// from the surface it steps from, the push is stiffness times how far the point has moved
  /// along `force` since then less.
  Vec3 published_point = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  /// A hold (a grasp's, across the pads' plane): the simulation's spring pulls back as well
  /// as it pushes, so the held point cannot overshoot the pads' plane and be let go.
  bool bilateral = false;
  /// A hold along a plane (a grasp's part along the pads' plane), as a unit normal of that
  /// plane; zero: none. The simulation holds the point in the whole plane, with `stiffness`
  /// across `force` as well as along it, both ways: along `force` alone the point was free
  /// to slide across it during a step, and the next patch stepped the hold.
  Vec3 hold_plane_normal = Vec3::Zero();
  /// Radius of the contact disc the force is spread over (contact/load_spread.hpp) [m].
  double contact_radius = 0.0;
  /// A sphere-set finger on a patch: each touching sphere's contact and its share of `force`
  /// (the shares sum to 1), spread each over its own disc. None: the contact above takes all.
  struct Part {
    std::int32_t triangle = -1;
    Vec3 barycentric = Vec3::Zero();
    double share = 0.0;
    double contact_radius = 0.0;
  };
  static constexpr int kMaxParts = 8;
  std::array<Part, kMaxParts> parts{};
  int part_count = 0;
  /// A pad of a pinch that holds `body` (seed 002 §V-D): the simulation keeps the body's
  /// nodes out of the pad's capsule on its own side of the pinch's plane, as real pads keep
  /// the fabric between them; the grasp's share above holds one point of it.
  struct Pad {
    bool active = false;
    Vec3 base = Vec3::Zero(), tip = Vec3::Zero();  ///< the capsule's axis [m]
    double radius = 0.0;                           ///< [m]
    Vec3 plane_point = Vec3::Zero();               ///< on the pinch's plane [m]
    Vec3 toward_partner = Vec3::UnitZ();           ///< the plane's unit normal, toward the other pad
  };
  Pad pad;
  /// A needle's shaft inside the tissue: `shaft_force` (on the tissue) is shared by the
  /// tissue nodes near the segment shaft_from → shaft_to of `body` (or its host).
  bool shaft = false;
  Vec3 shaft_from = Vec3::Zero(), shaft_to = Vec3::Zero();
  Vec3 shaft_force = Vec3::Zero();
};

/// A material point of a body's surface: its triangle in the body's numbering (−1: none) and
/// barycentric coordinates. Every patch of the body finds it again by that triangle.
struct MaterialPoint {
  std::int32_t body = -1;
  std::int32_t triangle = -1;
  Vec3 barycentric = Vec3::Zero();
  [[nodiscard]] bool valid() const { return body >= 0 && triangle >= 0; }
};

/// What a fingertip's loop tells its partner finger's loop each frame (seed 002: the thumb
/// and the index, each on its own device): its pose and its side of the contact.
struct PeerFinger {
  bool valid = false;             ///< published at least once
  Vec3 position = Vec3::Zero();   ///< tool frame origin, scene [m]
  Quat orientation = Quat::Identity();
  bool on_fabric = false;         ///< its V-proxy touches the fabric, or it holds it in the grasp
  bool slipping = false;          ///< its contact slips (dynamic friction)
  MaterialPoint held;             ///< the material point its grasp holds; invalid outside a grasp
};

}  // namespace tactus::haptics
