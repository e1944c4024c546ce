#pragma once
// A 3D label image (one integer label per voxel, 0 = background) with its placement in
// the world, and the readers and writers of the formats it comes in:
//   .nii .nii.gz     NIfTI-1, single file (magic "n+1"); uint8, int8, int16, uint16, int32,
//                    uint32, float32, float64 voxels; placement from the sform, else the
//                    qform, else pixdim alone; units from xyzt_units (none given: mm)
//   .nrrd            NRRD, raw or gzip, attached or detached ("data file"), either byte order
//   directory, glob  a stack of grayscale PNG slices (8 or 16 bit), sorted by name; the
//                    spacing comes from the caller
// Everything is converted to SI metres and to the world axes of the file (NIfTI's RAS;
// NRRD's "space", with LPS turned into RAS so that both formats of one image agree).
// Readers throw InputError naming the file and the field (text formats: the line; binary:
// the byte offset) and the reason.
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/math.hpp"

namespace tactus::imaging {

struct LabelImage {
  std::array<std::size_t, 3> size{};  ///< voxels along i, j, k
  Vec3 spacing = Vec3::Ones();        ///< voxel edge along i, j, k [m]
  /// Unit world directions of the i, j and k axes (columns); need not be orthogonal.
  Mat3 direction = Mat3::Identity();
  Vec3 origin = Vec3::Zero();  ///< world position of voxel (0, 0, 0)'s centre [m]
  std::vector<std::int32_t> labels;  ///< i fastest, then j, then k
  std::string source;                ///< the file it came from, for messages

  [[nodiscard]] std::size_t voxel_count() const { return size[0] * size[1] * size[2]; }
  [[nodiscard]] std::size_t index(std::size_t i, std::size_t j, std::size_t k) const {
    return i + size[0] * (j + size[1] * k);
  }
  /// World position [m] of the continuous voxel coordinates (i, j, k).
  [[nodiscard]] Vec3 world(const Vec3& ijk) const {
    return origin + direction * ijk.cwiseProduct(spacing);
  }
  /// Volume of one voxel [m³] (the parallelepiped of the three axes).
  [[nodiscard]] double voxel_volume() const {
    return std::abs((direction * spacing.asDiagonal()).determinant());
  }
};

struct LabelVoxels {
  std::int32_t label = 0;
  std::size_t voxels = 0;
};
/// Nonzero labels in increasing order with their voxel counts.
std::vector<LabelVoxels> count_labels(const LabelImage& image);

/// By name: .nii, .nii.gz, .nrrd; a directory or a name with '*' or '?' is a PNG stack,
/// which needs `png_spacing` [m].
LabelImage read_label_image(const std::filesystem::path& path, const std::optional<Vec3>& png_spacing = {});
LabelImage read_nifti(const std::filesystem::path& path);
LabelImage read_nrrd(const std::filesystem::path& path);
/// `pattern`: a directory (every *.png in it) or a glob.
LabelImage read_png_stack(const std::filesystem::path& pattern, const Vec3& spacing);

/// Writers (metres written as mm). NIfTI: int16 voxels when the labels fit, else int32;
/// gzip when the name ends in .gz; the placement goes into the sform and, when the
/// direction is a rotation (possibly mirrored), the qform too.
void write_nifti(const std::filesystem::path& path, const LabelImage& image);
/// NRRD: int32 voxels in RAS space; gzip encoding when `gzip`.
void write_nrrd(const std::filesystem::path& path, const LabelImage& image, bool gzip = true);

}  // namespace tactus::imaging
