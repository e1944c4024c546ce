// One device's haptic loop driven by hand: the force it renders from a local contact plane,
// that it allocates nothing per frame, and that it fades out when the simulation stalls.
#include <gtest/gtest.h>

#include <cmath>

#include "core/counting_allocator.hpp"  // tests/core
#include "haptics/devices/scripted_device.hpp"
#include "mesh/generators.hpp"
#include "haptics/algorithms/spheres_on_patch.hpp"
#include "haptics/algorithms/spheres_on_plane.hpp"
#include "runtime/haptic_loop.hpp"

namespace tactus::runtime {
namespace {

/// A 10 mm finger sphere rendering `law` on the contact plane.
haptics::HapticModel model(const haptics::ContactLaw& law) {
  haptics::HapticModel m;
  m.algorithms.push_back(std::make_shared<haptics::SpheresOnPlane>(std::vector<haptics::ToolSphere>{{Vec3::Zero(), 0.01}}, law));
  m.safety.max_force = 10.0;
  m.safety.watchdog_timeout = 0.1;
  return m;
}

struct Rig {
  DeviceChannels channels{1 << 12};
  std::unique_ptr<HapticLoop> loop;

  /// A device held still at height z over the plane z = 0 (normal +z).
  explicit Rig(double z, double stiffness = 1000.0) {
    haptics::WaypointsPath still;
    still.points = {{0.0, Vec3(0, 0, z)}};
    auto device = std::make_unique<haptics::ScriptedDevice>(still, haptics::Tremor{}, haptics::DeviceLimits{});
    loop = std::make_unique<HapticLoop>(model(haptics::ContactLaw::penalty(stiffness)), std::move(device), channels);
  }
  void publish_plane(double surface_time, double mean_curvature = 0.0) {
    LocalContact& lc = channels.contact.write_buffer();
    lc.valid = true;
    lc.body = 0;
    lc.triangle = 0;
    lc.point = Vec3::Zero();
    lc.normal = Vec3::UnitZ();
    lc.surface_time = surface_time;
    lc.mean_curvature = mean_curvature;
    channels.contact.publish();
  }
  HapticFrame step(double t) {
    loop->step(t, 0, now_ns(), false);
    HapticFrame f, last;
    while (channels.frames.try_pop(f)) last = f;
    return last;
  }
};

TEST(HapticLoop, RendersThePenaltyForceOfTheContactPlane) {
  Rig rig(0.008);  // a 10 mm sphere 2 mm into the plane
  rig.publish_plane(0.0);
  HapticFrame f;
  for (int k = 0; k < 20; ++k) f = rig.step(k * 1e-3);  // past the 5 ms onset ramp
  EXPECT_EQ(f.contact, 1);
  EXPECT_NEAR(f.force.z(), 1000.0 * 0.002, 1e-9);
  EXPECT_NEAR(f.force.x(), 0.0, 1e-12);
  // The tissue gets the reaction of what was sent.
  rig.channels.load.update();
  EXPECT_TRUE(rig.channels.load.read().active);
  EXPECT_EQ(rig.channels.load.read().force, -f.force);
}

TEST(HapticLoop, HertzFingerFeelsTheTissueCurvature) {
  // Silicone finger (E 1 MPa, ν 0.48, R 10 mm) 1 mm into tissue (E 30 kPa, ν 0.45).
  auto force_at = [](double curvature) {
    Rig rig(0.009);
    haptics::WaypointsPath still;
    still.points = {{0.0, Vec3(0, 0, 0.009)}};
    rig.loop = std::make_unique<HapticLoop>(
        model(haptics::ContactLaw::hertz(contact::HertzParameters{0.01, {1e6, 0.48}, {3e4, 0.45}})), std::make_unique<haptics::ScriptedDevice>(still, haptics::Tremor{}, haptics::DeviceLimits{}), rig.channels);
    rig.publish_plane(0.0, curvature);
    HapticFrame f;
    for (int k = 0; k < 20; ++k) f = rig.step(k * 1e-3);
    return f.force.z();
  };
  const double e_star = 1.0 / ((1 - 0.48 * 0.48) / 1e6 + (1 - 0.45 * 0.45) / 3e4);
  const double flat = 4.0 / 3.0 * e_star * std::sqrt(0.01) * std::pow(1e-3, 1.5);
  EXPECT_NEAR(force_at(0.0), flat, 1e-9 * flat);
  // A convex bump as curved as the finger halves the effective radius: F/√2.
  EXPECT_NEAR(force_at(100.0), flat / std::sqrt(2.0), 1e-9 * flat);
  // A concave dip is felt harder.
  EXPECT_GT(force_at(-50.0), flat);
}

TEST(HapticLoop, AFrameAllocatesNothing) {
  Rig rig(0.008);
  rig.publish_plane(0.0);
  rig.step(0.0);  // first frame outside the count: lazily initialised state, if any
  HapticFrame f;
  testing::AllocationCounter counter;
  for (int k = 1; k <= 2000; ++k) {
    rig.loop->step(k * 1e-3, 0, now_ns(), false);
    if (k % 100 == 0) {
      rig.publish_plane(k * 1e-3);  // what the interaction loop does
      while (rig.channels.frames.try_pop(f)) {}
    }
  }
  EXPECT_EQ(counter.count(), 0u) << counter.bytes() << " bytes";
}

TEST(HapticLoop, RendersAPatchModelWithoutAllocating) {
  // A rigid patch (no physics body: zero compliance) of a plate at z = 0: the tool 2 mm into
  // it feels the penalty force, as from the plane, and no frame allocates, new patches or not.
  const mesh::TriMesh plate = mesh::grid_plate(0.1, 0.1, 10, 10);
  DeviceChannels channels(1 << 12);
  PatchRequest request;
  request.kind = contact::LocalModelKind::compliance;
  request.radius = 0.012;
  channels.request_patches(request);
  contact::PatchBuilder builder(plate.vertices.size(), plate.triangles, request.capacity);
  auto publish_patch = [&](double t, const Vec3& center = Vec3(0.001, 0.002, 0.008)) {
    contact::PatchBuilder::Inputs in;
    in.kind = request.kind;
    in.body = 0;
    in.time = t;
    in.center = center;
    in.radius = request.radius;
    in.surface = plate.vertices;
    builder.build(in, channels.patch->write_buffer());
    channels.patch->publish();
  };
  haptics::WaypointsPath still;
  still.points = {{0.0, Vec3(0.001, 0.002, 0.008)}};
  haptics::HapticModel c;
  c.algorithms.push_back(std::make_shared<haptics::SpheresOnPatch>(
      std::vector<haptics::ToolSphere>{{Vec3::Zero(), 0.01}}, haptics::ContactLaw::penalty(1000.0), 0.0, request.kind,
      request.capacity, false));
  c.safety.max_force = 10.0;
  c.safety.watchdog_timeout = 0.1;
  c.force_smoothing = 0.005;
  HapticLoop loop(c, std::make_unique<haptics::ScriptedDevice>(still, haptics::Tremor{}, haptics::DeviceLimits{}),
                  channels);
  publish_patch(0.0);
  HapticFrame f;
  for (int k = 0; k < 20; ++k) {
    loop.step(k * 1e-3, 0, now_ns(), false);
    while (channels.frames.try_pop(f)) {}
  }
  EXPECT_EQ(f.contact, 1);
  EXPECT_NEAR(f.force.z(), 1000.0 * 0.002, 1e-9);
  EXPECT_NEAR(f.force.x(), 0.0, 1e-12);
  channels.load.update();
  EXPECT_TRUE(channels.load.read().active);
  EXPECT_GE(channels.load.read().triangle, 0);  // the plate's own triangle, not the patch's

  testing::AllocationCounter counter;
  std::uint64_t publishing = 0;  // the simulation's side, which may allocate (its own thread)
  for (int k = 20; k <= 2000; ++k) {
    loop.step(k * 1e-3, 0, now_ns(), false);
    if (k % 10 == 0) {
      const testing::AllocationCounter publish;
      publish_patch(k * 1e-3);
      publishing += publish.count();
      while (channels.frames.try_pop(f)) {}
    }
  }
  EXPECT_EQ(counter.count() - publishing, 0u);
  EXPECT_NEAR(f.force.z(), 1000.0 * 0.002, 1e-9);
  // The tool sat at every patch's centre; a patch cut 18 mm away (1.5 radii) leaves it outside.
  EXPECT_LT(loop.patch_reach().max_fraction, 1e-12);
  EXPECT_EQ(loop.patch_reach().frames_outside, 0u);
  publish_patch(2.001, Vec3(0.001, 0.020, 0.008));
  loop.step(2.001, 0, now_ns(), false);
  loop.step(2.002, 0, now_ns(), false);
  EXPECT_NEAR(loop.patch_reach().max_fraction, 1.5, 1e-9);
  EXPECT_EQ(loop.patch_reach().frames_outside, 2u);
}

TEST(HapticLoop, AStalledSimulationFadesTheForceOut) {
  Rig rig(0.008);
  rig.publish_plane(0.0);  // and never again
  HapticFrame f;
  for (int k = 0; k <= 50; ++k) f = rig.step(k * 1e-3);
  EXPECT_NEAR(f.force.z(), 2.0, 1e-9);  // fresh enough at 50 ms
  bool fading_seen = false;
  for (int k = 51; k <= 300; ++k) {
    f = rig.step(k * 1e-3);
    fading_seen |= (f.flags & frame_fading) != 0;
  }
  EXPECT_TRUE(fading_seen);
  EXPECT_EQ(f.force, Vec3::Zero());  // 100 ms timeout + 50 ms fade, long gone by 300 ms
  EXPECT_EQ(rig.loop->safety_counters().watchdog_trips, 1u);
  LoopEvent e;
  bool trip_event = false;
  while (rig.channels.events.try_pop(e)) trip_event |= e.kind == EventKind::watchdog_trip;
  EXPECT_TRUE(trip_event);
}

}  // namespace
}  // namespace tactus::runtime
