// The haptic step as a pipeline: the contact's force through the safety layer to the device,
// overlays added after the contact's smoothing and kept from the tissue's reaction, live edits
// as inputs, events, no allocation.
#include "haptics/haptic_step.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "core/counting_allocator.hpp"
#include "fixtures/step_rig.hpp"
#include "haptics/algorithms/spheres_on_plane.hpp"

namespace tactus::haptics {
namespace {

using test::StepRig;

std::shared_ptr<const ForceAlgorithm> finger(double stiffness = 1000.0) {
  return std::make_shared<SpheresOnPlane>(std::vector<ToolSphere>{{Vec3::Zero(), 0.01}}, ContactLaw::penalty(stiffness));
}

/// A constant push of `force` while the contact touches: an overlay like the pulse.
class ConstantOverlay final : public ForceAlgorithm {
 public:
  explicit ConstantOverlay(Vec3 force) : force_(std::move(force)) {}
  [[nodiscard]] Stage stage() const override { return Stage::overlay; }
  [[nodiscard]] std::unique_ptr<AlgorithmState> make_state() const override { return std::make_unique<AlgorithmState>(); }
  [[nodiscard]] Rendering render(const FrameInputs& f, AlgorithmState&) const override {
    Rendering r;
    if (f.contact_touching) r.force = force_;
    return r;
  }

 private:
  Vec3 force_;
};

TEST(HapticStep, WritesTheContactForceAndLoadsTheTissueWithItsReaction) {
  StepRig rig(test::model_of({finger()}));
  rig.plane(0.0);
  const HapticOutputs& out = rig.hold(Vec3(0, 0, 0.008), 20);  // 2 mm into the plane
  EXPECT_TRUE(out.touching);
  EXPECT_NEAR(rig.sink.force.z(), 2.0, 1e-12);
  EXPECT_EQ(rig.sink.writes, 20);
  EXPECT_EQ(out.sent.force, rig.sink.force);
  EXPECT_TRUE(out.load->active);
  EXPECT_EQ(out.load->triangle, 3);
  EXPECT_EQ(out.load->force, -rig.sink.force);
  EXPECT_EQ(out.frame_point, Vec3::Zero());  // the plane's point
}

TEST(HapticStep, AnOverlayIsFeltButNotPushedIntoTheTissue) {
  StepRig rig(test::model_of({finger(), std::make_shared<ConstantOverlay>(Vec3(0.1, 0, 0.3))}));
  rig.plane(0.0);
  rig.hold(Vec3(0, 0, 0.008), 20);
  EXPECT_NEAR(rig.sink.force.z(), 2.3, 1e-12);
  EXPECT_NEAR(rig.sink.force.x(), 0.1, 1e-12);
  // The vessel beneath pushes the overlay: the tissue takes the contact's 2 N alone.
  EXPECT_NEAR(rig.load.force.z(), -2.0, 1e-12);
  EXPECT_NEAR(rig.load.force.x(), 0.0, 1e-12);
  // Out of contact, no overlay either.
  rig.hold(Vec3(0, 0, 0.02), 20, 0.02);
  EXPECT_EQ(rig.sink.force, Vec3::Zero());
}

TEST(HapticStep, TheSafetyLayerScalesTheReactionAndSaysSo) {
  StepRig rig(test::model_of({finger(1e5)}));  // 200 N asked for
  rig.plane(0.0);
  bool clamped_event = false;
  for (int k = 0; k < 20; ++k) {
    const HapticOutputs& out = rig.step(k * 1e-3, Vec3(0, 0, 0.008));
    for (int i = 0; i < out.event_count; ++i)
      clamped_event |= out.events[static_cast<std::size_t>(i)].kind == HapticEvent::Kind::force_clamped;
  }
  EXPECT_LE(rig.sink.force.norm(), 10.0);
  EXPECT_GT(rig.sink.force.norm(), 9.99);
  EXPECT_TRUE(clamped_event);
  EXPECT_EQ(rig.load.force, -rig.sink.force);  // the tissue takes what the hand felt
}

TEST(HapticStep, ALiveEditArrivesAsAnInputAndAppliesFromItsTime) {
  StepRig rig(test::model_of({finger()}));
  rig.plane(0.0);
  rig.edit = {1, 0.050, {500.0, 0.0, 0.0}, 2000.0};
  rig.hold(Vec3(0, 0, 0.008), 50);
  EXPECT_NEAR(rig.sink.force.z(), 2.0, 1e-12);  // not yet
  rig.hold(Vec3(0, 0, 0.008), 10, 0.050);
  EXPECT_NEAR(rig.sink.force.z(), 1.0, 1e-12);
  // Bounded by the device's stiffness, whatever the writer sent.
  rig.edit = {2, 0.0, {1e9, 0.0, 0.0}, 2000.0};
  rig.hold(Vec3(0, 0, 0.008), 1, 0.060);
  EXPECT_NEAR(rig.sink.force.z(), 4.0, 1e-12);
}

TEST(HapticStep, TheEmergencyStopInputStopsTheForce) {
  StepRig rig(test::model_of({finger()}));
  rig.plane(0.0);
  rig.hold(Vec3(0, 0, 0.008), 20);
  rig.emergency_stop = true;
  const HapticOutputs& out = rig.step(0.02, Vec3(0, 0, 0.008));
  EXPECT_EQ(rig.sink.force, Vec3::Zero());
  ASSERT_GE(out.event_count, 1);
  EXPECT_EQ(out.events[static_cast<std::size_t>(out.event_count - 1)].kind, HapticEvent::Kind::emergency_stop);
}

TEST(HapticStep, ReportsContactChangesAsEvents) {
  StepRig rig(test::model_of({finger()}));
  rig.plane(0.0);
  const HapticOutputs& touch = rig.step(0.0, Vec3(0, 0, 0.008));
  ASSERT_EQ(touch.event_count, 1);
  EXPECT_EQ(touch.events[0].kind, HapticEvent::Kind::contact_begin);
  EXPECT_EQ(rig.step(0.001, Vec3(0, 0, 0.008)).event_count, 0);
  const HapticOutputs& leave = rig.step(0.002, Vec3(0, 0, 0.02));
  ASSERT_EQ(leave.event_count, 1);
  EXPECT_EQ(leave.events[0].kind, HapticEvent::Kind::contact_end);
}

TEST(HapticStep, AFrameAllocatesNothing) {
  StepRig rig(test::model_of({finger(), std::make_shared<ConstantOverlay>(Vec3(0, 0, 0.1))}));
  rig.model.force_smoothing = 0.005;
  rig.model.passivity_control = true;
  rig.state = HapticState(rig.model);
  rig.plane(0.0);
  rig.step(0.0, Vec3(0, 0, 0.008));
  testing::AllocationCounter counter;
  for (int k = 1; k < 2000; ++k) {
    if (k % 10 == 0) rig.plane(1e-6 * (k % 3));  // new planes: model updates to smooth
    rig.step(k * 1e-3, Vec3(0.00001 * (k % 7), 0, 0.008));
  }
  EXPECT_EQ(counter.count(), 0u) << counter.bytes() << " bytes";
}

TEST(HapticStep, ANewPlaneIsSmoothedInNotSteppedIn) {
  StepRig rig(test::model_of({finger()}));
  rig.model.force_smoothing = 0.01;
  rig.state = HapticState(rig.model);
  rig.plane(0.0);
  rig.hold(Vec3(0, 0, 0.008), 30);  // 2 N against the first plane
  rig.plane(0.001);                 // the surface rose 1 mm: 3 N at once without smoothing
  rig.step(0.030, Vec3(0, 0, 0.008));
  // The algorithm measured both models at this frame; the 1 N step is kept as an offset that
  // has already decayed by one frame of the 10 ms time constant.
  EXPECT_NEAR(rig.sink.force.z(), 3.0 - std::exp(-0.1), 1e-9);
  rig.hold(Vec3(0, 0, 0.008), 100, 0.031);
  EXPECT_NEAR(rig.sink.force.z(), 3.0, 1e-3);  // the offset decayed over 10 time constants
}

TEST(HapticStep, ADeviceRendersOneContactAlgorithm) {
  EXPECT_THROW(HapticState(test::model_of({finger(), finger()})), std::invalid_argument);
}

TEST(HapticStep, AToolWithoutAlgorithmsFeelsNothing) {
  StepRig rig(test::model_of({}));
  rig.plane(0.0);
  rig.hold(Vec3(0, 0, 0.0), 20);
  EXPECT_EQ(rig.sink.force, Vec3::Zero());
  EXPECT_FALSE(rig.load.active);
}

}  // namespace
}  // namespace tactus::haptics
