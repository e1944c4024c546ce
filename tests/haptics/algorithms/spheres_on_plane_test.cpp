// A sphere-set finger on the contact plane: each sphere's law summed, its torque about the
// tool origin, Hertz feeling the tissue's curvature, the penalty's live edit.
#include "haptics/algorithms/spheres_on_plane.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "../fixtures/step_rig.hpp"

namespace tactus::haptics {
namespace {

using test::StepRig;

TEST(SpheresOnPlane, SumsEverySpheresForceAndItsTorque) {
  // Two 10 mm spheres 20 mm apart in x, the right one 1 mm lower: 2 mm and 1 mm deep.
  StepRig rig(test::model_of({std::make_shared<SpheresOnPlane>(
      std::vector<ToolSphere>{{Vec3(-0.01, 0, 0), 0.01}, {Vec3(0.01, 0, -0.001), 0.01}}, ContactLaw::penalty(1000.0))}));
  rig.plane(0.0);
  rig.hold(Vec3(0, 0, 0.009), 20);
  EXPECT_NEAR(rig.sink.force.z(), 1.0 + 2.0, 1e-12);
  // Torque about y: x × F_z summed, −0.01·1 + 0.01·2.
  EXPECT_NEAR(rig.sink.torque.y(), -(-0.01 * 1.0 + 0.01 * 2.0), 1e-12);
}

TEST(SpheresOnPlane, AHertzFingerFeelsTheTissueCurvature) {
  auto force_at = [](double curvature) {
    StepRig rig(test::model_of({std::make_shared<SpheresOnPlane>(
        std::vector<ToolSphere>{{Vec3::Zero(), 0.01}},
        ContactLaw::hertz(contact::HertzParameters{0.01, {1e6, 0.48}, {3e4, 0.45}}))}));
    rig.plane(0.0, curvature);
    return rig.hold(Vec3(0, 0, 0.009), 20).sent.force.z();
  };
  const double e_star = 1.0 / ((1 - 0.48 * 0.48) / 1e6 + (1 - 0.45 * 0.45) / 3e4);
  const double flat = 4.0 / 3.0 * e_star * std::sqrt(0.01) * std::pow(1e-3, 1.5);
  EXPECT_NEAR(force_at(0.0), flat, 1e-9 * flat);
  EXPECT_NEAR(force_at(100.0), flat / std::sqrt(2.0), 1e-9 * flat);  // as curved as the finger
  EXPECT_GT(force_at(-50.0), flat);
}

TEST(SpheresOnPlane, OnlyThePenaltyLawIsEditable) {
  const SpheresOnPlane penalty({{Vec3::Zero(), 0.01}}, ContactLaw::penalty(700.0));
  EXPECT_EQ(penalty.editable_surface().kind, EditableSurface::Kind::penalty);
  EXPECT_EQ(penalty.editable_surface().values.stiffness, 700.0);
  const SpheresOnPlane pad({{Vec3::Zero(), 0.01}}, ContactLaw::fingerpad({}));
  EXPECT_EQ(pad.editable_surface().kind, EditableSurface::Kind::none);
}

TEST(SpheresOnPlane, NoPlaneNoForce) {
  StepRig rig(test::model_of({std::make_shared<SpheresOnPlane>(std::vector<ToolSphere>{{Vec3::Zero(), 0.01}},
                                                               ContactLaw::penalty(1000.0))}));
  rig.hold(Vec3(0, 0, -0.05), 20);  // deep below where a plane would be, but none is published
  EXPECT_EQ(rig.sink.force, Vec3::Zero());
  EXPECT_FALSE(rig.out.touching);
}

}  // namespace
}  // namespace tactus::haptics
