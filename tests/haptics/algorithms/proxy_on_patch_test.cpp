// The proxy on a local patch: on a rigid patch it renders the coupling spring as on a plane,
// and on a soft one the patch yields, so the same press is felt softer.
#include "haptics/algorithms/proxy_on_patch.hpp"

#include <gtest/gtest.h>

#include "../fixtures/step_rig.hpp"
#include "mesh/generators.hpp"

namespace tactus::haptics {
namespace {

double press(contact::LocalModelKind kind) {
  const mesh::TriMesh plate = mesh::grid_plate(0.1, 0.1, 10, 10);
  const contact::PatchCapacity capacity{48, 128, 240};
  contact::LocalPatch patch(kind, capacity);
  contact::PatchBuilder builder(plate.vertices.size(), plate.triangles, capacity);
  contact::PatchBuilder::Inputs in;
  in.kind = kind;
  in.body = 0;
  in.center = Vec3(0, 0, 0.01);
  in.radius = 0.022;
  in.surface = plate.vertices;
  in.material = {3e4, 0.45, 1000.0};
  in.frame_time = 1e-3;
  builder.build(in, patch);
  contact::ProxyParams p;
  p.radius = 0.005;
  p.stiffness = 500.0;
  test::StepRig rig(test::model_of({std::make_shared<ProxyOnPatch>(ToolSphere{Vec3::Zero(), 0.005}, p, kind, capacity, false)}));
  rig.plane(0.0);
  rig.patch = &patch;
  rig.patch_fresh = true;
  rig.hold(Vec3(0, 0, 0.01), 5);
  rig.hold(Vec3(0, 0, 0.001), 300, 0.005);  // 4 mm past the surface
  EXPECT_TRUE(rig.out.touching);
  EXPECT_TRUE(rig.load.active);
  return rig.sink.force.z();
}

TEST(ProxyOnPatch, ARigidPatchHoldsTheProxyAndASoftOneYields) {
  const double rigid = press(contact::LocalModelKind::compliance);
  EXPECT_NEAR(rigid, 500.0 * 0.004, 500.0 * 5e-6);  // less the proxy's clearance (ProxyParams::skin)
  const double soft = press(contact::LocalModelKind::mass_spring);
  EXPECT_LT(soft, rigid);
  EXPECT_GT(soft, 0.0);
}

}  // namespace
}  // namespace tactus::haptics
