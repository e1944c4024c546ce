// The god-object proxy on the contact plane: the coupling force of a press, static friction
// holding a small sideways move and letting a larger one slide, the friction's live edit.
#include "haptics/algorithms/proxy_on_plane.hpp"

#include <gtest/gtest.h>

#include "../fixtures/step_rig.hpp"

namespace tactus::haptics {
namespace {

using test::StepRig;

contact::ProxyParams params(double mu_s, double mu_k) {
  contact::ProxyParams p;
  p.radius = 0.01;
  p.stiffness = 500.0;
  p.static_friction = mu_s;
  p.kinetic_friction = mu_k;
  contact::validate_proxy_params(p);
  return p;
}

StepRig rig_with(double mu_s, double mu_k) {
  StepRig rig(test::model_of({std::make_shared<ProxyOnPlane>(ToolSphere{Vec3::Zero(), 0.01}, params(mu_s, mu_k))}));
  rig.plane(0.0);
  return rig;
}

TEST(ProxyOnPlane, PressingRendersTheCouplingSpring) {
  StepRig rig = rig_with(0.0, 0.0);
  rig.hold(Vec3(0, 0, 0.02), 5);                // start above the plane
  rig.hold(Vec3(0, 0, 0.006), 30, 0.005);       // 4 mm past the surface
  EXPECT_TRUE(rig.out.touching);
  // The proxy keeps a clearance of micrometres above the surface (ProxyParams::skin).
  EXPECT_NEAR(rig.sink.force.z(), 500.0 * 0.004, 500.0 * 5e-6);
  EXPECT_NEAR(rig.sink.force.x(), 0.0, 1e-12);
}

TEST(ProxyOnPlane, StaticFrictionHoldsASmallSlideAndLetsALargeOneGo) {
  StepRig rig = rig_with(0.5, 0.4);
  rig.hold(Vec3(0, 0, 0.02), 5);
  rig.hold(Vec3(0, 0, 0.006), 30, 0.005);  // 2 N normal
  rig.hold(Vec3(0.001, 0, 0.006), 30, 0.035);  // 0.5 N sideways < μs·2 N: held
  EXPECT_NEAR(rig.sink.force.x(), -500.0 * 0.001, 1e-6);
  rig.hold(Vec3(0.01, 0, 0.006), 50, 0.065);  // far beyond the cone: slides, trailing at μk
  EXPECT_NEAR(-rig.sink.force.x() / rig.sink.force.z(), 0.4, 0.02);
}

TEST(ProxyOnPlane, AnEditOfTheFrictionTakesEffect) {
  StepRig rig = rig_with(0.5, 0.4);
  rig.edit = {1, 0.0, {500.0, 0.0, 0.0}, 2000.0};  // frictionless from the start
  rig.hold(Vec3(0, 0, 0.02), 5);
  rig.hold(Vec3(0, 0, 0.006), 30, 0.005);
  rig.hold(Vec3(0.001, 0, 0.006), 30, 0.035);
  EXPECT_NEAR(rig.sink.force.x(), 0.0, 1e-9);
  EXPECT_EQ(ProxyOnPlane(ToolSphere{Vec3::Zero(), 0.01}, params(0.5, 0.4)).editable_surface().kind,
            EditableSurface::Kind::proxy);
}

}  // namespace
}  // namespace tactus::haptics
