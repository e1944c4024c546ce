// Label images as a stack of grayscale PNG slices (one file per k, sorted by name).
#include <glob.h>

#include <algorithm>
#include <cstring>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/input_file.hpp"
#include "imaging/label_image.hpp"
#include "imaging/voxel_data.hpp"

// Static: another library may carry its own copy of stb_image.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_NO_STDIO
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
#include <stb/stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace tactus::imaging {
namespace {

std::vector<std::filesystem::path> slice_files(const std::filesystem::path& pattern) {
  std::vector<std::filesystem::path> files;
  if (std::filesystem::is_directory(pattern)) {
    for (const auto& entry : std::filesystem::directory_iterator(pattern)) {
      std::string ext = entry.path().extension().string();
      for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (entry.is_regular_file() && ext == ".png") files.push_back(entry.path());
    }
  } else {
    glob_t g{};
    if (::glob(pattern.c_str(), 0, nullptr, &g) == 0)
      for (std::size_t i = 0; i < g.gl_pathc; ++i) files.emplace_back(g.gl_pathv[i]);
    globfree(&g);
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InputError(SourceLocation{pattern.string(), {}, {}, {}}, "no .png slices found");
  return files;
}

}  // namespace

LabelImage read_png_stack(const std::filesystem::path& pattern, const Vec3& spacing) {
  const auto files = slice_files(pattern);
  LabelImage image;
  image.source = pattern.string();
  image.spacing = spacing;
  image.size[2] = files.size();
  for (std::size_t k = 0; k < files.size(); ++k) {
    const std::string file = files[k].string();
    const std::string bytes = read_input_file(files[k]);
    const auto* raw = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int length = static_cast<int>(std::min<std::size_t>(bytes.size(), 0x7fffffff));
    int w = 0, h = 0, channels = 0;
    if (!stbi_info_from_memory(raw, length, &w, &h, &channels))
      throw InputError(SourceLocation{file, {}, {}, 0}, fmt::format("not a readable PNG: {}", stbi_failure_reason()));
    if (channels != 1)
      throw InputError(SourceLocation{file, {}, {}, 0},
                       fmt::format("a label slice must be one grayscale channel; this PNG has {}", channels));
    if (k == 0) {
      image.size[0] = static_cast<std::size_t>(w);
      image.size[1] = static_cast<std::size_t>(h);
      image.labels.resize(image.voxel_count());
    } else if (static_cast<std::size_t>(w) != image.size[0] || static_cast<std::size_t>(h) != image.size[1]) {
      throw InputError(SourceLocation{file, {}, {}, 0},
                       fmt::format("slice is {}x{}; the first slice ({}) is {}x{}", w, h, files[0].string(),
                                   image.size[0], image.size[1]));
    }
    const std::size_t plane = image.size[0] * image.size[1];
    int got = 0;
    if (stbi_is_16_bit_from_memory(raw, length)) {
      stbi_us* px = stbi_load_16_from_memory(raw, length, &w, &h, &got, 1);
      if (!px)
        throw InputError(SourceLocation{file, {}, {}, 0}, fmt::format("cannot decode: {}", stbi_failure_reason()));
      std::copy(px, px + plane, image.labels.begin() + static_cast<std::ptrdiff_t>(k * plane));
      stbi_image_free(px);
    } else {
      stbi_uc* px = stbi_load_from_memory(raw, length, &w, &h, &got, 1);
      if (!px)
        throw InputError(SourceLocation{file, {}, {}, 0}, fmt::format("cannot decode: {}", stbi_failure_reason()));
      std::copy(px, px + plane, image.labels.begin() + static_cast<std::ptrdiff_t>(k * plane));
      stbi_image_free(px);
    }
  }
  detail::check_geometry(image, "--spacing");
  return image;
}

}  // namespace tactus::imaging
