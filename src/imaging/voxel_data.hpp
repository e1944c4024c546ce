#pragma once
// Internal to src/imaging: gzip, and turning a file's voxel bytes into labels.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "imaging/label_image.hpp"

namespace tactus::imaging::detail {

/// The whole gzip stream in `data`, which starts at byte `offset` of `file`. A truncated
/// or corrupt stream, or one that inflates to more than max_input_bytes(), is an
/// InputError at the byte where it fails.
std::string gunzip(std::string_view data, const std::string& file, std::uint64_t offset);
std::string gzip(std::string_view data);

enum class VoxelType { u8, i8, i16, u16, i32, u32, f32, f64 };
std::size_t voxel_bytes(VoxelType type);

/// Decodes `count` voxels of `type` from `data` (big endian when `big_endian`). A value
/// that is not an integer label (a fraction, NaN, beyond int32) is an InputError at its
/// byte, `data_offset` being where `data` starts in the file (or the inflated stream).
std::vector<std::int32_t> decode_labels(std::string_view data, VoxelType type, bool big_endian, std::size_t count,
                                        const std::string& file, std::uint64_t data_offset,
                                        double slope = 1.0, double intercept = 0.0);

/// The readers' parsers, from memory (the fuzz target calls them). `gz`: the data is a gzip
/// stream. A NRRD's detached data file is looked up beside `path`.
LabelImage parse_nifti(std::string data, const std::string& file, bool gz);
LabelImage parse_nrrd(std::string_view data, const std::filesystem::path& path);

/// Refuses a placement that cannot be meshed: a size of zero, a spacing that is not
/// finite and positive, axes that are not independent. `where` names the field.
void check_geometry(const LabelImage& image, const std::string& where_spacing);

}  // namespace tactus::imaging::detail
