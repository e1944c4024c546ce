// Multiple-surface palpation as a force algorithm: the ray crossings become the layers'
// planes, the load goes to the layer pressed, and the ray to cast next is handed on.
#include "haptics/algorithms/multi_surface_algorithm.hpp"

#include <gtest/gtest.h>

#include "../fixtures/step_rig.hpp"

namespace tactus::haptics {
namespace {

TEST(MultiSurfaceAlgorithm, PressesTheOutermostLayerAndLoadsItsBody) {
  MultiSurfaceConfig c;
  c.stiffness = 800.0;
  c.layers = 2;
  c.radius = 0.005;
  test::StepRig rig(test::model_of({std::make_shared<MultiSurfaceAlgorithm>(c, std::vector<std::size_t>{6, 2}, Vec3::Zero())}));
  rig.plane(0.0);
  // Skin at z = 0 (body 6) over a deeper layer at z = −0.01 (body 2).
  for (std::size_t i = 0; i < 2; ++i) {
    rig.surfaces.layers[i].entry_found = true;
    rig.surfaces.layers[i].entry = Vec3(0, 0, -0.01 * static_cast<double>(i));
    rig.surfaces.layers[i].entry_normal = Vec3::UnitZ();
    rig.surfaces.layers[i].entry_triangle = static_cast<std::int32_t>(10 + i);
  }
  rig.surfaces_fresh = true;
  rig.hold(Vec3(0, 0, 0.01), 5);
  rig.hold(Vec3(0, 0, 0.003), 30, 0.005);  // the sphere 2 mm into the skin
  EXPECT_TRUE(rig.out.touching);
  EXPECT_NEAR(rig.sink.force.z(), 800.0 * 0.002, 1e-9);
  EXPECT_TRUE(rig.load.active);
  EXPECT_EQ(rig.load.body, 6);
  EXPECT_EQ(rig.load.triangle, 10);
  EXPECT_NEAR(rig.out.tool_axis.norm(), 1.0, 1e-12);
}

}  // namespace
}  // namespace tactus::haptics
