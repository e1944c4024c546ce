#include "fitting/plot.hpp"

#include <algorithm>
#include <cmath>

#include "core/png.hpp"
#include "core/raster.hpp"

namespace tactus::fitting {
namespace {

constexpr int kWidth = 720, kHeight = 480;
constexpr int kLeft = 80, kRight = 24, kTop = 40, kBottom = 56;
constexpr double kLabelSize = 14.0;
constexpr raster::Rgb kPaper{255, 255, 255}, kInk{30, 30, 30}, kData{31, 119, 180}, kFit{214, 39, 40};

/// Axis range [lo, hi] padded to whole ticks.
struct Axis {
  double lo = 0.0, hi = 1.0, step = 1.0;
};

Axis axis_of(const std::vector<double>& a, const std::vector<double>& b, double scale) {
  double lo = 0.0, hi = 0.0;  // the origin always shows: a curve from rest
  for (const auto* v : {&a, &b})
    for (double x : *v) {
      lo = std::min(lo, x * scale);
      hi = std::max(hi, x * scale);
    }
  if (hi <= lo) hi = lo + 1.0;
  Axis ax;
  ax.step = raster::nice_step(hi - lo, 5.0);
  ax.lo = std::floor(lo / ax.step + 1e-9) * ax.step;
  ax.hi = std::ceil(hi / ax.step - 1e-9) * ax.step;
  return ax;
}

}  // namespace

void write_plot(const std::filesystem::path& path, const CurvePlot& p) {
  raster::Image image(kWidth, kHeight, kPaper);
  const int w = kWidth - kLeft - kRight, h = kHeight - kTop - kBottom, bottom = kTop + h;
  const Axis ax = axis_of(p.x, p.x, p.x_scale), ay = axis_of(p.data, p.fit, p.y_scale);
  auto px = [&](double x) { return kLeft + (x * p.x_scale - ax.lo) / (ax.hi - ax.lo) * w; };
  auto py = [&](double y) { return kTop + (ay.hi - y * p.y_scale) / (ay.hi - ay.lo) * h; };

  for (double v = ax.lo; v <= ax.hi + 1e-9 * ax.step; v += ax.step) {
    const double x = kLeft + (v - ax.lo) / (ax.hi - ax.lo) * w;
    raster::draw_line(image, x, bottom, x, bottom + 5, kInk);
    const std::string label = raster::tick_label(v, ax.step);
    raster::draw_text(image, static_cast<int>(x) - raster::text_width(label, kLabelSize) / 2, bottom + 7, label,
                      kLabelSize, kInk);
  }
  for (double v = ay.lo; v <= ay.hi + 1e-9 * ay.step; v += ay.step) {
    const double y = kTop + (ay.hi - v) / (ay.hi - ay.lo) * h;
    raster::draw_line(image, kLeft - 6, y, kLeft - 1, y, kInk);
    const std::string label = raster::tick_label(v, ay.step);
    raster::draw_text(image, kLeft - 9 - raster::text_width(label, kLabelSize),
                      static_cast<int>(y) - static_cast<int>(kLabelSize / 2), label, kLabelSize, kInk);
  }
  raster::stroke_rect(image, kLeft - 1, kTop - 1, kLeft + w + 1, bottom + 1, kInk);
  raster::draw_text(image, kLeft + w / 2 - raster::text_width(p.x_label, kLabelSize) / 2, bottom + 28, p.x_label,
                    kLabelSize, kInk);
  raster::draw_text(image, 6, 14, p.y_label, kLabelSize, kInk);
  raster::draw_text(image, kLeft + w / 2 - raster::text_width(p.title, kLabelSize) / 2, 14, p.title, kLabelSize, kInk);

  // The fit as a line, the data as small squares over it.
  for (std::size_t i = 1; i < p.x.size() && i < p.fit.size(); ++i)
    raster::draw_line(image, px(p.x[i - 1]), py(p.fit[i - 1]), px(p.x[i]), py(p.fit[i]), kFit, 2.0);
  for (std::size_t i = 0; i < p.x.size() && i < p.data.size(); ++i) {
    const int x = static_cast<int>(std::lround(px(p.x[i]))), y = static_cast<int>(std::lround(py(p.data[i])));
    raster::stroke_rect(image, x - 3, y - 3, x + 4, y + 4, kData);
  }

  // Legend, top left inside the frame.
  const int lx = kLeft + 12, ly = kTop + 12;
  raster::stroke_rect(image, lx - 3, ly + 4, lx + 4, ly + 11, kData);
  raster::draw_text(image, lx + 16, ly, p.data_label, kLabelSize, kInk);
  raster::draw_line(image, lx - 6, ly + 28, lx + 8, ly + 28, kFit, 2.0);
  raster::draw_text(image, lx + 16, ly + 20, p.fit_label, kLabelSize, kInk);
  png::write_rgb(path, image.width, image.height, image.rgb);
}

}  // namespace tactus::fitting
