// A fingertip resting on a fabric's patch keeps its contact, and its force, when the
// simulation publishes a new patch whose triangles are numbered otherwise: the proxy finds
// the material point it rests on again by the body's triangle.
#include "haptics/algorithms/fabric_proxy_on_patch.hpp"

#include <gtest/gtest.h>

#include "../fixtures/step_rig.hpp"
#include "mesh/generators.hpp"

namespace tactus::haptics {
namespace {

TEST(FabricProxyOnPatch, KeepsItsContactAcrossAPatchNumberedOtherwise) {
  const mesh::TriMesh plate = mesh::grid_plate(0.1, 0.1, 20, 20);  // z = 0, normals +z
  const contact::PatchCapacity capacity{48, 128, 240};
  contact::PatchBuilder builder(plate.vertices.size(), plate.triangles, capacity);
  contact::PatchBuilder::Inputs in;
  in.kind = contact::LocalModelKind::compliance;
  in.body = 0;
  in.radius = 0.02;
  in.surface = plate.vertices;
  in.rigid = true;  // the sheet stays put: any change of force comes from the update alone
  contact::LocalPatch first(in.kind, capacity), second(in.kind, capacity);
  in.center = Vec3(0, 0, 0.01);
  builder.build(in, first);
  in.center = Vec3(0.012, 0.007, 0.01);  // another set of nodes, nearest first: other numbers
  builder.build(in, second);

  contact::FabricProxyParams p;
  p.finger.base = p.finger.tip = Vec3::Zero();
  p.finger.radius = 0.008;
  p.stiffness = 190.0;
  test::StepRig rig(test::model_of({std::make_shared<FabricProxyOnPatch>(p, in.kind, capacity, false)}));
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

}  // namespace
}  // namespace tactus::haptics
