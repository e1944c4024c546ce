// Property images: the depths they cast against closed forms, lookups that find the view
// that sees a point, painting that changes what is felt there and nowhere else.
#include "property_images/property_images.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <random>
#include <thread>

#include "core/counting_allocator.hpp"
#include "mesh/generators.hpp"

namespace tactus::property_images {
namespace {

SurfaceProperties material(double stiffness, double mus = 0.4, double muk = 0.3) {
  SurfaceProperties p;
  p[Channel::stiffness] = stiffness;
  p[Channel::static_friction] = mus;
  p[Channel::kinetic_friction] = muk;
  p[Channel::damping] = 1.0;
  return p;
}
const SourceLocation kHere{"test", {}, {}, {}};

TEST(PropertyImages, ABoxIsSeenOnePixelInFromEveryFace) {
  // A 0.1 × 0.06 × 0.04 m box: the longest side has 100 pixels of 1 mm, and the box is grown
  // by one pixel, so every ray through the face meets the surface 1 mm in.
  const auto images = PropertyImages::build(mesh::box_surface(Vec3(0.1, 0.06, 0.04)), 100, material(500), kHere);
  EXPECT_NEAR(images.pixel(), 1e-3, 1e-15);
  for (const View& v : images.views()) {
    const Vec3 size = images.box().size();
    EXPECT_EQ(v.width, static_cast<int>(std::ceil(size[v.u_axis] / images.pixel())));
    int hits = 0;
    for (int row = 1; row + 1 < v.height; ++row)
      for (int col = 1; col + 1 < v.width; ++col) {
        EXPECT_NEAR(v.depth[static_cast<std::size_t>(row) * v.width + col], 1e-3, 1e-7);
        ++hits;
      }
    EXPECT_GT(hits, 0);
  }
}

TEST(PropertyImages, SphereDepthsFollowTheSphere) {
  // Depth from the +z face at distance r from the axis: pad + R − √(R² − r²), within the
  // icosphere's deviation from the true sphere (R (1 − cos of half an edge's angle)).
  const double radius = 0.05;
  const auto ball = mesh::sphere(radius, 5);
  const auto images = PropertyImages::build(ball, 128, material(500), kHere);
  const View& top = images.views()[4];
  ASSERT_EQ(top.axis, 2);
  ASSERT_EQ(top.sign, 1);
  const double pad = images.box().max.z() - radius;
  double worst = 0.0;
  int seen = 0;
  for (int row = 0; row < top.height; ++row)
    for (int col = 0; col < top.width; ++col) {
      const Vec3 p = images.surface_point(4, col, row);
      const double r = std::hypot(p.x(), p.y());
      const float d = top.depth[static_cast<std::size_t>(row) * top.width + col];
      if (r > 0.9 * radius) continue;
      ASSERT_TRUE(std::isfinite(d));
      worst = std::max(worst, std::abs(d - (pad + radius - std::sqrt(radius * radius - r * r))));
      ++seen;
    }
  EXPECT_GT(seen, 5000);
  EXPECT_LT(worst, 2e-4);  // a subdivision-5 icosphere of 5 cm deviates up to ~0.1 mm
}

TEST(PropertyImages, EverySurfacePointOfAConvexBodyIsSeen) {
  const auto ball = mesh::sphere(0.05, 4);
  const auto images = PropertyImages::build(ball, 96, material(500), kHere);
  for (std::size_t i = 0; i < ball.vertices.size(); ++i) {
    const Vec3 p = ball.vertices[i];
    const Lookup l = images.lookup(p, p.normalized());
    ASSERT_GE(l.view, 0) << "vertex " << i;
    EXPECT_FLOAT_EQ(static_cast<float>(l.properties[Channel::stiffness]), 500.0f);
  }
}

TEST(PropertyImages, PaintingChangesWhatIsFeltThereAndNowhereElse) {
  auto images = PropertyImages::build(mesh::box_surface(Vec3(0.1, 0.1, 0.04)), 100, material(400), kHere);
  const Vec3 up = Vec3::UnitZ();
  const std::size_t written = images.paint(Vec3(0.02, 0, 0.02), 0.01, material(800), mask_of(Channel::stiffness));
  // A disc of 10 mm on a 1 mm grid: π·10² ≈ 314 pixels of the top view (and none of the
  // side views, whose surface points lie farther than 10 mm from the brush's centre but at
  // the top edge).
  EXPECT_NEAR(static_cast<double>(written), 314.0, 25.0);
  EXPECT_DOUBLE_EQ(images.lookup(Vec3(0.02, 0, 0.02), up).properties[Channel::stiffness], 800.0);
  EXPECT_DOUBLE_EQ(images.lookup(Vec3(0.02, 0.004, 0.02), up).properties[Channel::stiffness], 800.0);
  EXPECT_DOUBLE_EQ(images.lookup(Vec3(-0.02, 0, 0.02), up).properties[Channel::stiffness], 400.0);
  // Only the masked channel changed.
  EXPECT_NEAR(images.lookup(Vec3(0.02, 0, 0.02), up).properties[Channel::static_friction], 0.4, 1e-7);
  // The bottom face under the stroke is not painted.
  EXPECT_DOUBLE_EQ(images.lookup(Vec3(0.02, 0, -0.02), -up).properties[Channel::stiffness], 400.0);
  // Across the stroke's edge the value is filtered between the two, monotonically.
  double last = 800.0;
  for (double x = 0.026; x <= 0.034; x += 0.0005) {
    const double k = images.lookup(Vec3(x, 0, 0.02), up).properties[Channel::stiffness];
    EXPECT_LE(k, last + 1e-9);
    EXPECT_GE(k, 400.0 - 1e-9);
    last = k;
  }
  EXPECT_DOUBLE_EQ(last, 400.0);
}

TEST(PropertyImages, AHiddenPointTakesTheNextViewThatSeesIt) {
  // A box's side face seen from +x; a point on it with a normal tilted up would pick the top
  // view first, which sees the top face at another depth, so the +x view answers.
  auto images = PropertyImages::build(mesh::box_surface(Vec3(0.04, 0.04, 0.04)), 80, material(300), kHere);
  images.paint(Vec3(0.02, 0, 0), 0.005, material(600), kAllChannels);
  const Lookup l = images.lookup(Vec3(0.02, 0, 0), Vec3(0.6, 0, 0.8));
  EXPECT_EQ(l.view, 0);
  EXPECT_DOUBLE_EQ(l.properties[Channel::stiffness], 600.0);
  // A point inside, where no view sees a surface: the base material, view −1.
  const Lookup inside = images.lookup(Vec3(0, 0, 0), Vec3::UnitZ());
  EXPECT_EQ(inside.view, -1);
  EXPECT_DOUBLE_EQ(inside.properties[Channel::stiffness], 300.0);
}

TEST(PropertyImages, RoughnessGradientIsTheHeightsDerivative) {
  const auto images = PropertyImages::build(mesh::box_surface(Vec3(0.05, 0.05, 0.05)), 50, material(300), kHere);
  const Vec3 p(0.0031, -0.0072, 0.025);
  const double a = 1e-4, lambda = 0.004, h = 1e-8;
  const auto at = images.roughness_height(p, 4, a, lambda);
  EXPECT_LE(std::abs(at.h), a);
  for (int axis = 0; axis < 3; ++axis) {
    Vec3 step = Vec3::Zero();
    step[axis] = h;
    const double numeric = (images.roughness_height(p + step, 4, a, lambda).h -
                            images.roughness_height(p - step, 4, a, lambda).h) / (2 * h);
    EXPECT_NEAR(at.gradient[axis], numeric, 1e-6);
  }
  EXPECT_EQ(at.gradient.z(), 0.0);
  EXPECT_EQ(images.roughness_height(p, 4, 0.0, lambda).h, 0.0);
}

TEST(PropertyImages, LookupAllocatesNothing) {
  const auto images = PropertyImages::build(mesh::sphere(0.05, 3), 64, material(500), kHere);
  std::mt19937 rng(3);
  std::normal_distribution<double> n;
  std::vector<Vec3> dirs(500);
  for (Vec3& d : dirs) d = Vec3(n(rng), n(rng), n(rng)).normalized();
  double sum = 0.0;
  const tactus::testing::AllocationCounter counter;
  for (const Vec3& d : dirs) sum += images.lookup(0.05 * d, d).properties[Channel::stiffness];
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(sum, 0.0);
}

TEST(PropertyImages, LookupsWhilePaintingSeeOldOrNewValues) {
  // The haptic loop looks up while the viewer paints (a TSan build checks the race freedom).
  auto images = PropertyImages::build(mesh::box_surface(Vec3(0.05, 0.05, 0.05)), 64, material(100), kHere);
  std::atomic<bool> done{false};
  std::thread painter([&] {
    for (int i = 0; i < 200; ++i) images.paint(Vec3(0, 0, 0.025), 0.01, material(100 + i), kAllChannels);
    done = true;
  });
  int bad = 0, looks = 0;
  while (!done || looks < 1000) {
    const double k = images.lookup(Vec3(0, 0, 0.025), Vec3::UnitZ()).properties[Channel::stiffness];
    bad += (k < 100.0 || k > 299.0) ? 1 : 0;
    ++looks;
  }
  painter.join();
  EXPECT_EQ(bad, 0);
  EXPECT_DOUBLE_EQ(images.lookup(Vec3(0, 0, 0.025), Vec3::UnitZ()).properties[Channel::stiffness], 299.0);
}

TEST(PropertyImages, RefusesBadInput) {
  const auto box = mesh::box_surface(Vec3(0.05, 0.05, 0.05));
  EXPECT_THROW((void)PropertyImages::build(box, 1, material(100), kHere), InputError);
  EXPECT_THROW((void)PropertyImages::build(box, 64, material(-1), kHere), InputError);
  auto open = box;
  open.triangles.pop_back();
  try {
    (void)PropertyImages::build(open, 64, material(100), kHere);
    FAIL() << "an open surface was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("closed surface"), std::string::npos) << e.what();
  }
  const auto refused = [](auto change, const char* word) {
    SurfaceProperties p = material(100);
    change(p);
    try {
      validate(p, kHere);
      FAIL() << "accepted " << word;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
    }
  };
  refused([](SurfaceProperties& p) { p[Channel::stiffness] = -5; }, "stiffness");
  refused([](SurfaceProperties& p) { p[Channel::damping] = std::nan(""); }, "damping");
  refused([](SurfaceProperties& p) { p[Channel::kinetic_friction] = 0.9; }, "kinetic_friction");
  refused([](SurfaceProperties& p) { p[Channel::roughness_amplitude] = 1e-4; }, "roughness_wavelength");
  refused([](SurfaceProperties& p) { p[Channel::roughness_amplitude] = 0.5; }, "roughness_amplitude");
}

}  // namespace
}  // namespace tactus::property_images
