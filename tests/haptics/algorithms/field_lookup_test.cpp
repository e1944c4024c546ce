// A force field looked up at the tool: its force and torque, no load on the tissue, the
// simulation told where the tool is.
#include "haptics/algorithms/field_lookup.hpp"

#include <gtest/gtest.h>

#include "../fixtures/step_rig.hpp"

namespace tactus::haptics {
namespace {

/// A spring field F = −k (p − centre) inside a 10 cm box, nothing outside.
class SpringField final : public ForceField {
 public:
  [[nodiscard]] FieldForce force(const Vec3& p, const Quat& /*orientation*/, double /*t*/) const noexcept override {
    if ((p.array().abs() > 0.05).any()) return {};
    return {-300.0 * p, true};
  }
};

TEST(FieldLookup, RendersTheFieldAtTheToolsPointAndLoadsNothing) {
  const auto lookup = std::make_shared<FieldLookup>(std::make_shared<SpringField>(), Vec3(0, 0, -0.01));
  EXPECT_TRUE(lookup->simulation_follows_tool());
  test::StepRig rig(test::model_of({lookup}));
  rig.plane(0.0);  // a plane from the interaction loop takes no load either
  rig.hold(Vec3(0.01, 0, 0.01), 20);  // looked up at (0.01, 0, 0)
  EXPECT_NEAR(rig.sink.force.x(), -3.0, 1e-12);
  EXPECT_NEAR(rig.sink.force.z(), 0.0, 1e-12);
  EXPECT_NEAR(rig.sink.torque.y(), -0.01 * -3.0, 1e-12);  // (0, 0, −0.01) × (−3, 0, 0)
  EXPECT_FALSE(rig.load.active);
  rig.hold(Vec3(0.2, 0, 0), 20, 0.02);  // outside the box
  EXPECT_FALSE(rig.out.touching);
  EXPECT_EQ(rig.sink.force, Vec3::Zero());
}

}  // namespace
}  // namespace tactus::haptics
