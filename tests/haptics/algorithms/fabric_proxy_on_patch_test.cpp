// A fingertip resting on a fabric's patch keeps its contact, and its force, when the
// simulation publishes a new patch whose triangles are numbered otherwise: the proxy finds
// the material point it rests on again by the body's triangle. A thumb–index pair, each on
// its own haptic step and reading the other's frames, feels the fingers meet (Table I, II
// and III) and the fabric squeezed between them (VIII, IX) with the laws' own numbers.
#include "haptics/algorithms/fabric_proxy_on_patch.hpp"

#include <gtest/gtest.h>

#include "../fixtures/step_rig.hpp"
#include "contact/grasp_state.hpp"
#include "mesh/generators.hpp"

namespace tactus::haptics {
namespace {

/// Rigid patches of a 10 × 10 cm sheet in z = 0 (normals +z, 5 mm grid, a node at the
/// origin): the sheet stays put, so any change of force comes from the fingers or an update.
struct RigidSheet {
  RigidSheet() = default;
  /// The sheet with its nodes moved by `shape` (a fold, say).
  template <class Shape>
  explicit RigidSheet(Shape shape) {
    for (Vec3& v : plate.vertices) shape(v);
  }
  mesh::TriMesh plate = mesh::grid_plate(0.1, 0.1, 20, 20);
  const contact::PatchCapacity capacity{48, 128, 240};
  const contact::LocalModelKind kind = contact::LocalModelKind::compliance;
  contact::PatchBuilder builder{plate.vertices.size(), plate.triangles, capacity};
  /// The patch of `radius` around `center`, its nodes numbered nearest first.
  [[nodiscard]] contact::LocalPatch around(const Vec3& center, double radius = 0.02) {
    contact::PatchBuilder::Inputs in;
    in.kind = kind;
    in.body = 0;
    in.radius = radius;
    in.surface = plate.vertices;
    in.rigid = true;
    in.center = center;
    contact::LocalPatch patch(kind, capacity);
    builder.build(in, patch);
    return patch;
  }
};

TEST(FabricProxyOnPatch, KeepsItsContactAcrossAPatchNumberedOtherwise) {
  RigidSheet sheet;
  const contact::PatchCapacity& capacity = sheet.capacity;
  const contact::LocalPatch first = sheet.around(Vec3(0, 0, 0.01));
  const contact::LocalPatch second = sheet.around(Vec3(0.012, 0.007, 0.01));  // other nodes, other numbers

  contact::FabricProxyParams p;
  p.finger.base = p.finger.tip = Vec3::Zero();
  p.finger.radius = 0.008;
  p.stiffness = 190.0;
  test::StepRig rig(test::model_of({std::make_shared<FabricProxyOnPatch>(p, sheet.kind, capacity, false)}));
  rig.plane(0.0);
  rig.patch = &first;
  rig.patch_fresh = true;
  rig.hold(Vec3(0.003, 0.002, 0.012), 5);
  rig.hold(Vec3(0.003, 0.002, 0.007), 50, 0.005);  // 1 mm into the sheet's reach
  ASSERT_TRUE(rig.out.touching);
  const Vec3 before = rig.sink.force;
  EXPECT_NEAR(before.z(), 190.0 * 0.001, 1e-6);

  rig.patch = &second;
  rig.patch_fresh = true;
  rig.hold(Vec3(0.003, 0.002, 0.007), 1, 0.055);
  EXPECT_TRUE(rig.out.touching);
  EXPECT_LT((rig.sink.force - before).norm(), 1e-9);
}

/// A thumb and an index, spheres of 9 and 8 mm, each its own haptic step. The sheet's front
/// faces +z: the thumb comes from above, its pad facing −z, the index from below.
struct Pair {
  explicit Pair(const contact::PatchCapacity& capacity, contact::LocalModelKind kind)
      : thumb(test::model_of({algorithm(+1, 0.009, 0.008, capacity, kind)})),
        index(test::model_of({algorithm(-1, 0.008, 0.009, capacity, kind)})) {
    thumb.peer = &index_frame;
    index.peer = &thumb_frame;
  }
  static std::shared_ptr<const FabricProxyOnPatch> algorithm(int side, double own_radius, double partner_radius,
                                                             const contact::PatchCapacity& capacity,
                                                             contact::LocalModelKind kind) {
    contact::FabricProxyParams p;
    p.finger.base = p.finger.tip = Vec3::Zero();
    p.finger.radius = own_radius;
    p.stiffness = 190.0;
    p.side = side;
    TwoFingerParams two;
    two.own = p.finger;
    two.own.pad_normal = Vec3(0, 0, -side);
    two.partner.base = two.partner.tip = Vec3::Zero();
    two.partner.radius = partner_radius;
    two.partner.pad_normal = Vec3(0, 0, side);
    return std::make_shared<FabricProxyOnPatch>(p, kind, capacity, false, two);
  }
  /// One frame of each, the thumb first, each reading the other's newest frame.
  void step(double t, const Vec3& thumb_at, const Vec3& index_at) {
    thumb.step(t, thumb_at);
    thumb_frame = thumb.out.finger;
    index.step(t, index_at);
    index_frame = index.out.finger;
  }
  /// Each pad 0.45 mm past a sheet in z = 0 near the origin, held there for 50 frames from
  /// t: the grasp. Returns the time after them.
  static inline const Vec3 kThumbPinching{0, 0, 0.00855}, kIndexPinching{0, 0, -0.00755};
  double pinch(const contact::LocalPatch& patch, double t) {
    thumb.patch = index.patch = &patch;
    thumb.patch_fresh = index.patch_fresh = true;
    for (int k = 0; k < 50; ++k, t += 1e-3) step(t, kThumbPinching, kIndexPinching);
    return t;
  }
  test::StepRig thumb, index;
  PeerFinger thumb_frame, index_frame;
};

std::uint8_t state_of(const test::StepRig& rig) { return rig.state.contact_state; }

TEST(FabricProxyOnPatch, FingersMeetingWithoutFabricFeelThePadLawEqualAndOpposite) {
  Pair pair({48, 128, 240}, contact::LocalModelKind::compliance);
  // Centres 16.1 mm apart, radii 9 + 8 mm: the pads overlap by 0.9 mm; no fabric anywhere.
  const Vec3 thumb_at(0, 0, 0.0085), index_at(0, 0, -0.0076);
  for (int k = 0; k < 50; ++k) pair.step(1e-3 * k, thumb_at, index_at);
  const double expected = contact::FingerpadLaw{}.force(0.9e-3);  // (b/m)(e^{m·d} − 1), eq. 1
  EXPECT_NEAR(pair.thumb.sink.force.z(), expected, 1e-9);
  EXPECT_LT((pair.thumb.sink.force + pair.index.sink.force).norm(), 1e-12);
  EXPECT_EQ(state_of(pair.thumb), static_cast<std::uint8_t>(contact::ContactState::II));
  EXPECT_EQ(state_of(pair.index), static_cast<std::uint8_t>(contact::ContactState::II));
  EXPECT_FALSE(pair.thumb.load.active);  // no fabric takes any of it

  // The index slides along the thumb: the anchor spring drags until μs·F^N, then slips.
  double t = 0.05;
  for (int k = 0; k < 400 && state_of(pair.index) != static_cast<std::uint8_t>(contact::ContactState::III); ++k, t += 1e-3)
    pair.step(t, thumb_at, index_at + Vec3(2e-5 * k, 0, 0));
  EXPECT_EQ(state_of(pair.index), static_cast<std::uint8_t>(contact::ContactState::III));
  const double mu_s = contact::FingerContactParams{}.static_friction;
  EXPECT_LE(std::abs(pair.index.sink.force.x()), mu_s * expected * 1.001);
  // The rub turns each finger about its origin: the force acts where the pads meet, midway
  // between their surface points. The index saw the thumb's frame of this step, the thumb
  // the index's one frame before (one frame's 0.02 mm of slide apart).
  const auto torque_at = [](const Vec3& own, double own_radius, const Vec3& other, double other_radius,
                            const Vec3& force) {
    const Vec3 n = (other - own).normalized();
    const Vec3 where = 0.5 * ((own + own_radius * n) + (other - other_radius * n));
    return Vec3((where - own).cross(force));
  };
  const Vec3 index_now = pair.index.out.position, thumb_now = pair.thumb.out.position;
  const Vec3 on_index = torque_at(index_now, 0.008, thumb_now, 0.009, pair.index.sink.force);
  EXPECT_GT(std::abs(pair.index.sink.torque.y()), 1e-5);  // 8 mm × the friction, 0.1 N or more
  EXPECT_LT((pair.index.sink.torque - on_index).norm(), 1e-12);
  // The thumb's contact point is the one of the index's last frame, 0.02 mm back along x: its
  // lever differs by half of that at most.
  const Vec3 on_thumb = torque_at(thumb_now, 0.009, index_now, 0.008, pair.thumb.sink.force);
  EXPECT_GT(std::abs(pair.thumb.sink.torque.y()), 1e-5);
  EXPECT_LT((pair.thumb.sink.torque - on_thumb).norm(), 1.01e-5 * pair.thumb.sink.force.norm());
}

TEST(FabricProxyOnPatch, FabricSqueezedBetweenThePairIsGraspedWithTheSqueezeLaw) {
  RigidSheet sheet;
  const contact::LocalPatch patch = sheet.around(Vec3::Zero());

  Pair pair(sheet.capacity, sheet.kind);
  pair.thumb.patch = pair.index.patch = &patch;
  pair.thumb.patch_fresh = pair.index.patch_fresh = true;
  // Each pad 0.45 mm past the sheet: the pads 0.9 mm into each other through the sheet, which
  // lies in the shared contact plane (where the pads are equally far).
  const Vec3 thumb_at(0, 0, 0.00855), index_at(0, 0, -0.00755);
  for (int k = 0; k < 50; ++k) pair.step(1e-3 * k, thumb_at, index_at);
  const double squeeze = contact::FingerpadLaw{}.force(0.5e-3 + 0.9e-3);  // thickness − gap
  EXPECT_EQ(state_of(pair.thumb), static_cast<std::uint8_t>(contact::ContactState::VIII));
  EXPECT_EQ(state_of(pair.index), static_cast<std::uint8_t>(contact::ContactState::VIII));
  EXPECT_NEAR(pair.thumb.sink.force.z(), squeeze, 1e-9);
  EXPECT_NEAR(pair.index.sink.force.z(), -squeeze, 1e-9);
  EXPECT_LT(Vec3(pair.thumb.sink.force.x(), pair.thumb.sink.force.y(), 0).norm(), 1e-12);
  // The fabric takes the hold, not the squeezes, which cancel on it: held where it lies, none.
  // Each pad keeps the sheet out of it in the simulation.
  EXPECT_TRUE(pair.thumb.load.active);
  EXPECT_LT((pair.thumb.load.force + pair.index.load.force).norm(), 1e-9);
  EXPECT_TRUE(pair.thumb.load.pad.active);
  EXPECT_TRUE(pair.index.load.pad.active);
  EXPECT_NEAR(pair.thumb.load.pad.toward_partner.z(), -1.0, 1e-12);
  EXPECT_NEAR(pair.index.load.pad.toward_partner.z(), 1.0, 1e-12);

  // Both fingers pull along the rigid sheet: the held particles drag until the pinch slips,
  // and the pull stays within the Coulomb bound of both pads, 2·μ times the squeeze.
  double t = 0.05;
  for (int k = 0; k < 400 && state_of(pair.thumb) != static_cast<std::uint8_t>(contact::ContactState::IX); ++k, t += 1e-3)
    pair.step(t, thumb_at + Vec3(5e-5 * k, 0, 0), index_at + Vec3(5e-5 * k, 0, 0));
  EXPECT_EQ(state_of(pair.thumb), static_cast<std::uint8_t>(contact::ContactState::IX));
  const double pull = -(pair.thumb.sink.force.x() + pair.index.sink.force.x());
  EXPECT_GT(pull, 0.0);
  EXPECT_LE(pull, 2.0 * 0.5 * squeeze * 1.001);  // μs of the pads on the fabric, doubled
  // The pinch acts on each pad where it meets the fabric, the pad's point nearest the held
  // point (the frame's contact point): its drag along the sheet turns the finger about its
  // origin.
  for (const auto* finger : {&pair.thumb, &pair.index}) {
    const Vec3 at = finger->out.position;
    const double radius = finger == &pair.thumb ? 0.009 : 0.008;
    EXPECT_LT(std::abs(finger->out.frame_point.z()), 1e-12);  // on the sheet
    const Vec3 on_pad = at + radius * (finger->out.frame_point - at).normalized();
    EXPECT_LT((finger->sink.torque - (on_pad - at).cross(finger->sink.force)).norm(), 1e-12);
    EXPECT_GT(std::abs(finger->sink.torque.y()), 0.9 * radius * std::abs(finger->sink.force.x()));
  }
  // The fabric takes the hold, the fingers' reaction: the thumb's loop the part across the
  // pads' plane, as a spring that pulls back too, the index's the part along it. Each loop
  // sees the other's pose of its last frame: they differ by one frame of the pull's 0.05 mm
  // at the hold's 190 N/m, 9.5 mN at most.
  const Vec3 reaction = -(pair.thumb.sink.force + pair.index.sink.force);
  EXPECT_LT((pair.thumb.load.force + pair.index.load.force - reaction).norm(), 190.0 * 5e-5);
  EXPECT_LT(Vec3(pair.thumb.load.force.x(), pair.thumb.load.force.y(), 0).norm(), 1e-12);
  EXPECT_NEAR(pair.index.load.force.z(), 0.0, 1e-12);
  EXPECT_TRUE(pair.thumb.load.bilateral);
  EXPECT_FALSE(pair.index.load.bilateral);
  EXPECT_GT(pair.index.load.force.x(), 0.0);
  // The index's part holds the point in the whole pads' plane (the sheet's, z = 0).
  EXPECT_EQ(pair.thumb.load.hold_plane_normal, Vec3::Zero());
  EXPECT_NEAR(std::abs(pair.index.load.hold_plane_normal.z()), 1.0, 1e-12);
  // Once the pads open, the index's next load is a V-proxy's push again, not a hold.
  for (int k = 0; k < 30; ++k, t += 1e-3) pair.step(t, thumb_at + Vec3(0, 0, 0.02), index_at - Vec3(0, 0, 0.02));
  EXPECT_EQ(pair.index.load.hold_plane_normal, Vec3::Zero());
}

// A pinch slipping toward a fold of the sheet: past x = 5 mm the sheet rises 3 mm off the
// pads' plane. The material nearest the pads' centre then lies on the fold; holding it would
// step the hold's pull onto the plane (190 N/m · 3 mm), and each finger's force by half of
// that, in one frame. The pinch keeps the material it holds instead, and slips on smoothly.
TEST(FabricProxyOnPatch, ASlippingPinchTakesNoHoldOfAFoldOffItsPlane) {
  RigidSheet sheet([](Vec3& v) {
    if (v.x() > 0.0075) v.z() += 0.003;
  });
  const contact::LocalPatch patch = sheet.around(Vec3::Zero(), 0.03);
  Pair pair(sheet.capacity, sheet.kind);
  double t = pair.pinch(patch, 0.0);
  const Vec3& thumb_at = Pair::kThumbPinching;
  const Vec3& index_at = Pair::kIndexPinching;
  ASSERT_EQ(state_of(pair.thumb), static_cast<std::uint8_t>(contact::ContactState::VIII));
  // Both fingers slide 20 mm along +x at 50 mm/s: the pinch sticks, then slips from about
  // 8.6 mm on (the pull falling from μ_s to μ_k of the squeeze, in a frame), over the fold.
  Vec3 last = pair.thumb.sink.force;
  double largest_step = 0.0;
  int slipping = 0;
  for (int k = 0; k < 400; ++k, t += 1e-3) {
    const Vec3 shift(5e-5 * k, 0, 0);
    pair.step(t, thumb_at + shift, index_at + shift);
    ASSERT_TRUE(pair.thumb.out.touching) << "frame " << k;
    const bool slips = state_of(pair.thumb) == static_cast<std::uint8_t>(contact::ContactState::IX);
    if (slips && slipping++ > 0) largest_step = std::max(largest_step, (pair.thumb.sink.force - last).norm());
    last = pair.thumb.sink.force;
  }
  EXPECT_GT(slipping, 200);
  // A step onto the fold would be 0.5 · 190 N/m · 3 mm = 0.285 N along z.
  EXPECT_LT(largest_step, 0.02);
}

// Each finger's loop holds the fabric on its own patch, and each patch follows the simulation
// at its own frame. Here the index's new patch leaves the held point out (it lets go), and
// the next one shows the sheet 2 mm toward the thumb, lagging the squeeze: the index's
// V-proxy misses it. The pinch is one grasp: the index takes hold of the thumb's material
// point again at once, so the pads never squeeze the fabric one-sided.
TEST(FabricProxyOnPatch, AFingerThatLostTheHeldPointTakesThePartnersHoldAgain) {
  RigidSheet sheet;
  RigidSheet lagging([](Vec3& v) { v.z() += 0.002; });
  const contact::LocalPatch patch = sheet.around(Vec3::Zero());
  const contact::LocalPatch elsewhere = sheet.around(Vec3(0.04, 0.04, 0), 0.005);
  const contact::LocalPatch lagged = lagging.around(Vec3::Zero());
  Pair pair(sheet.capacity, sheet.kind);
  double t = pair.pinch(patch, 0.0);
  const Vec3& thumb_at = Pair::kThumbPinching;
  const Vec3& index_at = Pair::kIndexPinching;
  ASSERT_EQ(state_of(pair.index), static_cast<std::uint8_t>(contact::ContactState::VIII));
  const MaterialPoint held = pair.thumb.out.finger.held;
  ASSERT_TRUE(held.valid());

  pair.index.patch = &elsewhere;
  pair.index.patch_fresh = true;
  pair.step(t, thumb_at, index_at);
  t += 1e-3;
  EXPECT_FALSE(pair.index.out.finger.held.valid());  // its patch has nothing of the sheet there

  pair.index.patch = &lagged;
  pair.index.patch_fresh = true;
  pair.step(t, thumb_at, index_at);
  t += 1e-3;
  EXPECT_EQ(state_of(pair.index), static_cast<std::uint8_t>(contact::ContactState::VIII));
  EXPECT_EQ(pair.index.out.finger.held.triangle, held.triangle);
  EXPECT_EQ(pair.index.out.finger.held.barycentric, held.barycentric);
  // Its force comes back over 20 ms, never as a step; then the index feels the squeeze
  // (thickness − gap, eq. 1), less half the hold that pulls the material it sees 2 mm off
  // the pads' plane back onto it (at most 190 N/m · 2 mm).
  const double squeeze = contact::FingerpadLaw{}.force(0.5e-3 + 0.9e-3);
  Vec3 last = pair.index.sink.force;
  for (int k = 0; k < 25; ++k, t += 1e-3) {
    pair.step(t, thumb_at, index_at);
    EXPECT_LE((pair.index.sink.force - last).norm(), squeeze / 20.0 * 1.001) << "frame " << k;
    last = pair.index.sink.force;
  }
  EXPECT_NEAR(pair.index.sink.force.z(), -squeeze, 0.5 * 190.0 * 2e-3 * 1.001);
  EXPECT_NEAR(pair.thumb.sink.force.z(), squeeze, 1e-9);
}

// When the pads open the V-proxy takes the contact back: its force comes in over 20 ms from
// the force the grasp left, never as a step, and is the V-proxy's own after that.
TEST(FabricProxyOnPatch, OpeningThePadsHandsTheFabricBackToTheProxyWithoutAStep) {
  RigidSheet sheet;
  const contact::LocalPatch patch = sheet.around(Vec3::Zero());
  Pair pair(sheet.capacity, sheet.kind);
  double t = pair.pinch(patch, 0.0);
  const Vec3& thumb_at = Pair::kThumbPinching;
  ASSERT_EQ(state_of(pair.thumb), static_cast<std::uint8_t>(contact::ContactState::VIII));
  const Vec3 grasped = pair.thumb.sink.force;
  // The index drops away; the thumb stays 0.45 mm into the sheet's reach.
  const Vec3 away(0, 0, -0.03);
  const double proxy_force = 190.0 * 0.45e-3;  // k^K times the thumb's push past the sheet
  const double largest_step = (grasped.z() - proxy_force) / 20.0;
  Vec3 last = grasped;
  for (int k = 0; k < 30; ++k, t += 1e-3) {
    pair.step(t, thumb_at, away);
    const Vec3 now = pair.thumb.sink.force;
    EXPECT_LE((now - last).norm(), largest_step * 1.0001 + 1e-12) << "frame " << k;
    last = now;
  }
  EXPECT_NEAR(pair.thumb.sink.force.z(), proxy_force, 1e-9);
  EXPECT_TRUE(pair.thumb.out.touching);
}

}  // namespace
}  // namespace tactus::haptics
