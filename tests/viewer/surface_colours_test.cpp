// Colours per triangle: a multi-region body's regions (by their materials, with a legend), and
// a fabric's strain (the largest principal Green–Lagrange strain, checked against a stretch
// written out by hand).
#include "viewer/surface_colours.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <string>

#include "mesh/generators.hpp"
#include "mesh/io/mesh_io.hpp"
#include "scene/scene.hpp"

namespace tactus::viewer {
namespace {

TEST(StrainColours, AStretchAlongOneAxisGivesItsGreenStrain) {
  const Vec3 a0(0, 0, 0), b0(0.01, 0, 0), c0(0, 0.01, 0);
  // 10 % along x: E_xx = ((1.1)² − 1)/2 = 0.105, E_yy = 0.
  EXPECT_NEAR(largest_strain(a0, b0, c0, a0, 1.1 * b0, c0), 0.105, 1e-12);
  // The same stretch turned and moved anywhere: strain does not see rigid motion.
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Vec3 shift(0.3, -0.2, 0.1);
  EXPECT_NEAR(largest_strain(a0, b0, c0, turn * a0 + shift, turn * (1.1 * b0) + shift, turn * c0 + shift), 0.105,
              1e-12);
  // Squeezed 10 % in y and unchanged in x: the largest principal strain is 0.
  EXPECT_NEAR(largest_strain(a0, b0, c0, a0, b0, 0.9 * c0), 0.0, 1e-12);
  // A degenerate rest triangle has no strain to show.
  EXPECT_EQ(largest_strain(a0, b0, 2.0 * b0, a0, b0, c0), 0.0);
}

TEST(StrainColours, BlueAtRestRedAtFullScale) {
  const std::vector<Vec3> rest{{0, 0, 0}, {0.01, 0, 0}, {0, 0.01, 0}};
  const std::vector<mesh::Triangle> triangles{{0, 1, 2}};
  std::vector<Colour> out;
  strain_colours(rest, rest, triangles, 0.05, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0].isApprox(pressure_colour(0.0)));
  // Stretched until E = 0.05 along x: (s² − 1)/2 = 0.05, s = √1.1.
  std::vector<Vec3> pulled = rest;
  pulled[1].x() *= std::sqrt(1.1);
  strain_colours(rest, pulled, triangles, 0.05, out);
  EXPECT_TRUE(out[0].isApprox(pressure_colour(1.0), 1e-9));
  // Half of it: the ramp's middle.
  pulled[1].x() = 0.01 * std::sqrt(1.05);
  strain_colours(rest, pulled, triangles, 0.05, out);
  EXPECT_TRUE(out[0].isApprox(pressure_colour(0.5), 1e-9));
}

TEST(RegionColours, EachSurfaceTriangleTakesItsTetrahedronsRegion) {
  const auto dir = std::filesystem::temp_directory_path() / ("tactus_region_colours_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  mesh::TetMesh m = mesh::box_volume(Vec3(0.1, 0.02, 0.02), 6, 2, 2);
  for (const auto& t : m.tets) {
    double x = 0.0;
    for (const auto v : t) x += 0.25 * m.vertices[static_cast<std::size_t>(v)].x();
    m.tet_regions.push_back(x < 0.0 ? 1 : 2);
  }
  mesh::write_mesh(dir / "bar.vtu", m);
  const scene::Model model = scene::parse_scene(R"([materials.muscle]
young_modulus = 1e4
poisson_ratio = 0.45
density = 1060
[materials.bone]
young_modulus = 1e7
poisson_ratio = 0.3
density = 1900
[bodies.leg]
kind = "fem"
material = "muscle"
mesh = "bar.vtu"
[bodies.leg.regions]
2 = "bone"
)",
                                                (dir / "scene.toml").string());
  std::filesystem::remove_all(dir);
  const scene::Body& leg = model.bodies.at(0);
  const RegionColours c = region_colours(model, leg);
  ASSERT_EQ(c.triangles.size(), leg.surface.triangles.size());
  ASSERT_EQ(c.legend.size(), 2u);
  EXPECT_EQ(c.legend[0].first, "leg: muscle");
  EXPECT_EQ(c.legend[1].first, "leg: bone");
  EXPECT_FALSE(c.legend[0].second.isApprox(c.legend[1].second));
  // Every triangle on the bar's far half (x > 0) is bone's colour, on the near half muscle's.
  for (std::size_t i = 0; i < leg.surface.triangles.size(); ++i) {
    Vec3 centre = Vec3::Zero();
    for (const auto v : leg.surface.triangles[i]) centre += leg.surface.vertices[static_cast<std::size_t>(v)] / 3.0;
    if (std::abs(centre.x()) < 1e-9) continue;
    const Colour expected = centre.x() > 0 ? c.legend[1].second : c.legend[0].second;
    EXPECT_TRUE(c.triangles[i].isApprox(expected)) << "triangle " << i << " at x " << centre.x();
  }
  // A body of one region keeps its one colour.
  scene::Body plain = leg;
  plain.volume->tet_regions.assign(plain.volume->tets.size(), 1);
  EXPECT_TRUE(region_colours(model, plain).triangles.empty());
}

}  // namespace
}  // namespace tactus::viewer
