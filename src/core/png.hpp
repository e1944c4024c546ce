#pragma once
// PNG images through stb_image_write (Debian libstb-dev): force maps, snapshots.
#include <cstdint>
#include <filesystem>
#include <vector>

namespace tactus::png {

/// Writes an 8-bit RGB image, rows top to bottom, 3 bytes per pixel. InputError naming
/// the file for bad dimensions, a pixel buffer of the wrong size or a file that cannot be
/// written.
void write_rgb(const std::filesystem::path& path, int width, int height, const std::vector<std::uint8_t>& rgb);

}  // namespace tactus::png
