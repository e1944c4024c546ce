#include "core/png.hpp"

#include <string>

#include "core/error.hpp"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wpedantic"
#endif
#include <stb/stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace tactus::png {

void write_rgb(const std::filesystem::path& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
  const SourceLocation where{path.string(), {}, {}, {}};
  // stb computes sizes in int: keep the image far below that.
  constexpr int max_side = 1 << 14;
  if (width <= 0 || height <= 0 || width > max_side || height > max_side)
    throw InputError(where, "cannot write a " + std::to_string(width) + "x" + std::to_string(height) +
                                " image (each side must be 1 to " + std::to_string(max_side) + " pixels)");
  if (rgb.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3)
    throw InputError(where, "the pixel buffer does not hold " + std::to_string(width) + "x" + std::to_string(height) +
                                " RGB pixels");
  if (stbi_write_png(path.string().c_str(), width, height, 3, rgb.data(), width * 3) == 0)
    throw InputError(where, "could not write the PNG file (missing folder, no permission or disk full)");
}

}  // namespace tactus::png
