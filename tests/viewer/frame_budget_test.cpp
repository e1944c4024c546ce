// Keeping the visual frame within its budget: the resolution governor's steps, which renderers
// count as software ones, and the plots' envelope (two points a pixel column, spikes kept).
#include "viewer/frame_budget.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "viewer/panel.hpp"

namespace tactus::viewer {
namespace {

ResolutionGovernor::Settings settings() {
  ResolutionGovernor::Settings s;
  s.budget_ms = 16.0;
  s.min_scale = 0.35;
  s.target = 0.85;
  s.grow_below = 0.6;
  s.period = 4;
  return s;
}

void feed(ResolutionGovernor& g, double ms, int frames) {
  for (int i = 0; i < frames; ++i) g.add(ms);
}

TEST(ResolutionGovernor, ShrinksByTheSquareRootOfTheOverrunOncePerPeriod) {
  ResolutionGovernor g(settings());
  feed(g, 40.0, 3);
  EXPECT_EQ(g.scale(), 1.0) << "no change before a period's frames are in";
  g.add(40.0);
  // The pixels' cost goes with scale², so 40 ms → 13.6 ms (85 % of 16) needs √(13.6/40).
  EXPECT_NEAR(g.scale(), std::sqrt(13.6 / 40.0), 1e-12);
}

TEST(ResolutionGovernor, SettlesWhereAFillBoundFrameFitsTheBudget) {
  // A frame of 2 ms fixed cost and 38 ms of pixels at full size.
  ResolutionGovernor g(settings());
  const auto frame = [&] { return 2.0 + 38.0 * g.scale() * g.scale(); };
  for (int i = 0; i < 400; ++i) g.add(frame());
  EXPECT_LE(frame(), 16.0);
  EXPECT_GE(frame(), 0.6 * 16.0) << "not shrunk further than the budget needs";
  // Settled: another 100 frames change nothing.
  const double settled = g.scale();
  for (int i = 0; i < 100; ++i) g.add(frame());
  EXPECT_EQ(g.scale(), settled);
}

TEST(ResolutionGovernor, NeverBelowTheLeastScaleNorAboveFullSize) {
  ResolutionGovernor g(settings());
  feed(g, 500.0, 40);
  EXPECT_EQ(g.scale(), 0.35);
  feed(g, 0.5, 40);
  EXPECT_EQ(g.scale(), 1.0);
}

TEST(ResolutionGovernor, OneStalledFrameInAPeriodDoesNotShrinkThePicture) {
  ResolutionGovernor g(settings());
  feed(g, 12.0, 3);
  g.add(90.0);  // the median of the period is 12 ms: within the budget
  EXPECT_EQ(g.scale(), 1.0);
}

TEST(ResolutionGovernor, IgnoresTimesThatAreNotTimes) {
  ResolutionGovernor g(settings());
  feed(g, std::numeric_limits<double>::quiet_NaN(), 10);
  feed(g, -1.0, 10);
  EXPECT_EQ(g.scale(), 1.0);
  feed(g, 40.0, 4);
  EXPECT_LT(g.scale(), 1.0);
}

TEST(FrameBudget, SoftwareRenderersAreKnownByTheirNames) {
  EXPECT_TRUE(is_software_renderer("llvmpipe (LLVM 15.0.6, 256 bits)"));
  EXPECT_TRUE(is_software_renderer("softpipe"));
  EXPECT_TRUE(is_software_renderer("Mesa X11 swrast"));
  EXPECT_FALSE(is_software_renderer("NVIDIA H100 80GB HBM3/PCIe/SSE2"));
  EXPECT_FALSE(is_software_renderer("AMD Radeon RX 7900 XTX (radeonsi, navi31, LLVM 15.0.6, DRM 3.49)"));
  EXPECT_FALSE(is_software_renderer(""));
}

TEST(PlotEnvelope, KeepsEverySpikeWithTwoPointsAColumn) {
  std::vector<float> values(2000, 1.0f);
  values[777] = 9.0f;   // a spike
  values[1500] = -3.0f;  // a dip
  const std::vector<float> env = min_max_envelope(values, 300);
  ASSERT_EQ(env.size(), 600u);
  float hi = -1e9f, lo = 1e9f;
  for (const float v : env) {
    hi = std::max(hi, v);
    lo = std::min(lo, v);
  }
  EXPECT_EQ(hi, 9.0f);
  EXPECT_EQ(lo, -3.0f);
  // The spike's column: sample 777 of 2000 falls in column 777·300/2000 = 116.
  EXPECT_TRUE(env[2 * 116] == 9.0f || env[2 * 116 + 1] == 9.0f);
  // Few values: unchanged.
  const std::vector<float> few{1.0f, 2.0f, 3.0f};
  EXPECT_EQ(min_max_envelope(few, 300), few);
  EXPECT_EQ(min_max_envelope(values, 0).size(), values.size());
}

TEST(PlotEnvelope, KeepsTheOrderOfTheColumnsExtremes) {
  // Falling within one column: the largest came first.
  const std::vector<float> falling{5.0f, 4.0f, 3.0f, 2.0f, 1.0f, 0.0f};
  EXPECT_EQ(min_max_envelope(falling, 1), (std::vector<float>{5.0f, 0.0f}));
  const std::vector<float> rising{0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f};
  EXPECT_EQ(min_max_envelope(rising, 1), (std::vector<float>{0.0f, 5.0f}));
}

}  // namespace
}  // namespace tactus::viewer
