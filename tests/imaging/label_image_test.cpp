// The label image readers: round trips, known placements, and located refusals.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "core/png.hpp"
#include "imaging/label_image.hpp"
#include "png_slices.hpp"

namespace tactus::imaging {
namespace {

namespace fs = std::filesystem;

class LabelImageFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("tactus_label_image_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  static void spit(const fs::path& p, const std::string& data) {
    std::ofstream out(p, std::ios::binary);
    out << data;
  }
  /// The message of the InputError that reading `path` throws; "" when none is thrown.
  static std::string error_of(const fs::path& path, const std::optional<Vec3>& spacing = {}) {
    try {
      (void)read_label_image(path, spacing);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
};

LabelImage sample() {
  LabelImage image;
  image.size = {5, 4, 3};
  image.spacing = Vec3(0.5e-3, 0.75e-3, 1.25e-3);
  image.direction = Eigen::AngleAxisd(0.4, Vec3(0.2, -1, 0.5).normalized()).toRotationMatrix();
  image.origin = Vec3(-0.01, 0.02, 0.125);
  image.labels.resize(image.voxel_count());
  for (std::size_t v = 0; v < image.labels.size(); ++v) image.labels[v] = static_cast<std::int32_t>((v * 7) % 5);
  image.labels[3] = 300;  // beyond a byte
  return image;
}

void expect_same(const LabelImage& a, const LabelImage& b) {
  EXPECT_EQ(a.size, b.size);
  EXPECT_TRUE(a.spacing.isApprox(b.spacing, 1e-6)) << a.spacing.transpose() << " vs " << b.spacing.transpose();
  EXPECT_TRUE(a.direction.isApprox(b.direction, 1e-6)) << a.direction << "\nvs\n" << b.direction;
  EXPECT_LT((a.origin - b.origin).norm(), 1e-9);
  EXPECT_EQ(a.labels, b.labels);
}

TEST_F(LabelImageFiles, NiftiRoundTrip) {
  for (const char* name : {"a.nii", "a.nii.gz"}) {
    write_nifti(dir_ / name, sample());
    expect_same(sample(), read_label_image(dir_ / name));
  }
  LabelImage mirrored = sample();
  mirrored.direction.col(0) *= -1.0;
  write_nifti(dir_ / "m.nii", mirrored);
  expect_same(mirrored, read_nifti(dir_ / "m.nii"));
}

TEST_F(LabelImageFiles, NrrdRoundTrip) {
  write_nrrd(dir_ / "raw.nrrd", sample(), false);
  expect_same(sample(), read_label_image(dir_ / "raw.nrrd"));
  write_nrrd(dir_ / "gz.nrrd", sample(), true);
  expect_same(sample(), read_label_image(dir_ / "gz.nrrd"));
}

// Header fields built by hand, byte by byte as the NIfTI-1 standard places them.
struct NiftiHeader {
  std::string bytes = std::string(352, '\0');
  NiftiHeader() {
    put<std::int32_t>(0, 348);
    put<std::int16_t>(40, 3);
    put<std::int16_t>(42, 2);
    put<std::int16_t>(44, 2);
    put<std::int16_t>(46, 2);
    put<std::int16_t>(70, 2);  // uint8
    put<std::int16_t>(72, 8);
    for (int a = 1; a <= 3; ++a) put<float>(76 + 4 * a, 2.0f);
    put<float>(108, 352.0f);
    bytes[123] = 2;  // mm
    std::memcpy(bytes.data() + 344, "n+1\0", 4);
  }
  template <typename T>
  void put(std::size_t offset, T value) {
    std::memcpy(bytes.data() + offset, &value, sizeof(T));
  }
  [[nodiscard]] std::string with_voxels() const { return bytes + std::string("\1\0\0\0\0\0\0\2", 8); }
};

TEST_F(LabelImageFiles, NiftiPlacementFromEachForm) {
  NiftiHeader h;  // no form: pixdim alone, origin 0
  spit(dir_ / "plain.nii", h.with_voxels());
  LabelImage image = read_nifti(dir_ / "plain.nii");
  EXPECT_TRUE(image.spacing.isApprox(Vec3::Constant(2e-3)));
  EXPECT_TRUE(image.world(Vec3(1, 1, 1)).isApprox(Vec3::Constant(2e-3)));
  EXPECT_EQ(image.labels.front(), 1);
  EXPECT_EQ(image.labels.back(), 2);

  // qform: 90° about z (quatern_d = sin 45°), qfac -1 flips k, offset (10, 20, 30) mm.
  h.put<std::int16_t>(252, 1);
  h.put<float>(76, -1.0f);
  h.put<float>(264, static_cast<float>(std::sqrt(0.5)));
  h.put<float>(268, 10.0f);
  h.put<float>(272, 20.0f);
  h.put<float>(276, 30.0f);
  spit(dir_ / "qform.nii", h.with_voxels());
  image = read_nifti(dir_ / "qform.nii");
  EXPECT_TRUE(image.world(Vec3(0, 0, 0)).isApprox(Vec3(0.010, 0.020, 0.030)));
  EXPECT_TRUE(image.world(Vec3(1, 0, 0)).isApprox(Vec3(0.010, 0.022, 0.030), 1e-6)) << image.world(Vec3(1, 0, 0));
  EXPECT_TRUE(image.world(Vec3(0, 1, 0)).isApprox(Vec3(0.008, 0.020, 0.030), 1e-6)) << image.world(Vec3(0, 1, 0));
  EXPECT_TRUE(image.world(Vec3(0, 0, 1)).isApprox(Vec3(0.010, 0.020, 0.028), 1e-6)) << image.world(Vec3(0, 0, 1));

  // sform wins over the qform: a shear-free anisotropic affine, in metres (xyzt_units 1).
  h.put<std::int16_t>(254, 2);
  const float srow[3][4] = {{0, 0, 0.003f, 1}, {0.001f, 0, 0, 2}, {0, -0.002f, 0, 3}};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) h.put<float>(280 + 16 * r + 4 * c, srow[r][c]);
  h.bytes[123] = 1;
  spit(dir_ / "sform.nii", h.with_voxels());
  image = read_nifti(dir_ / "sform.nii");
  EXPECT_TRUE(image.spacing.isApprox(Vec3(0.001, 0.002, 0.003), 1e-6)) << image.spacing.transpose();
  EXPECT_TRUE(image.world(Vec3(1, 1, 1)).isApprox(Vec3(1.003, 2.001, 2.998), 1e-6)) << image.world(Vec3(1, 1, 1));
}

TEST_F(LabelImageFiles, NrrdLpsSpaceBecomesRas) {
  const std::string header =
      "NRRD0004\n# a comment\ntype: unsigned char\ndimension: 3\nspace: left-posterior-superior\n"
      "sizes: 2 2 2\nspace directions: (0.5,0,0) (0,0.5,0) (0,0,2)\nspace origin: (10,20,30)\n"
      "endian: little\nencoding: raw\ndata file: voxels.raw\n";
  spit(dir_ / "detached.nrrd", header);
  spit(dir_ / "voxels.raw", std::string("\0\0\0\0\0\0\0\3", 8));
  const LabelImage image = read_nrrd(dir_ / "detached.nrrd");
  EXPECT_TRUE(image.world(Vec3(0, 0, 0)).isApprox(Vec3(-0.010, -0.020, 0.030)));
  EXPECT_TRUE(image.world(Vec3(1, 1, 1)).isApprox(Vec3(-0.0105, -0.0205, 0.032)));
  EXPECT_EQ(image.labels.back(), 3);
}

TEST_F(LabelImageFiles, PngStackInNameOrder) {
  fs::create_directories(dir_ / "slices");
  spit(dir_ / "slices" / "s10.png", test::gray_png(3, 2, {0, 0, 0, 0, 0, 9}, 8));
  spit(dir_ / "slices" / "s00.png", test::gray_png(3, 2, {1, 0, 0, 0, 0, 0}, 8));
  spit(dir_ / "slices" / "notes.txt", "ignored");
  const Vec3 spacing(1e-3, 1e-3, 2e-3);
  LabelImage image = read_label_image(dir_ / "slices", spacing);
  EXPECT_EQ(image.size, (std::array<std::size_t, 3>{3, 2, 2}));
  EXPECT_EQ(image.labels.front(), 1);
  EXPECT_EQ(image.labels.back(), 9);
  EXPECT_TRUE(image.spacing.isApprox(spacing));

  spit(dir_ / "slices" / "s20.png", test::gray_png(3, 2, {0, 0, 0, 0, 0, 1000}, 16));
  image = read_label_image(dir_ / "slices" / "s*.png", spacing);
  EXPECT_EQ(image.size[2], 3u);
  EXPECT_EQ(image.labels.back(), 1000);

  EXPECT_NE(error_of(dir_ / "slices").find("needs --spacing"), std::string::npos);
  png::write_rgb(dir_ / "slices" / "s30.png", 3, 2, std::vector<std::uint8_t>(18, 0));
  EXPECT_NE(error_of(dir_ / "slices", spacing).find("s30.png: byte 0: a label slice must be one grayscale channel"),
            std::string::npos)
      << error_of(dir_ / "slices", spacing);
  fs::remove(dir_ / "slices" / "s30.png");
  spit(dir_ / "slices" / "s40.png", test::gray_png(2, 2, {0, 0, 0, 0}, 8));
  EXPECT_NE(error_of(dir_ / "slices", spacing).find("s40.png: byte 0: slice is 2x2; the first slice"),
            std::string::npos);
}

TEST_F(LabelImageFiles, EachBadInputIsLocated) {
  const std::string f = (dir_ / "bad.nii").string();
  auto nifti_error = [&](const NiftiHeader& h, std::string tail = "") {
    spit(f, h.bytes + (tail.empty() ? std::string(8, '\1') : tail));
    return error_of(f);
  };
  NiftiHeader h;
  h.bytes[344] = 'x';
  EXPECT_EQ(nifti_error(h), f + ": byte 344: magic is not 'n+1': not a NIfTI-1 file");
  h = NiftiHeader();
  h.put<std::int16_t>(70, 128);  // RGB
  EXPECT_EQ(nifti_error(h), f + ": byte 70: datatype 128 is not supported for labels (uint8, int8, int16, uint16, "
                                "int32, uint32, float32, float64)");
  h = NiftiHeader();
  h.put<float>(84, 0.0f);
  EXPECT_EQ(nifti_error(h), f + ": byte 84: pixdim[2] (voxel spacing) is 0; it must be finite and positive");
  h.put<float>(84, -1.0f);
  EXPECT_EQ(nifti_error(h), f + ": byte 84: pixdim[2] (voxel spacing) is -1; it must be finite and positive");
  h.put<float>(84, std::nanf(""));
  EXPECT_EQ(nifti_error(h), f + ": byte 84: pixdim[2] (voxel spacing) is nan; it must be finite and positive");
  h = NiftiHeader();
  EXPECT_EQ(nifti_error(h, std::string(3, '\1')), f + ": byte 355: voxel data ends early: 3 bytes for 8 voxels of 1 byte");
  h.put<std::int16_t>(70, 16);  // float labels must be integers
  h.put<std::int16_t>(72, 32);
  float values[8] = {0, 1, 2.5f, 0, 0, 0, 0, 0};
  EXPECT_EQ(nifti_error(h, std::string(reinterpret_cast<const char*>(values), 32)),
            f + ": byte 360: voxel 2 holds 2.5, not an integer label");

  // A truncated .nii.gz: the gzip stream ends early; the byte is where the file ends.
  write_nifti(dir_ / "whole.nii.gz", sample());
  const std::string gz = slurp(dir_ / "whole.nii.gz");
  spit(dir_ / "cut.nii.gz", gz.substr(0, gz.size() / 2));
  EXPECT_EQ(error_of(dir_ / "cut.nii.gz"), (dir_ / "cut.nii.gz").string() + ": byte " +
                                              std::to_string(gz.size() / 2) + ": gzip data ends early (truncated file?)");

  // NRRD: the header line.
  write_nrrd(dir_ / "good.nrrd", sample(), true);
  std::string nrrd = slurp(dir_ / "good.nrrd");
  const std::string n = (dir_ / "bad.nrrd").string();
  {
    std::string text = nrrd;
    const auto at = text.find("space directions:");
    const auto eol = text.find('\n', at);
    text.replace(at, eol - at, "space directions: (0,0,0) (0,1,0) (0,0,1)");
    spit(n, text);
    EXPECT_EQ(error_of(n), n + ":7: space directions: axis 1 has zero length");
    text.replace(at, text.find('\n', at) - at, "space directions: (nan,0,0) (0,1,0) (0,0,1)");
    spit(n, text);
    EXPECT_EQ(error_of(n), n + ":7: space directions: a vector is 'none' or not finite");
  }
  {
    std::string text = nrrd;
    text.replace(text.find("type: int"), 9, "type: block");
    spit(n, text);
    EXPECT_EQ(error_of(n), n + ":3: type 'block' is not supported for labels (8, 16, 32-bit integers, float, double)");
  }
  spit(n, "NRRD0004\ntype: int\ndimension: 3\nsizes: 2 2 2\nspacings: 1 -1 1\nencoding: raw\n\n");
  EXPECT_EQ(error_of(n), n + ":5: spacings: axis 2 has spacing -1; it must be finite and positive");
  spit(n, nrrd.substr(0, nrrd.size() - 20));
  EXPECT_NE(error_of(n).find("gzip data ends early (truncated file?)"), std::string::npos) << error_of(n);
  spit(n, "PK\3\4 a zip file");
  EXPECT_EQ(error_of(n), n + ":1: the first line does not start with 'NRRD': not a NRRD file");
  EXPECT_EQ(error_of(dir_ / "image.tiff"),
            (dir_ / "image.tiff").string() +
                ": unknown label image format (.nii, .nii.gz, .nrrd, a directory or glob of .png slices)");
}

}  // namespace
}  // namespace tactus::imaging
