#pragma once
// Drawing on 8-bit RGB images on the CPU: rectangles, lines, circles and text, for the
// pictures Tactus writes (force maps, the labels over snapshots). Text is DejaVu Sans
// (Debian fonts-dejavu-core) rasterized by stb_truetype (libstb-dev).
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace tactus::raster {

using Rgb = std::array<std::uint8_t, 3>;

/// Rows top to bottom, 3 bytes per pixel (the layout png::write_rgb takes).
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;

  Image() = default;
  Image(int width, int height, Rgb fill);
  [[nodiscard]] bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
  [[nodiscard]] Rgb at(int x, int y) const;
  /// Mixes `colour` over the pixel with weight `alpha` in [0, 1]; outside the image: nothing.
  void blend(int x, int y, Rgb colour, double alpha = 1.0);
};

/// Fills the pixels x0 ≤ x < x1, y0 ≤ y < y1 (clipped to the image).
void fill_rect(Image& image, int x0, int y0, int x1, int y1, Rgb colour);
/// The outline of that rectangle, one pixel wide.
void stroke_rect(Image& image, int x0, int y0, int x1, int y1, Rgb colour);
/// An anti-aliased segment of the given width [px] between pixel centres.
void draw_line(Image& image, double x0, double y0, double x1, double y1, Rgb colour, double width = 1.0);

/// Whether a font was found, so that text can be drawn (fonts-dejavu-core; the environment
/// variable TACTUS_FONT names another TrueType file).
bool text_available();
/// Draws UTF-8 `text` with its top-left corner at (x, y), `size` pixels from ascender to
/// descender; returns its width [px]. Without a font it draws nothing and returns 0.
int draw_text(Image& image, int x, int y, std::string_view text, double size, Rgb colour);
/// The width [px] `text` would take.
int text_width(std::string_view text, double size);

/// An axis' tick step: 1, 2 or 5 × 10^k, giving about `count` intervals over `range` (> 0).
double nice_step(double range, double count);
/// A tick's value with as many decimals as its step needs ("0", "2.5", "20").
std::string tick_label(double value, double step);

}  // namespace tactus::raster
