// The pulse overlay: felt only while the contact presses, beating at its rate.
#include "haptics/algorithms/pulse_overlay.hpp"

#include <gtest/gtest.h>

#include "../fixtures/step_rig.hpp"
#include "haptics/algorithms/spheres_on_plane.hpp"

namespace tactus::haptics {
namespace {

PulseForce pulse() {
  PulseConfig c;
  c.rate = 60.0;  // one beat a second, the first 0.2 s of it
  c.duty_cycle = 0.2;
  c.amplitude = 0.3;
  c.range = 0.05;
  c.sources = {Vec3(0, 0, -0.01)};  // under the finger
  return PulseForce(c);
}

TEST(PulseOverlay, BeatsOnlyWhilePressing) {
  const auto overlay = std::make_shared<PulseOverlay>(pulse(), Vec3::Zero());
  EXPECT_EQ(overlay->stage(), ForceAlgorithm::Stage::overlay);
  test::StepRig rig(test::model_of(
      {std::make_shared<SpheresOnPlane>(std::vector<ToolSphere>{{Vec3::Zero(), 0.01}}, ContactLaw::penalty(1000.0)),
       overlay}));
  rig.plane(0.0);
  rig.hold(Vec3(0, 0, 0.02), 100);  // above the skin, during a beat: nothing
  EXPECT_EQ(rig.sink.force, Vec3::Zero());
  rig.hold(Vec3(0, 0, 0.008), 50, 1.0);  // pressing 2 N during the next beat
  const double beating = rig.sink.force.z();
  rig.hold(Vec3(0, 0, 0.008), 50, 1.5);  // between beats
  const double resting = rig.sink.force.z();
  EXPECT_NEAR(resting, 2.0, 1e-12);
  EXPECT_GT(beating, resting + 0.1);
  EXPECT_NEAR(rig.load.force.z(), -2.0, 1e-12);  // the tissue never takes the beat
}

}  // namespace
}  // namespace tactus::haptics
