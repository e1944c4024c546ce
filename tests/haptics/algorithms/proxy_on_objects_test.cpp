// The proxy among touchable objects: the union of their levels, the painted material felt as
// painted, the roughness texture, the level chosen within the budget and switched by force
// with the force continuous, and the proxy carried across a switch without falling through.
#include "haptics/algorithms/proxy_on_objects.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/counting_allocator.hpp"
#include "mesh/generators.hpp"

namespace tactus::haptics {
namespace {

using property_images::Channel;

constexpr double kDt = 0.001;

contact::ProxyParams coupling(double stiffness) {
  contact::ProxyParams p;
  p.radius = 0.002;
  p.stiffness = stiffness;
  contact::validate_proxy_params(p);
  return p;
}

mesh::TriMesh moved(mesh::TriMesh m, const Vec3& by) {
  for (Vec3& v : m.vertices) v += by;
  return m;
}

TouchableObject object_of(const mesh::TriMesh& surface, int coarse, int finer, std::int32_t body = 0) {
  lod::ImpostorParams p;
  p.coarse_levels = coarse;
  p.subdivision_levels = finer;
  TouchableObject o;
  o.body = body;
  o.levels = std::make_shared<const lod::ImpostorHierarchy>(lod::build_impostors(surface, p));
  return o;
}

property_images::SurfaceProperties material(double stiffness) {
  property_images::SurfaceProperties m;
  m[Channel::stiffness] = stiffness;
  return m;
}

/// Drives an algorithm frame by frame with no contact plane.
struct Driver {
  explicit Driver(std::shared_ptr<const ProxyOnObjects> a) : algorithm(std::move(a)), state(algorithm->make_state()) {}
  Rendering step(const Vec3& position) {
    FrameInputs f;
    f.t = t;
    f.dt = kDt;
    f.position = position;
    f.contact = &plane;
    last = algorithm->render(f, *state);
    t += kDt;
    return last;
  }
  /// Moves in a straight line over `frames`, returning the last rendering.
  Rendering move(const Vec3& from, const Vec3& to, int frames) {
    for (int i = 1; i <= frames; ++i) step(from + (to - from) * (static_cast<double>(i) / frames));
    return last;
  }
  std::shared_ptr<const ProxyOnObjects> algorithm;
  std::unique_ptr<AlgorithmState> state;
  LocalContact plane;
  Rendering last;
  double t = 0.0;
};

TEST(ProxyOnObjects, PaintedStiffnessIsFeltAsPainted) {
  // A slab 10 × 10 × 2 cm, top at z = 0.01, painted at 800 N/m on its left half's middle and
  // 400 N/m elsewhere: pressing 3 mm into each gives twice the force on the painted spot.
  const mesh::TriMesh slab = mesh::box_surface(Vec3(0.1, 0.1, 0.02), 4);
  TouchableObject o = object_of(slab, 0, 0);
  o.properties = std::make_shared<property_images::PropertyImages>(
      property_images::PropertyImages::build(slab, 128, material(400), {"test", {}, {}, {}}));
  o.properties->paint(Vec3(-0.025, 0, 0.01), 0.015, material(800), property_images::mask_of(Channel::stiffness));
  const auto algorithm =
      std::make_shared<ProxyOnObjects>(ToolSphere{Vec3::Zero(), 0.002}, coupling(500), std::vector{o}, ObjectsSettings{});
  const auto press = [&](double x) {
    Driver d(algorithm);
    d.move(Vec3(x, 0, 0.03), Vec3(x, 0, 0.012), 20);
    return d.move(Vec3(x, 0, 0.012), Vec3(x, 0, 0.009), 200).force.z();  // 3 mm past the surface
  };
  const double painted = press(-0.025), plain = press(0.025);
  std::printf("painted %.4f N, plain %.4f N, ratio %.4f\n", painted, plain, painted / plain);
  EXPECT_NEAR(plain, 400.0 * 0.003, 400.0 * 0.003 * 0.01);
  EXPECT_NEAR(painted / plain, 2.0, 2.0 * 0.02);
}

TEST(ProxyOnObjects, RoughnessTiltsTheForceWithTheTexture) {
  // Sliding 12 mm across a frictionless rough strip (100 µm, 4 mm): the sideways force changes
  // sign with the texture's slope, at most F_n·A·2π/λ, and its mean is near zero.
  const mesh::TriMesh slab = mesh::box_surface(Vec3(0.1, 0.1, 0.02), 4);
  TouchableObject o = object_of(slab, 0, 0);
  property_images::SurfaceProperties m = material(500);
  m[Channel::roughness_amplitude] = 1e-4;
  m[Channel::roughness_wavelength] = 0.004;
  o.properties = std::make_shared<property_images::PropertyImages>(
      property_images::PropertyImages::build(slab, 128, m, {"test", {}, {}, {}}));
  Driver d(std::make_shared<ProxyOnObjects>(ToolSphere{Vec3::Zero(), 0.002}, coupling(500), std::vector{o},
                                            ObjectsSettings{}));
  d.move(Vec3(0, 0.001, 0.03), Vec3(0, 0.001, 0.009), 100);
  double lo = 0.0, hi = 0.0, sum = 0.0;
  const int frames = 600;
  for (int i = 1; i <= frames; ++i) {
    const Rendering r = d.step(Vec3(0.012 * i / frames, 0.001, 0.009));
    lo = std::min(lo, r.force.x());
    hi = std::max(hi, r.force.x());
    sum += r.force.x();
  }
  const double bound = d.last.force.z() * 1.2 * 1e-4 * 2.0 * M_PI / 0.004;
  EXPECT_LT(lo, -0.2 * bound);
  EXPECT_GT(hi, 0.2 * bound);
  EXPECT_LT(std::max(-lo, hi), bound);
  EXPECT_LT(std::abs(sum / frames), 0.25 * bound);
}

TEST(ProxyOnObjects, TheUnionOfObjectsStopsTheProxyAtTheNearest) {
  const auto a = object_of(moved(mesh::box_surface(Vec3(0.04, 0.04, 0.04)), Vec3(-0.05, 0, 0)), 0, 0, 0);
  const auto b = object_of(moved(mesh::box_surface(Vec3(0.04, 0.04, 0.06)), Vec3(0.05, 0, 0)), 0, 0, 1);
  Driver d(std::make_shared<ProxyOnObjects>(ToolSphere{Vec3::Zero(), 0.002}, coupling(500), std::vector{a, b},
                                            ObjectsSettings{}));
  d.move(Vec3(-0.05, 0, 0.05), Vec3(-0.05, 0, 0.019), 50);  // onto a's top (z = 0.02)
  EXPECT_NEAR(d.last.force.z(), 500.0 * 0.003, 0.01);
  d.move(Vec3(-0.05, 0, 0.019), Vec3(-0.05, 0, 0.06), 30);
  d.move(Vec3(-0.05, 0, 0.06), Vec3(0.05, 0, 0.06), 100);
  d.move(Vec3(0.05, 0, 0.06), Vec3(0.05, 0, 0.029), 50);    // onto b's top (z = 0.03)
  EXPECT_NEAR(d.last.force.z(), 500.0 * 0.003, 0.01);
}

TEST(ProxyOnObjects, LevelsStayWithinTheBudgetAndFollowNearness) {
  // Three spheres in a row; a budget too small for all at their finest: the one under the
  // tool is finest, the far ones coarser, and the summed cost never exceeds the budget.
  std::vector<TouchableObject> objects;
  for (int i = 0; i < 3; ++i)
    objects.push_back(object_of(moved(mesh::sphere(0.02, 3), Vec3(0.06 * i, 0, 0)), 2, 1, i));
  ObjectsSettings settings;
  double finest = 0.0;
  for (const auto& o : objects) finest += LevelChooser::level_cost(o.levels->levels.back());
  settings.budget = 0.6 * finest;
  settings.influence_radius = 0.05;
  Driver d(std::make_shared<ProxyOnObjects>(ToolSphere{Vec3::Zero(), 0.002}, coupling(500), objects, settings));
  for (int i = 0; i <= 240; ++i) {
    d.step(Vec3(-0.02 + 0.0005 * i, 0, 0.03));
    ASSERT_LE(ProxyOnObjects::cost_in_use(*d.state), settings.budget * (1 + 1e-12)) << "frame " << i;
  }
  const auto levels = ProxyOnObjects::levels_in_use(*d.state);  // the tool is over sphere 2
  EXPECT_EQ(levels[2], objects[2].levels->levels.size() - 1);
  EXPECT_LT(levels[0], levels[2]);
}

TEST(ProxyOnObjects, AForceSwitchKeepsTheForceContinuousAndTheProxyOutside) {
  // Two spheres side by side and a budget that affords one at its finest only with the other
  // at its coarsest. Approaching between them, both get middle levels by nearness; pressing A
  // past raise_force takes it finer, level by level, to its finest (the touched object goes
  // first). The force steps at most 10 % of its value from frame to frame beyond the press's
  // own change, and the proxy is never inside the level it renders.
  const double radius = 0.03;
  TouchableObject a = object_of(mesh::sphere(radius, 3), 2, 0, 0);
  const TouchableObject b = object_of(moved(mesh::sphere(radius, 3), Vec3(0.07, 0, 0)), 2, 0, 1);
  a.raise_force = 0.5;
  a.lower_force = 0.1;
  ObjectsSettings settings;
  settings.influence_radius = 0.1;
  settings.budget = LevelChooser::level_cost(a.levels->levels.back()) +
                    LevelChooser::level_cost(b.levels->levels.front()) + 1e-12;
  const auto algorithm = std::make_shared<ProxyOnObjects>(ToolSphere{Vec3::Zero(), 0.002}, coupling(500),
                                                          std::vector{a, b}, settings);
  Driver d(algorithm);
  const std::size_t finest = a.levels->levels.size() - 1;
  // The top of A's levels along the tool's line.
  const Vec3 line(0.01, 0, 0);
  std::vector<contact::RayHit> hits;
  a.levels->levels.back().bvh.raycast(line + Vec3(0, 0, 0.1), Vec3(0, 0, -1), 0.2, hits);
  ASSERT_FALSE(hits.empty());
  const double top = hits.front().point.z();
  d.move(line + Vec3(0, 0, 0.06), line + Vec3(0, 0, top + 0.004), 100);
  const std::size_t start = ProxyOnObjects::levels_in_use(*d.state)[0];
  ASSERT_LT(start, finest);
  double worst = 0.0, previous = d.last.force.norm();
  std::size_t switches = 0, level = start;
  const int frames = 1000;
  for (int i = 1; i <= frames; ++i) {
    const Rendering r = d.step(line + Vec3(0, 0, top + 0.004 - 0.008 * i / frames));
    const double f = r.force.norm();
    const auto levels = ProxyOnObjects::levels_in_use(*d.state);
    if (levels[0] != level) {
      ++switches;
      level = levels[0];
    }
    ASSERT_LE(ProxyOnObjects::cost_in_use(*d.state), settings.budget);
    worst = std::max(worst, (std::abs(f - previous) - 500.0 * 0.008 / frames) / std::max(f, 0.1));
    previous = f;
    if (r.touching) {
      const auto c = a.levels->levels[levels[0]].bvh.closest_point_with_side(r.point + 1e-7 * r.force.normalized());
      EXPECT_FALSE(c.behind && c.distance > 1e-6) << "frame " << i;
    }
  }
  EXPECT_GE(switches, 1u);
  EXPECT_EQ(level, finest);
  EXPECT_GT(d.last.force.norm(), 1.0);
  EXPECT_LT(worst, 0.10);
}

TEST(ProxyOnObjects, ALightTouchKeepsItsLevelUntilLetGo) {
  // Below lower_force for far longer than hold_time, the touched object keeps its level (a
  // coarser level's surface lies elsewhere: switching under the finger would be felt).
  TouchableObject o = object_of(mesh::sphere(0.03, 3), 2, 0);
  o.lower_force = 0.5;
  o.raise_force = 1.0;
  o.hold_time = 0.05;
  Driver d(std::make_shared<ProxyOnObjects>(ToolSphere{Vec3::Zero(), 0.002}, coupling(500), std::vector{o},
                                            ObjectsSettings{}));
  std::vector<contact::RayHit> hits;
  o.levels->levels.back().bvh.raycast(Vec3(0, 0, 0.1), Vec3(0, 0, -1), 0.2, hits);
  ASSERT_FALSE(hits.empty());
  const double top = hits.front().point.z();
  d.move(Vec3(0, 0, 0.06), Vec3(0, 0, top + 0.0019), 100);  // 0.05 N
  const std::size_t touched_at = ProxyOnObjects::levels_in_use(*d.state)[0];
  for (int i = 0; i < 500; ++i) {
    ASSERT_TRUE(d.step(Vec3(0, 0, top + 0.0019)).touching) << i;
    ASSERT_EQ(ProxyOnObjects::levels_in_use(*d.state)[0], touched_at) << "frame " << i;
  }
}

TEST(ProxyOnObjects, RenderAllocatesNothing) {
  std::vector<TouchableObject> objects;
  for (int i = 0; i < 2; ++i) objects.push_back(object_of(moved(mesh::sphere(0.02, 2), Vec3(0.05 * i, 0, 0)), 1, 0, i));
  ObjectsSettings settings;
  settings.budget = 1e-6;
  Driver d(std::make_shared<ProxyOnObjects>(ToolSphere{Vec3::Zero(), 0.002}, coupling(500), objects, settings));
  d.step(Vec3(0, 0, 0.05));
  const tactus::testing::AllocationCounter counter;
  d.move(Vec3(0, 0, 0.05), Vec3(0.05, 0, 0.015), 300);
  EXPECT_EQ(counter.count(), 0u);
}

TEST(ProxyOnObjects, RefusesSwitchThresholdsOutOfOrder) {
  TouchableObject o = object_of(mesh::sphere(0.02, 1), 0, 0);
  o.raise_force = 0.5;
  o.lower_force = 1.0;
  EXPECT_THROW(ProxyOnObjects(ToolSphere{}, coupling(500), std::vector{o}, ObjectsSettings{}), InputError);
  TouchableObject none;
  EXPECT_THROW(ProxyOnObjects(ToolSphere{}, coupling(500), std::vector{none}, ObjectsSettings{}), InputError);
}

}  // namespace
}  // namespace tactus::haptics
