// The force map picture, read back from its PNG: cells in report::viridis where the map says, axes
// with tick labels in mm, a colour bar from 0 N at the bottom to the strongest cell at the
// top, grey for cells never visited, and the nodules' outlines.
#include <gtest/gtest.h>
#include <stb/stb_image.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "report/force_map.hpp"

namespace tactus::runtime {
namespace {

namespace fs = std::filesystem;

/// 10 × 8 cells of 4 mm centred on the origin, the mean rising along x, one cell unvisited,
/// a 5 mm nodule at (2, 2) mm.
report::ForceMap synthetic_map() {
  report::ForceMap m;
  m.columns = 10;
  m.rows = 8;
  m.cell = 0.004;
  m.origin = Vec2(-0.018, -0.014);
  const std::size_t n = static_cast<std::size_t>(m.columns * m.rows);
  m.peak.assign(n, 0.0);
  m.mean.assign(n, 0.0);
  m.samples.assign(n, 10);
  for (int row = 0; row < m.rows; ++row)
    for (int column = 0; column < m.columns; ++column) {
      m.mean[m.index(column, row)] = 0.2 * column;  // 0 to 1.8 N
      m.peak[m.index(column, row)] = 0.25 * column;
    }
  m.samples[m.index(0, 0)] = 0;
  m.nodules.emplace_back(Vec2(0.002, 0.002), 0.005);
  return m;
}

struct Png {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  [[nodiscard]] raster::Rgb at(int x, int y) const {
    const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x));
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

Png read_png(const fs::path& path) {
  Png p;
  int channels = 0;
  unsigned char* pixels = stbi_load(path.string().c_str(), &p.width, &p.height, &channels, 3);
  if (!pixels) return p;
  p.rgb.assign(pixels, pixels + static_cast<std::size_t>(p.width) * static_cast<std::size_t>(p.height) * 3);
  stbi_image_free(pixels);
  return p;
}

double distance(const raster::Rgb& a, const raster::Rgb& b) {
  return std::hypot(double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2]);
}

/// Pixels darker than light grey in the rectangle: axis ink and text.
int ink(const Png& p, int x0, int y0, int x1, int y1) {
  int n = 0;
  for (int y = std::max(y0, 0); y < std::min(y1, p.height); ++y)
    for (int x = std::max(x0, 0); x < std::min(x1, p.width); ++x) {
      const raster::Rgb c = p.at(x, y);
      n += c[0] < 160 && c[1] < 160 && c[2] < 160;
    }
  return n;
}

TEST(ForceMapPicture, CellsAxesColourBarAndNodulesAsTheMapSays) {
  const report::ForceMap map = synthetic_map();
  const fs::path path = fs::temp_directory_path() / "tactus_force_map_test.png";
  fs::remove(path);
  const std::string legend = report::write_force_map_png(map, path);
  EXPECT_NE(legend.find("1.800 N"), std::string::npos) << legend;
  EXPECT_NE(legend.find("nodules"), std::string::npos) << legend;
  const Png png = read_png(path);
  const report::ForceMapLayout l = report::force_map_layout(map);
  ASSERT_EQ(png.width, l.width);
  ASSERT_EQ(png.height, l.height);
  EXPECT_DOUBLE_EQ(l.full_scale, 1.8);
  EXPECT_GE(std::max(l.plot_width, l.plot_height), 256);

  // Each cell's centre pixel (away from the nodule's outline) is report::viridis of its mean over 1.8 N;
  // +y is up, so row 0 is the bottom row of the plot.
  const auto centre = [&](int column, int row) {
    return std::pair{l.plot_left + column * l.cell_pixels + l.cell_pixels / 2,
                     l.plot_top + (map.rows - 1 - row) * l.cell_pixels + l.cell_pixels / 2};
  };
  for (const auto& [column, row] : {std::pair{9, 0}, std::pair{5, 7}, std::pair{1, 3}}) {
    const auto [x, y] = centre(column, row);
    const auto expected = report::viridis(map.mean[map.index(column, row)] / 1.8);
    EXPECT_LT(distance(png.at(x, y), {expected[0], expected[1], expected[2]}), 2.0) << column << ", " << row;
  }
  const auto [ux, uy] = centre(0, 0);
  EXPECT_EQ(png.at(ux, uy), (raster::Rgb{128, 128, 128})) << "an unvisited cell is grey";

  // The colour bar runs from report::viridis(0) at its bottom to report::viridis(1) at its top.
  const int bar_x = l.bar_left + l.bar_width / 2;
  const auto low = report::viridis(0.0), high = report::viridis(1.0);
  EXPECT_LT(distance(png.at(bar_x, l.bar_top + l.bar_height - 1), {low[0], low[1], low[2]}), 6.0);
  EXPECT_LT(distance(png.at(bar_x, l.bar_top), {high[0], high[1], high[2]}), 6.0);

  // The nodule's dashed outline: white pixels on the circle of 5 mm around (2, 2) mm, inside
  // a cell whose colour is not white.
  const double mm = l.plot_width / (1e3 * map.cell * map.columns);  // pixels per mm
  const double cx = l.plot_left + (2.0 - (-20.0)) * mm, cy = l.plot_top + (16.0 - 2.0) * mm;
  int white = 0;
  for (int k = 0; k < 72; ++k) {
    const double a = 2.0 * 3.14159265358979 * (k + 0.5) / 72.0;
    const raster::Rgb c = png.at(static_cast<int>(std::lround(cx + 5.0 * mm * std::cos(a))),
                                 static_cast<int>(std::lround(cy - 5.0 * mm * std::sin(a))));
    white += c[0] > 200 && c[1] > 200 && c[2] > 200;
  }
  EXPECT_GT(white, 20) << "the outline is dashed: about half of the circle";
  EXPECT_LT(white, 60);

  if (!raster::text_available()) GTEST_SKIP() << "no font: the labels are not drawn";
  // Tick labels under the plot and left of it, the colour bar's labels right of it.
  const int bottom = l.plot_top + l.plot_height;
  EXPECT_GT(ink(png, l.plot_left - 10, bottom + 6, l.plot_left + l.plot_width + 10, bottom + 22), 80);
  EXPECT_GT(ink(png, 0, l.plot_top, l.plot_left - 8, bottom), 60);
  EXPECT_GT(ink(png, l.bar_left + l.bar_width + 6, l.bar_top - 8, l.width, l.bar_top + l.bar_height + 8), 40);
  // The axis title.
  EXPECT_GT(ink(png, l.plot_left, bottom + 24, l.plot_left + l.plot_width, l.height), 20);
}

TEST(ForceMapPicture, AnUnwritablePathIsAnInputError) {
  EXPECT_THROW(report::write_force_map_png(synthetic_map(), fs::temp_directory_path() / "no_such_folder_tactus" / "m.png"),
               InputError);
}

}  // namespace
}  // namespace tactus::runtime
