// A Hertz finger among touchable objects: pressed into a sphere object it gives Hertz's
// two-sphere force with the object's own material and the curvature its level holds; into a
// flat top, the sphere-on-half-space force; and the level choice is the proxy's.
#include "haptics/algorithms/spheres_on_objects.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/counting_allocator.hpp"
#include "mesh/generators.hpp"

namespace tactus::haptics {
namespace {

TouchableObject object_of(const mesh::TriMesh& surface) {
  lod::ImpostorParams p;
  p.coarse_levels = 1;
  p.subdivision_levels = 0;
  TouchableObject o;
  o.body = 0;
  o.levels = std::make_shared<const lod::ImpostorHierarchy>(lod::build_impostors(surface, p));
  return o;
}

/// Hertz's law, written out: F = 4/3 E* √R d^{3/2}, 1/E* = Σ (1 − ν²)/E, 1/R = Σ 1/R.
double hertz(double finger_radius, double object_radius, double depth, double e1, double nu1, double e2, double nu2) {
  const double e_star = 1.0 / ((1 - nu1 * nu1) / e1 + (1 - nu2 * nu2) / e2);
  const double r = 1.0 / (1.0 / finger_radius + (object_radius > 0 ? 1.0 / object_radius : 0.0));
  return 4.0 / 3.0 * e_star * std::sqrt(r) * std::pow(depth, 1.5);
}

Rendering press(const SpheresOnObjects& a, const Vec3& at) {
  auto state = a.make_state();
  LocalContact plane;
  Rendering r;
  for (int i = 0; i < 20; ++i) {  // a few frames: the level choice settles
    FrameInputs f;
    f.t = 0.001 * i;
    f.dt = 0.001;
    f.position = at;
    f.contact = &plane;
    r = a.render(f, *state);
  }
  return r;
}

TEST(SpheresOnObjects, AHertzFingerOnASphereObjectGivesTheTwoSphereForce) {
  const double rf = 0.008, ro = 0.05, depth = 5e-4;
  const contact::ElasticMaterial silicone{1e6, 0.48}, object{2e5, 0.45};
  contact::HertzParameters hp;
  hp.finger_radius = rf;
  hp.finger = silicone;
  hp.tissue = object;
  const TouchableObject ball = object_of(mesh::sphere(ro, 4));
  const SpheresOnObjects a({ToolSphere{Vec3::Zero(), rf}}, {ContactLaw::hertz(hp), ContactLaw::hertz(hp)}, 0.0, {ball},
                           ObjectsSettings{});
  // Where the finest level's surface is along +z: the finger's depth is measured from it.
  std::vector<contact::RayHit> hits;
  ball.levels->levels.back().bvh.raycast(Vec3(0, 0, 1), Vec3(0, 0, -1), 2.0, hits);
  ASSERT_FALSE(hits.empty());
  const double top = hits.front().point.z();
  const Rendering r = press(a, Vec3(0, 0, top + rf - depth));
  ASSERT_TRUE(r.touching);
  const double expected = hertz(rf, ro, depth, silicone.youngs_modulus, silicone.poisson_ratio, object.youngs_modulus,
                                object.poisson_ratio);
  std::printf("Hertz finger on a sphere object: %.5f N, Hertz %.5f N (%+.2f %%)\n", r.force.z(), expected,
              100.0 * (r.force.z() / expected - 1.0));
  // The level's voted curvature is within a few per cent of 1/r; F goes as √R.
  EXPECT_NEAR(r.force.z(), expected, 0.02 * expected);
  EXPECT_NEAR(r.force.x(), 0.0, 1e-3 * expected);
  // A ten times stiffer object pushes back harder, as Hertz says.
  contact::HertzParameters stiff = hp;
  stiff.tissue = {2e6, 0.45};
  const SpheresOnObjects b({ToolSphere{Vec3::Zero(), rf}}, {ContactLaw::hertz(stiff), ContactLaw::hertz(stiff)}, 0.0,
                           {ball}, ObjectsSettings{});
  const double stiffer = hertz(rf, ro, depth, 1e6, 0.48, 2e6, 0.45);
  EXPECT_NEAR(press(b, Vec3(0, 0, top + rf - depth)).force.z(), stiffer, 0.02 * stiffer);
}

TEST(SpheresOnObjects, OnAFlatTopItIsTheSphereOnAHalfSpace) {
  const double rf = 0.008, depth = 4e-4;
  contact::HertzParameters hp;
  hp.finger_radius = rf;
  hp.finger = {1e6, 0.48};
  hp.tissue = {5e5, 0.4};
  const TouchableObject slab = object_of(mesh::box_surface(Vec3(0.2, 0.2, 0.04), 8));
  const SpheresOnObjects a({ToolSphere{Vec3::Zero(), rf}}, {ContactLaw::hertz(hp), ContactLaw::hertz(hp)}, 0.0, {slab},
                           ObjectsSettings{});
  const Rendering r = press(a, Vec3(0.013, -0.021, 0.02 + rf - depth));
  const double expected = hertz(rf, 0.0, depth, 1e6, 0.48, 5e5, 0.4);
  EXPECT_NEAR(r.force.z(), expected, 1e-3 * expected);
  EXPECT_EQ(SpheresOnObjects::levels_in_use(*a.make_state()).size(), 1u);
}

// E and ν painted into the object's property images are what the Hertz finger presses where
// it touches: on the painted half of a slab the force is Hertz's with the painted material,
// on the other half with the object's own, at equal depth (only E* differs, so the ratio is
// that of the two E*, exactly up to the images' float storage).
TEST(SpheresOnObjects, PaintedElasticConstantsAreFeltWhereTheyArePainted) {
  const double rf = 0.008, depth = 4e-4;
  contact::HertzParameters hp;
  hp.finger_radius = rf;
  hp.finger = {1e6, 0.48};
  hp.tissue = {5e5, 0.4};
  const mesh::TriMesh surface = mesh::box_surface(Vec3(0.2, 0.2, 0.04), 8);
  TouchableObject slab = object_of(surface);
  using property_images::Channel;
  property_images::SurfaceProperties base;
  base[Channel::stiffness] = 500.0;
  base[Channel::young_modulus] = 5e5;
  base[Channel::poisson_ratio] = 0.4;
  slab.properties = std::make_shared<property_images::PropertyImages>(
      property_images::PropertyImages::build(surface, 256, base, SourceLocation{"slab", {}, {}, {}}));
  property_images::SurfaceProperties painted = base;
  painted[Channel::young_modulus] = 2e6;
  painted[Channel::poisson_ratio] = 0.3;
  // The slab's top at x > 0.005 m: E 2 MPa, ν 0.3.
  for (double x = 0.013; x <= 0.1; x += 0.005)
    for (double y = -0.1; y <= 0.1; y += 0.005)
      slab.properties->paint(Vec3(x, y, 0.02), 0.008,
                             painted, property_images::mask_of(Channel::young_modulus) |
                                          property_images::mask_of(Channel::poisson_ratio));
  const SpheresOnObjects a({ToolSphere{Vec3::Zero(), rf}}, {ContactLaw::hertz(hp), ContactLaw::hertz(hp)}, 0.0, {slab},
                           ObjectsSettings{});
  // Two points mirror images of each other across x = 0, so the level's voted curvature (a
  // little off zero this near the box's edges) is the same at both.
  const double own = press(a, Vec3(-0.025, 0.0, 0.02 + rf - depth)).force.z();
  const double stiff = press(a, Vec3(0.025, 0.0, 0.02 + rf - depth)).force.z();
  const double expected_own = hertz(rf, 0.0, depth, 1e6, 0.48, 5e5, 0.4);
  const double expected_stiff = hertz(rf, 0.0, depth, 1e6, 0.48, 2e6, 0.3);
  std::printf("Hertz finger on painted E: %.5f N (Hertz %.5f N), unpainted %.5f N (Hertz %.5f N)\n", stiff,
              expected_stiff, own, expected_own);
  // Against Hertz on a half-space: within the curvature the coarse box's voting finds here.
  EXPECT_NEAR(own, expected_own, 1e-2 * expected_own);
  EXPECT_NEAR(stiff, expected_stiff, 1e-2 * expected_stiff);
  EXPECT_NEAR(stiff / own, expected_stiff / expected_own, 1e-6 * expected_stiff / expected_own);
}

TEST(SpheresOnObjects, RenderAllocatesNothing) {
  contact::HertzParameters hp;
  hp.finger_radius = 0.008;
  hp.finger = {1e6, 0.48};
  hp.tissue = {2e5, 0.45};
  const TouchableObject ball = object_of(mesh::sphere(0.05, 3));
  const SpheresOnObjects a({ToolSphere{Vec3::Zero(), 0.008}}, {ContactLaw::hertz(hp), ContactLaw::hertz(hp)}, 0.0,
                           {ball}, ObjectsSettings{});
  auto state = a.make_state();
  LocalContact plane;
  FrameInputs f;
  f.dt = 0.001;
  f.contact = &plane;
  double pressed = 0.0;
  const tactus::testing::AllocationCounter counter;
  for (int i = 0; i < 300; ++i) {
    f.t = 0.001 * i;
    f.position = Vec3(0.0, 0.0, 0.07 - 0.0001 * i);  // from above into the ball
    pressed = std::max(pressed, a.render(f, *state).force.norm());
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(pressed, 0.1);
}

}  // namespace
}  // namespace tactus::haptics
