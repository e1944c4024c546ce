// Property image files: saved and reloaded exactly, and every broken file refused with the
// file and the reason.
#include "property_images/property_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/hdf5_file.hpp"
#include "mesh/generators.hpp"

namespace tactus::property_images {
namespace {

namespace fs = std::filesystem;

SurfaceProperties material(double stiffness) {
  SurfaceProperties p;
  p[Channel::stiffness] = stiffness;
  p[Channel::static_friction] = 0.5;
  p[Channel::kinetic_friction] = 0.25;
  p[Channel::roughness_amplitude] = 5e-5;
  p[Channel::roughness_wavelength] = 2e-3;
  return p;
}

class PropertyFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("tactus_property_file_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;

  static std::string refusal(const fs::path& p, std::optional<std::uint64_t> hash = std::nullopt) {
    try {
      (void)read_property_images(p, hash);
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().file.rfind(p.string(), 0), 0u) << e.what();
      return e.reason();
    }
    ADD_FAILURE() << "accepted " << p;
    return {};
  }
};

TEST_F(PropertyFile, RoundTripIsExact) {
  const auto ball = mesh::sphere(0.04, 3);
  auto images = PropertyImages::build(ball, 48, material(300), {"test", {}, {}, {}});
  images.paint(Vec3(0, 0, 0.04), 0.012, material(650), kAllChannels);
  const fs::path file = dir_ / "ball.h5";
  write_property_images(file, images);
  EXPECT_FALSE(fs::exists(file.string() + ".tmp"));
  const auto back = read_property_images(file, ball.content_hash());
  EXPECT_EQ(back.mesh_hash(), images.mesh_hash());
  EXPECT_EQ(back.pixel(), images.pixel());
  EXPECT_EQ(back.box().min, images.box().min);
  EXPECT_EQ(back.box().max, images.box().max);
  EXPECT_EQ(back.base().values, images.base().values);
  for (int i = 0; i < PropertyImages::kViewCount; ++i) {
    EXPECT_EQ(back.views()[i].width, images.views()[i].width);
    EXPECT_EQ(back.views()[i].depth, images.views()[i].depth);
    EXPECT_EQ(back.views()[i].values, images.views()[i].values);
  }
  EXPECT_DOUBLE_EQ(back.lookup(Vec3(0, 0, 0.04), Vec3::UnitZ()).properties[Channel::stiffness], 650.0);
}

// Rewrites a version 2 file as version 1 wrote it: the first six channels only.
void write_as_version_1(const fs::path& path, const PropertyImages& images) {
  write_property_images(path, images);
  hdf5::Handle file(H5Fopen(path.string().c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
  ASSERT_TRUE(file.valid());
  for (const char* name : {"version", "channels", "base"}) ASSERT_GE(H5Adelete(file, name), 0);
  hdf5::Writer w(path, "a version 1 file");
  const int one = 1;
  w.attribute(file, "version", H5T_NATIVE_INT, &one);
  w.attribute(file, "channels", "stiffness,static_friction,kinetic_friction,damping,roughness_amplitude,"
                                "roughness_wavelength");
  w.attribute(file, "base", H5T_NATIVE_DOUBLE, images.base().values.data(), 6);
  const std::array<const char*, 6> names = {"views/+x", "views/-x", "views/+y", "views/-y", "views/+z", "views/-z"};
  for (int i = 0; i < PropertyImages::kViewCount; ++i) {
    const View& v = images.views()[i];
    hdf5::Handle g(H5Gopen2(file, names[i], H5P_DEFAULT), H5Gclose);
    ASSERT_GE(H5Ldelete(g, "values", H5P_DEFAULT), 0);
    std::vector<float> six;
    for (std::size_t p = 0; p < v.depth.size(); ++p)
      for (int c = 0; c < 6; ++c) six.push_back(v.values[p * kChannelCount + static_cast<std::size_t>(c)]);
    w.dataset(g, "values", H5T_NATIVE_FLOAT,
              {static_cast<hsize_t>(v.height), static_cast<hsize_t>(v.width), hsize_t{6}}, six.data());
  }
}

// A file written before E and ν were channels reads with them 0 (the body's material) and
// every other channel as it was.
TEST_F(PropertyFile, ReadsVersion1FilesWithTheBodysElasticConstants) {
  const auto ball = mesh::sphere(0.04, 3);
  auto images = PropertyImages::build(ball, 32, material(300), {"test", {}, {}, {}});
  images.paint(Vec3(0, 0, 0.04), 0.012, material(650), kAllChannels);
  const fs::path file = dir_ / "old.h5";
  write_as_version_1(file, images);
  const auto back = read_property_images(file, ball.content_hash());
  EXPECT_EQ(back.base().values, images.base().values);
  for (int i = 0; i < PropertyImages::kViewCount; ++i) EXPECT_EQ(back.views()[i].values, images.views()[i].values);
  const auto at = back.lookup(Vec3(0, 0, 0.04), Vec3::UnitZ()).properties;
  EXPECT_DOUBLE_EQ(at[Channel::stiffness], 650.0);
  EXPECT_EQ(at[Channel::young_modulus], 0.0);
}

// E and ν round-trip like the other channels, and a ν above 0.5 is refused.
TEST_F(PropertyFile, ElasticConstantChannelsRoundTripAndAreChecked) {
  const auto ball = mesh::sphere(0.04, 3);
  SurfaceProperties base = material(300);
  base[Channel::young_modulus] = 5e4;
  base[Channel::poisson_ratio] = 0.45;
  auto images = PropertyImages::build(ball, 32, base, {"test", {}, {}, {}});
  SurfaceProperties stiff = base;
  stiff[Channel::young_modulus] = 4e5;
  images.paint(Vec3(0, 0, 0.04), 0.012, stiff, mask_of(Channel::young_modulus));
  const fs::path file = dir_ / "elastic.h5";
  write_property_images(file, images);
  const auto back = read_property_images(file, ball.content_hash());
  EXPECT_NEAR(back.lookup(Vec3(0, 0, 0.04), Vec3::UnitZ()).properties[Channel::young_modulus], 4e5, 1e-9 * 4e5);
  EXPECT_NEAR(back.lookup(Vec3(0, 0, -0.04), -Vec3::UnitZ()).properties[Channel::young_modulus], 5e4, 1e-9 * 5e4);
  EXPECT_NEAR(back.lookup(Vec3(0, 0, 0.04), Vec3::UnitZ()).properties[Channel::poisson_ratio], 0.45, 1e-7);
  SurfaceProperties wrong = base;
  wrong[Channel::poisson_ratio] = 0.6;
  try {
    validate(wrong, {"scene.toml", {}, {}, {}});
    FAIL() << "accepted ν = 0.6";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("poisson_ratio must be in [0, 0.5]"), std::string::npos) << e.what();
  }
}

TEST_F(PropertyFile, RefusesBrokenFiles) {
  const auto box = mesh::box_surface(Vec3(0.03, 0.03, 0.03));
  const auto images = PropertyImages::build(box, 16, material(300), {"test", {}, {}, {}});
  const fs::path good = dir_ / "good.h5";
  write_property_images(good, images);

  EXPECT_NE(refusal(dir_ / "missing.h5").find("file not found"), std::string::npos);
  EXPECT_NE(refusal(good, box.content_hash() + 1).find("another mesh"), std::string::npos);

  const fs::path garbage = dir_ / "garbage.h5";
  std::ofstream(garbage) << "not an image at all";
  EXPECT_NE(refusal(garbage).find("not an HDF5 file"), std::string::npos);

  const fs::path truncated = dir_ / "truncated.h5";
  fs::copy_file(good, truncated);
  fs::resize_file(truncated, fs::file_size(good) / 2);
  EXPECT_FALSE(refusal(truncated).empty());

  // A negative stiffness in one pixel: the error names the view and the pixel.
  auto views = images.views();
  views[4].values[(3 * static_cast<std::size_t>(views[4].width) + 5) * kChannelCount] = -2.0f;
  const PropertyImages negative(images.box(), images.pixel(), images.mesh_hash(), images.base(), views);
  const fs::path bad = dir_ / "negative.h5";
  write_property_images(bad, negative);
  try {
    (void)read_property_images(bad);
    FAIL() << "accepted a negative stiffness";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("views/+z pixel (column 5, row 3)"), std::string::npos) << what;
    EXPECT_NE(what.find("stiffness must be"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace tactus::property_images
