// CPU drawing for the pictures Tactus writes: shapes land where asked and clip at the edges,
// text has ink where it is written and a width that grows with its length.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "core/raster.hpp"

namespace tactus::raster {
namespace {

constexpr Rgb kWhite{255, 255, 255}, kBlack{0, 0, 0}, kRed{255, 0, 0};

/// Pixels of `image` in [x0, x1) × [y0, y1) that are not white.
int ink(const Image& image, int x0, int y0, int x1, int y1) {
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) n += image.at(x, y) != kWhite;
  return n;
}

TEST(Raster, RectanglesFillExactlyTheirPixelsAndClip) {
  Image image(20, 10, kWhite);
  fill_rect(image, 2, 3, 5, 7, kRed);
  EXPECT_EQ(ink(image, 0, 0, 20, 10), 3 * 4);
  EXPECT_EQ(image.at(2, 3), kRed);
  EXPECT_EQ(image.at(4, 6), kRed);
  EXPECT_EQ(image.at(5, 6), kWhite);
  fill_rect(image, -5, -5, 100, 1, kBlack);  // clipped, no write outside
  EXPECT_EQ(ink(image, 0, 0, 20, 1), 20);
  EXPECT_EQ(image.rgb.size(), 20u * 10u * 3u);
  Image blended(1, 1, {0, 0, 0});
  blended.blend(0, 0, {200, 100, 50}, 0.5);
  EXPECT_EQ(blended.at(0, 0), (Rgb{100, 50, 25}));
}

TEST(Raster, LinesPassThroughTheirPoints) {
  Image image(40, 40, kWhite);
  draw_line(image, 5, 5, 30, 20, kBlack, 2.0);
  EXPECT_EQ(image.at(5, 5), kBlack);
  EXPECT_EQ(image.at(30, 20), kBlack);
  EXPECT_NE(image.at(17, 12), kWhite);  // the midpoint (17.5, 12.5)
  EXPECT_EQ(image.at(30, 5), kWhite);
  // Non-finite coordinates draw nothing rather than looping or writing out of bounds.
  const int before = ink(image, 0, 0, 40, 40);
  draw_line(image, 0, 0, std::numeric_limits<double>::infinity(), 5, kRed);
  draw_line(image, std::numeric_limits<double>::quiet_NaN(), 5, 3, 8, kRed);
  EXPECT_EQ(ink(image, 0, 0, 40, 40), before);
}

TEST(Raster, TicksStepByOneTwoOrFiveAndWriteTheirDecimals) {
  EXPECT_DOUBLE_EQ(nice_step(19.1, 4.0), 5.0);
  EXPECT_DOUBLE_EQ(nice_step(0.711, 4.0), 0.2);
  EXPECT_DOUBLE_EQ(nice_step(64.0, 5.0), 20.0);
  EXPECT_EQ(tick_label(15.0, 5.0), "15");
  EXPECT_EQ(tick_label(0.4, 0.2), "0.4");
  EXPECT_EQ(tick_label(-1e-17, 0.2), "0.0");  // not "-0.0"
}

TEST(Raster, TextHasInkWhereItIsWritten) {
  if (!text_available()) GTEST_SKIP() << "no font (install fonts-dejavu-core or set TACTUS_FONT)";
  Image image(200, 40, kWhite);
  const int width = draw_text(image, 10, 8, "x [mm] 1.25 N", 16.0, kBlack);
  EXPECT_EQ(width, text_width("x [mm] 1.25 N", 16.0));
  EXPECT_GT(width, 60);
  EXPECT_LT(width, 150);
  EXPECT_GT(ink(image, 10, 8, 10 + width, 8 + 17), 60);
  EXPECT_EQ(ink(image, 0, 0, 200, 6), 0);               // nothing above the line
  EXPECT_EQ(ink(image, 10 + width + 2, 0, 200, 40), 0);  // nor after it
  EXPECT_GT(text_width("pressure [kPa]", 15.0), text_width("kPa", 15.0));
  // Non-ASCII (µ, ×) and malformed UTF-8 are drawn or replaced, never read past the end.
  EXPECT_GT(draw_text(image, 0, 20, "5 µs × 2", 12.0, kBlack), 0);
  EXPECT_GE(draw_text(image, 0, 20, std::string("\xE2\x82", 2), 12.0, kBlack), 0);
  EXPECT_EQ(draw_text(image, 0, 20, "", 12.0, kBlack), 0);
}

}  // namespace
}  // namespace tactus::raster
