#include "core/raster.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <mutex>
#include <optional>
#include <string>

#define STB_TRUETYPE_IMPLEMENTATION
#define STBTT_STATIC
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wpedantic"
#endif
#include <stb/stb_truetype.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace tactus::raster {
namespace {

/// The TrueType file and stb's view of it, loaded once.
struct Font {
  std::vector<unsigned char> data;
  stbtt_fontinfo info{};
};

const Font* font() {
  static std::optional<Font> loaded;
  static std::once_flag once;
  std::call_once(once, [] {
    std::vector<std::string> candidates;
    if (const char* chosen = std::getenv("TACTUS_FONT"); chosen && *chosen) candidates.emplace_back(chosen);
    candidates.emplace_back("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf");
    for (const std::string& path : candidates) {
      std::ifstream in(path, std::ios::binary);
      if (!in) continue;
      Font f;
      f.data.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
      const int offset = stbtt_GetFontOffsetForIndex(f.data.data(), 0);
      if (offset < 0 || !stbtt_InitFont(&f.info, f.data.data(), offset)) continue;
      loaded = std::move(f);
      // stbtt_InitFont kept a pointer into the vector that was moved: point it at the copy.
      stbtt_InitFont(&loaded->info, loaded->data.data(), offset);
      break;
    }
  });
  return loaded ? &*loaded : nullptr;
}

/// The next code point of UTF-8 `text` from `i` (advanced); U+FFFD for a malformed byte.
int next_code_point(std::string_view text, std::size_t& i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char b = byte(i++);
  int extra = 0, cp = 0;
  if (b < 0x80) return b;
  if ((b & 0xE0) == 0xC0) extra = 1, cp = b & 0x1F;
  else if ((b & 0xF0) == 0xE0) extra = 2, cp = b & 0x0F;
  else if ((b & 0xF8) == 0xF0) extra = 3, cp = b & 0x07;
  else return 0xFFFD;
  for (int k = 0; k < extra; ++k) {
    if (i >= text.size() || (byte(i) & 0xC0) != 0x80) return 0xFFFD;
    cp = (cp << 6) | (byte(i++) & 0x3F);
  }
  return cp;
}

/// Lays out `text` glyph by glyph; `glyph(code point, pen x [px])` for each; returns the width.
template <class Glyph>
int layout(const Font& f, std::string_view text, float scale, Glyph&& glyph) {
  float pen = 0.0F;
  int previous = 0;
  for (std::size_t i = 0; i < text.size();) {
    const int cp = next_code_point(text, i);
    if (previous) pen += scale * static_cast<float>(stbtt_GetCodepointKernAdvance(&f.info, previous, cp));
    glyph(cp, pen);
    int advance = 0, bearing = 0;
    stbtt_GetCodepointHMetrics(&f.info, cp, &advance, &bearing);
    pen += scale * static_cast<float>(advance);
    previous = cp;
  }
  return static_cast<int>(std::ceil(pen));
}

}  // namespace

Image::Image(int w, int h, Rgb fill) : width(std::max(0, w)), height(std::max(0, h)) {
  rgb.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  for (std::size_t i = 0; i < rgb.size(); i += 3) std::copy(fill.begin(), fill.end(), rgb.begin() + static_cast<std::ptrdiff_t>(i));
}

Rgb Image::at(int x, int y) const {
  if (!contains(x, y)) return {0, 0, 0};
  const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x));
  return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

void Image::blend(int x, int y, Rgb colour, double alpha) {
  if (!contains(x, y) || !(alpha > 0.0)) return;
  alpha = std::min(alpha, 1.0);
  const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x));
  for (std::size_t k = 0; k < 3; ++k)
    rgb[i + k] = static_cast<std::uint8_t>(std::lround((1.0 - alpha) * rgb[i + k] + alpha * colour[k]));
}

void fill_rect(Image& image, int x0, int y0, int x1, int y1, Rgb colour) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0);
  x1 = std::min(x1, image.width), y1 = std::min(y1, image.height);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) image.blend(x, y, colour);
}

void stroke_rect(Image& image, int x0, int y0, int x1, int y1, Rgb colour) {
  fill_rect(image, x0, y0, x1, y0 + 1, colour);
  fill_rect(image, x0, y1 - 1, x1, y1, colour);
  fill_rect(image, x0, y0, x0 + 1, y1, colour);
  fill_rect(image, x1 - 1, y0, x1, y1, colour);
}

void draw_line(Image& image, double x0, double y0, double x1, double y1, Rgb colour, double width) {
  if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1)) return;
  const double half = 0.5 * std::max(width, 0.5);
  const double dx = x1 - x0, dy = y1 - y0, length2 = dx * dx + dy * dy;
  const int xa = static_cast<int>(std::floor(std::min(x0, x1) - half - 1)), xb = static_cast<int>(std::ceil(std::max(x0, x1) + half + 1));
  const int ya = static_cast<int>(std::floor(std::min(y0, y1) - half - 1)), yb = static_cast<int>(std::ceil(std::max(y0, y1) + half + 1));
  for (int y = std::max(ya, 0); y <= std::min(yb, image.height - 1); ++y)
    for (int x = std::max(xa, 0); x <= std::min(xb, image.width - 1); ++x) {
      // Coverage from the pixel centre's distance to the segment, one pixel of ramp.
      const double s = length2 > 0.0 ? std::clamp(((x - x0) * dx + (y - y0) * dy) / length2, 0.0, 1.0) : 0.0;
      const double distance = std::hypot(x - (x0 + s * dx), y - (y0 + s * dy));
      image.blend(x, y, colour, std::clamp(half + 0.5 - distance, 0.0, 1.0));
    }
}

bool text_available() { return font() != nullptr; }

int text_width(std::string_view text, double size) {
  const Font* f = font();
  if (!f || !(size > 0.0)) return 0;
  const float scale = stbtt_ScaleForPixelHeight(&f->info, static_cast<float>(size));
  return layout(*f, text, scale, [](int, float) {});
}

int draw_text(Image& image, int x, int y, std::string_view text, double size, Rgb colour) {
  const Font* f = font();
  if (!f || !(size > 0.0)) return 0;
  const float scale = stbtt_ScaleForPixelHeight(&f->info, static_cast<float>(size));
  int ascent = 0, descent = 0, gap = 0;
  stbtt_GetFontVMetrics(&f->info, &ascent, &descent, &gap);
  const int baseline = y + static_cast<int>(std::lround(scale * static_cast<float>(ascent)));
  std::vector<unsigned char> bitmap;
  return layout(*f, text, scale, [&](int cp, float pen) {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    const float shift = pen - std::floor(pen);
    stbtt_GetCodepointBitmapBoxSubpixel(&f->info, cp, scale, scale, shift, 0.0F, &x0, &y0, &x1, &y1);
    const int w = x1 - x0, h = y1 - y0;
    if (w <= 0 || h <= 0) return;
    bitmap.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
    stbtt_MakeCodepointBitmapSubpixel(&f->info, bitmap.data(), w, h, w, scale, scale, shift, 0.0F, cp);
    const int left = x + static_cast<int>(std::floor(pen)) + x0, top = baseline + y0;
    for (int row = 0; row < h; ++row)
      for (int column = 0; column < w; ++column)
        image.blend(left + column, top + row, colour, bitmap[static_cast<std::size_t>(row * w + column)] / 255.0);
  });
}

double nice_step(double range, double count) {
  const double raw = range / count;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0})
    if (m * decade >= raw) return m * decade;
  return 10.0 * decade;
}

std::string tick_label(double value, double step) {
  const int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
  // A value a rounding error from zero is written "0", not "-0".
  return fmt::format("{:.{}f}", std::abs(value) < 0.5 * step ? 0.0 : value, decimals);
}

}  // namespace tactus::raster
