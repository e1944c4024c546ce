// `tactus mesh --labels` as a user runs it: the outputs carry the regions, and every bad
// input is one located line on stderr with exit status 1.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "imaging/label_image.hpp"
#include "mesh/io/mesh_io.hpp"
#include "phantom.hpp"
#include "png_slices.hpp"

namespace tactus::imaging {
namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code;
  std::string out, err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class LabelCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("tactus_label_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  Result run(const std::string& args) {
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    const std::string cmd = std::string("CI=1 '") + TACTUS_BINARY + "' " + args + " >'" + out.string() + "' 2>'" +
                            err.string() + "' </dev/null";
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
  }
  /// Runs and expects exit 1 with exactly one line on stderr holding `expected`.
  void expect_refused(const std::string& args, const std::string& expected) {
    const Result r = run(args);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << "expected '" << expected << "' in: " << r.err;
  }

  fs::path dir_;
};

TEST_F(LabelCli, WritesRegionsToVtuAndMsh) {
  const fs::path image = dir_ / "spheres.nii.gz";
  write_nifti(image, test::nested_spheres(40, 1e-3, 15e-3, 8e-3));
  for (const char* out : {"spheres.vtu", "spheres.msh"}) {
    const Result r = run("mesh --labels '" + image.string() + "' -o '" + (dir_ / out).string() +
                         "' --cell-size 3e-3 --cell-size-label 2=2e-3 --smooth 1");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("tetrahedra"), std::string::npos) << r.out;
    const auto file = mesh::read_mesh(dir_ / out);
    ASSERT_TRUE(file.volume);
    const std::set<int> regions(file.volume->tet_regions.begin(), file.volume->tet_regions.end());
    EXPECT_EQ(regions, (std::set<int>{1, 2})) << out;
  }
}

TEST_F(LabelCli, PngSlicesNeedTheirSpacing) {
  // A 12 x 12 x 8 block of label 3 in 16 x 16 slices, 0.5 mm pixels, 1 mm apart.
  fs::create_directories(dir_ / "slices");
  for (int k = 0; k < 10; ++k) {
    std::vector<int> px(256, 0);
    for (int j = 2; j < 14; ++j)
      for (int i = 2; i < 14; ++i) px[static_cast<std::size_t>(j * 16 + i)] = k >= 1 && k < 9 ? 3 : 0;
    std::string name = "z";
    name.append(std::to_string(10 + k)).append(".png");
    std::ofstream(dir_ / "slices" / name, std::ios::binary) << test::gray_png(16, 16, px, 8);
  }
  std::string args = "mesh --labels '";
  args.append((dir_ / "slices").string()).append("/*.png' -o '").append((dir_ / "block.vtu").string());
  args.append("' --cell-size 2e-3");
  expect_refused(args, "slices/*.png: a PNG slice stack needs --spacing SX,SY,SZ (metres)");
  const Result r = run(args.append(" --spacing 0.5e-3,0.5e-3,1e-3"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto file = mesh::read_mesh(dir_ / "block.vtu");
  ASSERT_TRUE(file.volume);
  // 6 x 6 x 8 mm of voxels; the interpolated boundary rounds the block's edges and corners.
  EXPECT_NEAR(file.volume->volume(), 6e-3 * 6e-3 * 8e-3, 0.1 * 6e-3 * 6e-3 * 8e-3);
  EXPECT_EQ(std::set<int>(file.volume->tet_regions.begin(), file.volume->tet_regions.end()), std::set<int>{3});
}

TEST_F(LabelCli, BadInputsAreOneLocatedLine) {
  LabelImage empty;
  empty.size = {4, 4, 4};
  empty.spacing = Vec3::Constant(1e-3);
  empty.labels.assign(64, 0);
  write_nifti(dir_ / "empty.nii", empty);
  const std::string out = " -o '" + (dir_ / "out.vtu").string() + "' --cell-size 1e-3";
  expect_refused("mesh --labels '" + (dir_ / "empty.nii").string() + "'" + out,
                 (dir_ / "empty.nii").string() + ": the image has no nonzero labels");

  LabelImage speck = empty;
  speck.labels[21] = 5;
  write_nrrd(dir_ / "speck.nrrd", speck);
  expect_refused("mesh --labels '" + (dir_ / "speck.nrrd").string() + "'" + out,
                 "speck.nrrd: label 5 has 1 voxel; at least 8 are needed to mesh it");

  write_nifti(dir_ / "whole.nii.gz", test::nested_spheres(20, 1e-3, 8e-3, 4e-3));
  const std::string gz = slurp(dir_ / "whole.nii.gz");
  std::ofstream(dir_ / "cut.nii.gz", std::ios::binary) << gz.substr(0, gz.size() - 100);
  expect_refused("mesh --labels '" + (dir_ / "cut.nii.gz").string() + "'" + out,
                 "cut.nii.gz: byte " + std::to_string(gz.size() - 100) + ": gzip data ends early");

  std::string header = slurp(dir_ / "empty.nii");
  const float zero = 0.0f;
  std::memcpy(header.data() + 80, &zero, 4);
  std::ofstream(dir_ / "flat.nii", std::ios::binary) << header;
  expect_refused("mesh --labels '" + (dir_ / "flat.nii").string() + "'" + out,
                 "flat.nii: byte 80: pixdim[1] (voxel spacing) is 0");

  expect_refused("mesh --labels '" + (dir_ / "whole.nii.gz").string() + "' -o '" + (dir_ / "x.vtu").string() + "'",
                 "--labels needs --cell-size");
  expect_refused("mesh --labels '" + (dir_ / "whole.nii.gz").string() + "'" + out + " --cell-size-label 9=1e-3",
                 "a cell size is given for label 9, which the image does not hold");
  expect_refused("mesh --labels '" + (dir_ / "whole.nii.gz").string() + "'" + out + " --facet-distance-label 9=1e-4",
                 "a facet distance is given for label 9, which the image does not hold");
  expect_refused("mesh --labels '" + (dir_ / "whole.nii.gz").string() + "'" + out + " --facet-distance-label 1",
                 "--facet-distance-label '1': expected LABEL=SIZE");
  expect_refused("mesh --labels '" + (dir_ / "whole.nii.gz").string() + "'" + out + " --cell-size-label x",
                 "--cell-size-label 'x': expected LABEL=SIZE");
  expect_refused("mesh --labels '" + (dir_ / "whole.nii.gz").string() + "' -o '" + (dir_ / "x.stl").string() +
                     "' --cell-size 1e-3",
                 "x.stl: a labelled mesh is written as .vtu, .vtk, .msh or TetGen");
}

}  // namespace
}  // namespace tactus::imaging
