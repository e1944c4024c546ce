// The needle as a force algorithm: the layer's spring on the hand and on the layer's body,
// the rupture reported as an event, the scripted axis handed to the interaction loop.
#include "haptics/algorithms/needle_algorithm.hpp"

#include <gtest/gtest.h>

#include "../fixtures/step_rig.hpp"

namespace tactus::haptics {
namespace {

TEST(NeedleAlgorithm, PressesOnTheLayerThenTearsItAndSaysSo) {
  NeedleConfig c;
  NeedleLayer skin;
  skin.body = 4;
  skin.rupture_force = 2.0;
  skin.stiffness = 1000.0;
  c.layers = {skin};
  test::StepRig rig(test::model_of({std::make_shared<NeedleAlgorithm>(c, Vec3(0, 0, -1))}));
  rig.plane(0.0);
  NeedleLayerSurface& surface = rig.surfaces.layers[0];
  surface.entry_found = true;
  surface.entry = Vec3::Zero();
  surface.entry_normal = Vec3::UnitZ();
  surface.entry_triangle = 7;
  rig.surfaces_fresh = true;

  bool torn = false;
  double before_tear = 0.0;
  for (int k = 0; k <= 60 && !torn; ++k) {
    const HapticOutputs& out = rig.step(k * 1e-3, Vec3(0, 0, 0.001 - 0.0001 * k));  // 0.1 mm a frame down
    EXPECT_EQ(out.tool_axis, Vec3(0, 0, -1));
    for (int i = 0; i < out.event_count; ++i)
      if (out.events[static_cast<std::size_t>(i)].kind == HapticEvent::Kind::rupture) {
        torn = true;
        EXPECT_EQ(out.events[static_cast<std::size_t>(i)].detail, 0);
        EXPECT_NEAR(out.events[static_cast<std::size_t>(i)].value, 2.0, 0.15);
      }
    if (!torn && out.touching) {
      before_tear = rig.sink.force.z();
      EXPECT_TRUE(out.load->active);
      EXPECT_EQ(out.load->body, 4);
      EXPECT_EQ(out.load->triangle, 7);
    }
  }
  EXPECT_TRUE(torn);
  EXPECT_GT(before_tear, 1.5);  // the layer resisted up to its threshold
  EXPECT_LT(rig.sink.force.z(), before_tear);  // and gave way
}

}  // namespace
}  // namespace tactus::haptics
