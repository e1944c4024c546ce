// A finger on a local patch: a rigid patch renders what the plane would, the load goes to the
// body's own triangle, and the finger's spheres each dent a soft patch under their own force.
#include "haptics/algorithms/spheres_on_patch.hpp"

#include <gtest/gtest.h>

#include "../fixtures/step_rig.hpp"
#include "core/counting_allocator.hpp"
#include "mesh/generators.hpp"

namespace tactus::haptics {
namespace {

struct Plate {
  mesh::TriMesh mesh = mesh::grid_plate(0.1, 0.1, 10, 10);
  contact::PatchCapacity capacity{48, 128, 240};
  contact::LocalPatch patch;
  contact::PatchBuilder builder{mesh.vertices.size(), mesh.triangles, capacity};

  /// A patch around `centre` at time t: rigid (compliance, no body behind it) or soft.
  const contact::LocalPatch& cut(contact::LocalModelKind kind, const Vec3& centre, double t) {
    patch = contact::LocalPatch(kind, capacity);
    contact::PatchBuilder::Inputs in;
    in.kind = kind;
    in.body = 0;
    in.time = t;
    in.center = centre;
    in.radius = 0.022;
    in.surface = mesh.vertices;
    in.material = {3e4, 0.45, 1000.0};
    in.frame_time = 1e-3;
    builder.build(in, patch);
    return patch;
  }
};

TEST(SpheresOnPatch, ARigidPatchRendersThePlanesForceWithoutAllocating) {
  Plate plate;
  const Vec3 where(0.001, 0.002, 0.008);
  test::StepRig rig(test::model_of({std::make_shared<SpheresOnPatch>(
      std::vector<ToolSphere>{{Vec3::Zero(), 0.01}}, ContactLaw::penalty(1000.0), 0.0,
      contact::LocalModelKind::compliance, plate.capacity, false)}));
  rig.patch = &plate.cut(contact::LocalModelKind::compliance, where, 0.0);
  rig.patch_fresh = true;
  rig.hold(where, 20);
  EXPECT_TRUE(rig.out.touching);
  EXPECT_NEAR(rig.sink.force.z(), 1000.0 * 0.002, 1e-9);
  EXPECT_TRUE(rig.load.active);
  EXPECT_GE(rig.load.triangle, 0);  // the plate's own triangle, not the patch's
  EXPECT_NEAR(rig.out.frame_point.z(), 0.0, 1e-12);  // the contact point on the plate
  testing::AllocationCounter counter;
  for (int k = 20; k < 500; ++k) {
    rig.patch_fresh = k % 10 == 0;  // the same patch published again, as the simulation would
    rig.step(k * 1e-3, where);
  }
  EXPECT_EQ(counter.count(), 0u);
}

TEST(SpheresOnPatch, EachSphereDentsASoftPatchUnderItsOwnForce) {
  Plate plate;
  const Vec3 where(0.0, 0.0, 0.004);
  test::StepRig rig(test::model_of({std::make_shared<SpheresOnPatch>(
      std::vector<ToolSphere>{{Vec3(-0.015, 0, 0), 0.005}, {Vec3(0.015, 0, 0), 0.005}}, ContactLaw::penalty(1000.0),
      0.0, contact::LocalModelKind::mass_spring, plate.capacity, false)}));
  rig.patch = &plate.cut(contact::LocalModelKind::mass_spring, where, 0.0);
  rig.patch_fresh = true;
  rig.hold(where, 300);
  ASSERT_TRUE(rig.out.touching);
  EXPECT_LT(rig.sink.force.z(), 2.0 * 0.95);  // the patch yields under both
  EXPECT_GT(rig.sink.force.z(), 0.2);
  ASSERT_EQ(rig.load.part_count, 2);  // each sphere's share where it touches
  EXPECT_NEAR(rig.load.parts[0].share + rig.load.parts[1].share, 1.0, 1e-12);
  EXPECT_NEAR(rig.load.parts[0].share, 0.5, 1e-6);  // symmetric plate, symmetric finger
}

}  // namespace
}  // namespace tactus::haptics
