#pragma once
// Property images on disk: one HDF5 file per object (docs/property-images.md), readable
// with h5py or HDFView. Written to a temporary file and moved into place, so an interrupted
// save never leaves half a file where the last good one was.
#include <cstdint>
#include <filesystem>
#include <optional>

#include "property_images/property_images.hpp"

namespace tactus::property_images {

void write_property_images(const std::filesystem::path& path, const PropertyImages& images);

/// Reads and checks a file: format and version, image sizes against the box and pixel,
/// depths non-negative, every pixel's material in range (an error names the view and pixel),
/// and, when `mesh_hash` is given, that the file was made for that mesh. Every problem is an
/// InputError naming the file and the reason.
PropertyImages read_property_images(const std::filesystem::path& path,
                                    std::optional<std::uint64_t> mesh_hash = std::nullopt);

}  // namespace tactus::property_images
