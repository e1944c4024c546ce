#include "report/latency_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/png.hpp"
#include "core/raster.hpp"
#include "report/palette.hpp"

namespace tactus::report {
namespace {

constexpr int kWidth = 760, kPanel = 170, kLeft = 70, kRight = 24, kTop = 80, kGap = 44, kBottom = 52;
constexpr double kText = 13.0;
constexpr int kBinsPerDecade = 10;
constexpr raster::Rgb kGrid{215, 215, 215}, kCompute{31, 119, 180}, kPeriod{255, 127, 14}, kNominal{90, 90, 90};

/// Three significant digits in s, ms or µs.
std::string duration_label(double seconds) {
  if (seconds >= 1.0) return fmt::format("{:.3g} s", seconds);
  if (seconds >= 1e-3) return fmt::format("{:.3g} ms", seconds * 1e3);
  return fmt::format("{:.3g} µs", seconds * 1e6);
}

/// The bins: kBinsPerDecade a decade, centred on the decades (so that a round rate's period
/// falls in the middle of a bin), from 10^lo to 10^hi seconds.
int bin_count(int lo, int hi) { return (hi - lo) * kBinsPerDecade + 1; }
double bin_edge(int lo, int b) { return lo + (static_cast<double>(b) - 0.5) / kBinsPerDecade; }  ///< log10 [s]

/// Per bin: the share of h's values in it [%]; what lies beyond the axis goes to the end bins.
std::vector<double> shares(const LatencyHistogram& h, int lo, int hi) {
  std::vector<double> out;
  if (h.count() == 0) return out;
  const int bins = bin_count(lo, hi);
  auto edge = [&](int b) { return static_cast<Nanos>(std::llround(1e9 * std::pow(10.0, bin_edge(lo, b)))); };
  for (int b = 0; b < bins; ++b) {
    // The last bin also takes what lies above the axis (the histogram's top bucket).
    const std::uint64_t below = h.count_below(edge(b));
    const std::uint64_t upto = b + 1 == bins ? h.count() : h.count_below(edge(b + 1));
    out.push_back(100.0 * static_cast<double>(upto - below) / static_cast<double>(h.count()));
  }
  // Values below the axis go into the first bin.
  out.front() += 100.0 * static_cast<double>(h.count_below(edge(0))) / static_cast<double>(h.count());
  return out;
}

}  // namespace

void write_latency_plot(const std::filesystem::path& path, const std::vector<runtime::LoopStats>& loops,
                        bool real_time) {
  const SourceLocation where{path.string(), {}, {}, {}};
  std::vector<const runtime::LoopStats*> shown;
  double shortest = 1e9, longest = 0.0;  // [s] over every value and nominal period
  for (const auto& l : loops) {
    if (l.compute.count() == 0) continue;
    shown.push_back(&l);
    for (const auto* h : {&l.compute, &l.period}) {
      if (h->count() == 0) continue;
      shortest = std::min(shortest, std::max(1e-9, 1e-9 * static_cast<double>(h->min())));
      longest = std::max(longest, 1e-9 * static_cast<double>(h->max()));
    }
    if (l.rate > 0.0) {
      shortest = std::min(shortest, 1.0 / l.rate);
      longest = std::max(longest, 1.0 / l.rate);
    }
  }
  if (shown.empty()) throw InputError(where, "no loop ran a step: nothing to plot");
  const int lo = static_cast<int>(std::floor(std::log10(shortest) + 1e-9));
  const int hi = std::max(lo + 1, static_cast<int>(std::ceil(std::log10(longest) - 1e-9)));

  const int height = kTop + static_cast<int>(shown.size()) * (kPanel + kGap) - kGap + kBottom;
  raster::Image image(kWidth, height, kPaper);
  const int w = kWidth - kLeft - kRight;
  const double axis_lo = bin_edge(lo, 0), axis_hi = bin_edge(lo, bin_count(lo, hi));
  auto px = [&](double seconds) { return kLeft + (std::log10(seconds) - axis_lo) / (axis_hi - axis_lo) * w; };
  const std::string title = fmt::format("Loop latencies ({}): share of the steps [%] by duration", real_time ? "real time" : "lockstep, compute time only");
  raster::draw_text(image, kLeft + w / 2 - raster::text_width(title, kText) / 2, 10, title, kText, kInk);
  // Legend under the title.
  int lx = kLeft;
  auto legend = [&](raster::Rgb colour, const std::string& text) {
    raster::fill_rect(image, lx, 34, lx + 12, 44, colour);
    raster::draw_text(image, lx + 16, 31, text, kText, kInk);
    lx += 16 + raster::text_width(text, kText) + 24;
  };
  legend(kCompute, "compute time of a step");
  if (real_time) legend(kPeriod, "start-to-start period");
  legend(kNominal, "nominal period (1 / rate)");

  for (std::size_t k = 0; k < shown.size(); ++k) {
    const runtime::LoopStats& l = *shown[k];
    const int top = kTop + static_cast<int>(k) * (kPanel + kGap), bottom = top + kPanel;
    const std::vector<double> compute = shares(l.compute, lo, hi), period = shares(l.period, lo, hi);
    double peak = 0.0;
    for (double v : compute) peak = std::max(peak, v);
    for (double v : period) peak = std::max(peak, v);
    const double step = raster::nice_step(std::max(peak, 1.0), 4.0);
    const double top_share = std::ceil(std::max(peak, 1.0) / step) * step;
    auto py = [&](double share) { return bottom - share / top_share * kPanel; };
    for (double v = 0.0; v <= top_share + 1e-9; v += step) {
      const double y = py(v);
      raster::draw_line(image, kLeft, y, kLeft + w, y, kGrid);
      const std::string label = raster::tick_label(v, step);
      raster::draw_text(image, kLeft - 8 - raster::text_width(label, kText), static_cast<int>(y) - 7, label, kText, kInk);
    }
    // Bars: compute on the left half of each bin, the period on the right half.
    const int bins = static_cast<int>(compute.size());
    for (int b = 0; b < bins; ++b) {
      const double x0 = px(std::pow(10.0, bin_edge(lo, b))), x1 = px(std::pow(10.0, bin_edge(lo, b + 1)));
      const double mid = real_time ? 0.5 * (x0 + x1) : x1 - 1.0;
      if (compute[static_cast<std::size_t>(b)] > 0.0)
        raster::fill_rect(image, static_cast<int>(x0) + 1, static_cast<int>(py(compute[static_cast<std::size_t>(b)])),
                          static_cast<int>(mid), bottom, kCompute);
      if (real_time && !period.empty() && period[static_cast<std::size_t>(b)] > 0.0)
        raster::fill_rect(image, static_cast<int>(mid), static_cast<int>(py(period[static_cast<std::size_t>(b)])),
                          static_cast<int>(x1) - 1, bottom, kPeriod);
    }
    if (l.rate > 0.0)  // dashed, so that the bars under it still show
      for (int y = top; y < bottom; y += 8)
        raster::draw_line(image, px(1.0 / l.rate), y, px(1.0 / l.rate), std::min(y + 4, bottom), kNominal, 1.5);
    raster::stroke_rect(image, kLeft - 1, top - 1, kLeft + w + 1, bottom + 1, kInk);
    // Decades on the time axis.
    for (int d = lo; d <= hi; ++d) {
      const double x = px(std::pow(10.0, d));
      raster::draw_line(image, x, bottom, x, bottom + 5, kInk);
      const std::string label = duration_label(std::pow(10.0, d));
      raster::draw_text(image, static_cast<int>(x) - raster::text_width(label, kText) / 2, bottom + 6, label, kText, kInk);
    }
    const LatencySummary c = summarize(l.compute);
    const std::string heading =
        fmt::format("{} at {:g} Hz, {} steps: compute p50 {}, p99 {}, max {}{}", l.name, l.rate, l.steps,
                    duration_label(1e-9 * static_cast<double>(c.p50)), duration_label(1e-9 * static_cast<double>(c.p99)),
                    duration_label(1e-9 * static_cast<double>(c.max)),
                    real_time ? fmt::format("; {} missed deadlines", l.missed_deadlines) : std::string());
    raster::draw_text(image, kLeft, top - 20, heading, kText, kInk);
  }
  const std::string x_label = "duration (logarithmic)";
  raster::draw_text(image, kLeft + w / 2 - raster::text_width(x_label, kText) / 2, height - 24, x_label, kText, kInk);
  png::write_rgb(path, image.width, image.height, image.rgb);
}

}  // namespace tactus::report
