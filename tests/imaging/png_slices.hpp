#pragma once
// Grayscale PNG slices (8 or 16 bit) written with zlib alone, for the PNG stack reader's tests.
#include <zlib.h>

#include <cstdint>
#include <string>
#include <vector>

namespace tactus::imaging::test {

/// A minimal grayscale PNG (8 or 16 bit), so that the test needs no PNG library.
inline std::string gray_png(int w, int h, const std::vector<int>& values, int bits) {
  auto be32 = [](std::uint32_t v) {
    return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8),
                       static_cast<char>(v)};
  };
  auto chunk = [&](const std::string& type, const std::string& data) {
    const std::string body = type + data;
    const auto crc = static_cast<std::uint32_t>(
        crc32(0, reinterpret_cast<const Bytef*>(body.data()), static_cast<uInt>(body.size())));
    return be32(static_cast<std::uint32_t>(data.size())) + body + be32(crc);
  };
  std::string raw;
  for (int y = 0; y < h; ++y) {
    raw.push_back('\0');
    for (int x = 0; x < w; ++x) {
      const int v = values[static_cast<std::size_t>(y * w + x)];
      if (bits == 16) raw.push_back(static_cast<char>(v >> 8));
      raw.push_back(static_cast<char>(v & 0xff));
    }
  }
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  std::string z(size, '\0');
  compress(reinterpret_cast<Bytef*>(z.data()), &size, reinterpret_cast<const Bytef*>(raw.data()),
           static_cast<uLong>(raw.size()));
  z.resize(size);
  std::string ihdr = be32(static_cast<std::uint32_t>(w)) + be32(static_cast<std::uint32_t>(h));
  ihdr.append({static_cast<char>(bits), 0, 0, 0, 0});
  std::string png("\x89PNG\r\n\x1a\n", 8);
  png.append(chunk("IHDR", ihdr));
  png.append(chunk("IDAT", z));
  png.append(chunk("IEND", ""));
  return png;
}

}  // namespace tactus::imaging::test
