// A sphere-set finger on a patch local model (issue 7, eq. 1 of seed 000): every sphere that
// touches renders its own force against its own dent of the patch, and the forces are summed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "haptics/devices/scripted_device.hpp"
#include "mesh/generators.hpp"
#include "runtime/haptic_loop.hpp"

namespace tactus::runtime {
namespace {

/// A finger of `spheres` held still at height 4 mm over a soft 10 mm grid plate, rendered by
/// the penalty law (1000 N/m) on a mass-spring patch published once, for 0.3 s: the patch
/// settles under the finger (the watchdog is set past the run, as no simulation follows).
HapticFrame hold(const std::vector<HapticConfig::Sphere>& spheres) {
  const mesh::TriMesh plate = mesh::grid_plate(0.1, 0.1, 10, 10);
  const Vec3 where(0.0, 0.0, 0.004);  // over a vertex: the plate is symmetric about it
  DeviceChannels channels(1 << 12);
  PatchRequest request;
  request.kind = contact::LocalModelKind::mass_spring;
  request.radius = 0.022;
  request.capacity = {48, 128, 240};
  channels.request_patches(request);
  contact::PatchBuilder builder(plate.vertices.size(), plate.triangles, request.capacity);
  auto publish_patch = [&](double t) {
    contact::PatchBuilder::Inputs in;
    in.kind = request.kind;
    in.body = 0;
    in.time = t;
    in.center = where;
    in.radius = request.radius;
    in.surface = plate.vertices;
    in.material = {3e4, 0.45, 1000.0};
    in.frame_time = 1e-3;
    builder.build(in, channels.patch->write_buffer());
    channels.patch->publish();
  };
  haptics::WaypointsPath still;
  still.points = {{0.0, where}};
  HapticConfig c;
  c.spheres = spheres;
  c.stiffness = 1000.0;
  c.safety.max_force = 10.0;
  c.safety.watchdog_timeout = 1.0;
  c.local_model = request.kind;
  HapticLoop loop(c, std::make_unique<haptics::ScriptedDevice>(still, haptics::Tremor{}, haptics::DeviceLimits{}),
                  channels);
  HapticFrame f;
  for (int k = 0; k <= 300; ++k) {
    if (k == 0) publish_patch(0.0);
    loop.step(k * 1e-3, 0, now_ns(), false);
    while (channels.frames.try_pop(f)) {}
  }
  return f;
}

TEST(SphereSetOnPatch, EverySphereRendersItsOwnContactAndTheForcesAreSummed) {
  // Two 5 mm spheres 30 mm apart (on triangles with no corner in common), each 1 mm into the
  // plate, against one of them alone.
  const HapticFrame one = hold({{Vec3(-0.015, 0.0, 0.0), 0.005}});
  const HapticFrame two = hold({{Vec3(-0.015, 0.0, 0.0), 0.005}, {Vec3(0.015, 0.0, 0.0), 0.005}});
  std::printf("one sphere %.4f N, two spheres %.4f N, torque about y %.2e N·m (arm × force %.2e)\n", one.force.z(),
              two.force.z(), two.torque.y(), 0.015 * two.force.z());
  ASSERT_EQ(one.contact, 1);
  ASSERT_EQ(two.contact, 1);
  // The patch yields under each sphere: less than the rigid 1 N per sphere.
  EXPECT_LT(one.force.z(), 0.95);
  EXPECT_GT(one.force.z(), 0.1);
  // Each sphere presses its own dent, as hard as one alone (within the little the other's
  // dent lowers its surface): the sum is nearly twice one. With the whole force on the
  // deepest sphere's dent, that sphere's side sank and the other pressed an undented patch.
  EXPECT_NEAR(two.force.z(), 2.0 * one.force.z(), 0.1 * one.force.z());
  EXPECT_LE(two.force.z(), 2.0 * one.force.z() + 1e-9);
  // The same force on both sides of the finger: no torque about the finger's centre.
  EXPECT_LT(std::abs(two.torque.y()), 0.05 * 0.015 * two.force.z());
}

}  // namespace
}  // namespace tactus::runtime
