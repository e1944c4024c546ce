// PNG writing through stb_image_write: a valid file, and clear errors for what cannot be written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "core/png.hpp"

namespace tactus::png {
namespace {

namespace fs = std::filesystem;

TEST(Png, WritesAnRgbImage) {
  const fs::path path = fs::temp_directory_path() / "tactus_png_test.png";
  fs::remove(path);
  std::vector<std::uint8_t> rgb(5 * 3 * 3, 0);
  rgb[0] = 255;  // top-left pixel red
  write_rgb(path, 5, 3, rgb);
  std::ifstream in(path, std::ios::binary);
  std::string head(24, '\0');
  in.read(head.data(), 24);
  ASSERT_TRUE(in);
  EXPECT_EQ(head.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(head.substr(12, 4), "IHDR");
  EXPECT_EQ(static_cast<unsigned char>(head[19]), 5u);  // width, big-endian
  EXPECT_EQ(static_cast<unsigned char>(head[23]), 3u);  // height
}

TEST(Png, RefusesWhatItCannotWrite) {
  const fs::path dir = fs::temp_directory_path();
  auto message = [](auto&& call) {
    try {
      call();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([&] { write_rgb(dir / "a.png", 0, 3, {}); }).find("each side must be 1 to"), std::string::npos);
  EXPECT_NE(message([&] { write_rgb(dir / "a.png", 2, 2, std::vector<std::uint8_t>(5)); }).find("does not hold 2x2"),
            std::string::npos);
  const std::string missing = message([&] { write_rgb(dir / "no_such_dir_tactus" / "a.png", 1, 1, {1, 2, 3}); });
  EXPECT_NE(missing.find("no_such_dir_tactus/a.png"), std::string::npos) << missing;
  EXPECT_NE(missing.find("could not write the PNG file"), std::string::npos) << missing;
}

}  // namespace
}  // namespace tactus::png
