// A sphere-set finger on a patch local model (issue 7, eq. 1 of seed 000): every sphere that
// touches renders its own force against its own dent of the patch, and the forces are summed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "haptics/devices/scripted_device.hpp"
#include "mesh/generators.hpp"
#include "haptics/algorithms/spheres_on_patch.hpp"
#include "runtime/haptic_loop.hpp"

namespace tactus::runtime {
namespace {

/// A finger of `spheres` held still at height 4 mm over a soft 10 mm grid plate, rendered by
/// the penalty law (1000 N/m) on a mass-spring patch published once, for 0.3 s: the patch
/// settles under the finger (the watchdog is set past the run, as no simulation follows).
struct Held {
  HapticFrame frame;
  ContactLoad load;  ///< the last load sent to the simulation
  std::vector<Vec3> plate;
  std::vector<mesh::Triangle> triangles;
};

Held hold(const std::vector<haptics::ToolSphere>& spheres) {
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
  haptics::HapticModel c;
  c.algorithms.push_back(std::make_shared<haptics::SpheresOnPatch>(spheres, haptics::ContactLaw::penalty(1000.0), 0.0,
                                                                   request.kind, request.capacity, false));
  c.safety.max_force = 10.0;
  c.safety.watchdog_timeout = 1.0;
  HapticLoop loop(c, std::make_unique<haptics::ScriptedDevice>(still, haptics::Tremor{}, haptics::DeviceLimits{}),
                  channels);
  HapticFrame f;
  for (int k = 0; k <= 300; ++k) {
    if (k == 0) publish_patch(0.0);
    loop.step(k * 1e-3, 0, now_ns(), false);
    while (channels.frames.try_pop(f)) {}
  }
  channels.load.update();
  return {f, channels.load.read(), plate.vertices, plate.triangles};
}

TEST(SphereSetOnPatch, EverySphereRendersItsOwnContactAndTheForcesAreSummed) {
  // Two 5 mm spheres 30 mm apart (on triangles with no corner in common), each 1 mm into the
  // plate, against one of them alone.
  const Held held_one = hold({{Vec3(-0.015, 0.0, 0.0), 0.005}});
  const Held held_two = hold({{Vec3(-0.015, 0.0, 0.0), 0.005}, {Vec3(0.015, 0.0, 0.0), 0.005}});
  const HapticFrame& one = held_one.frame;
  const HapticFrame& two = held_two.frame;
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

  // The tissue takes each sphere's force under that sphere: two parts of the load, half
  // each (the same force on both sides), on triangles under each sphere's centre.
  ASSERT_TRUE(held_two.load.active);
  ASSERT_EQ(held_two.load.part_count, 2);
  double shares = 0.0;
  for (int i = 0; i < 2; ++i) {
    const ContactLoad::Part& part = held_two.load.parts[static_cast<std::size_t>(i)];
    shares += part.share;
    EXPECT_NEAR(part.share, 0.5, 0.025);
    ASSERT_GE(part.triangle, 0);
    const mesh::Triangle& tri = held_two.triangles[static_cast<std::size_t>(part.triangle)];
    Vec3 at = Vec3::Zero();
    for (int k = 0; k < 3; ++k) at += part.barycentric[k] * held_two.plate[static_cast<std::size_t>(tri[static_cast<std::size_t>(k)])];
    const double x = i == 0 ? -0.015 : 0.015;
    // The closest point of the dented patch, mapped onto the flat plate: under the centre to
    // within a tenth of the 10 mm cell (the dent of a triangulated patch is not symmetric).
    EXPECT_LT((at.head<2>() - Vec2(x, 0.0)).norm(), 1e-3) << "part " << i << " at " << at.transpose();
  }
  EXPECT_NEAR(shares, 1.0, 1e-12);
  // One sphere: the single contact carries the whole load.
  EXPECT_EQ(held_one.load.part_count, 0);
}

}  // namespace
}  // namespace tactus::runtime
