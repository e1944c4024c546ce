// The pulse force: rate and duty cycle measured from a sampled force trace, the fade with
// distance and its range, the orientation, the sources along a vessel, no NaN, no allocation.
#include "haptics/algorithms/pulse.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "core/counting_allocator.hpp"

namespace tactus::haptics {
namespace {

constexpr double kHapticPeriod = 1e-3;  // [s]: a 1 kHz haptic loop samples the force
const Vec3 kUp(0, 0, 1);

PulseConfig config(double rate, double duty, std::vector<Vec3> sources = {Vec3::Zero()}) {
  PulseConfig c;
  c.rate = rate;
  c.duty_cycle = duty;
  c.amplitude = 0.3;
  c.range = 0.03;
  c.sources = std::move(sources);
  return c;
}

/// Rate [beats/min] and duty cycle measured from a force trace sampled every kHapticPeriod,
/// as an oscilloscope would: the period from the first to the last rising edge, the pulse
/// duration from each rising edge to the next falling one.
struct Measured {
  double rate = 0.0, duty = 0.0;
  int beats = 0;
};
Measured measure(const std::vector<double>& magnitude) {
  std::vector<std::size_t> rises, falls;
  for (std::size_t k = 1; k < magnitude.size(); ++k) {
    const bool high = magnitude[k] > 0.0, was = magnitude[k - 1] > 0.0;
    if (high && !was) rises.push_back(k);
    if (!high && was && !rises.empty()) falls.push_back(k);
  }
  Measured m;
  if (rises.size() < 2) return m;
  m.beats = static_cast<int>(rises.size());
  const double period = static_cast<double>(rises.back() - rises.front()) * kHapticPeriod / static_cast<double>(rises.size() - 1);
  double high = 0.0;
  std::size_t pulses = 0;
  for (std::size_t i = 0; i < rises.size() && i < falls.size(); ++i, ++pulses)
    high += static_cast<double>(falls[i] - rises[i]) * kHapticPeriod;
  m.rate = 60.0 / period;
  m.duty = high / static_cast<double>(pulses) / period;
  return m;
}

TEST(Pulse, MeasuredRateAndDutyCycleAreTheConfiguredOnes) {
  // The seed's range of rates (50–160 bpm) and its duty cycle 0.2, and an unusual duty.
  for (const double rate : {50.0, 72.0, 113.0, 160.0}) {
    for (const double duty : {0.2, 0.45}) {
      const PulseForce pulse(config(rate, duty));
      std::vector<double> trace;
      // 20 s of a finger pressing 5 mm above the source; starts off the beat's edge.
      for (int k = 0; k < 20000; ++k) {
        const double t = 0.0123 + k * kHapticPeriod;
        trace.push_back(pulse.force(t, Vec3(0, 0, 0.005), Vec3(0, 0, 2.0)).norm());
      }
      const Measured m = measure(trace);
      ASSERT_GE(m.beats, 15) << rate;
      // Within one haptic period: the edges are seen on 1 ms frames.
      const double period = 60.0 / rate;
      EXPECT_NEAR(60.0 / m.rate, period, kHapticPeriod) << rate << " bpm";
      EXPECT_NEAR(m.duty * period, duty * period, kHapticPeriod) << rate << " bpm, D = " << duty;
    }
  }
}

TEST(Pulse, ZeroBeyondRangeAndWhenNotPressing) {
  const PulseForce pulse(config(60.0, 0.2, {Vec3(0, 0, 0), Vec3(0.01, 0, 0)}));
  const double t = 0.05;  // on the beat
  ASSERT_TRUE(pulse.beating(t));
  EXPECT_GT(pulse.force(t, Vec3(0, 0, 0.01), kUp).norm(), 0.0);
  // 0.03 m from the nearest source and farther: nothing.
  for (const double z : {0.03, 0.0300001, 0.05, 1.0})
    EXPECT_EQ(pulse.force(t, Vec3(0.01, 0, z), kUp).norm(), 0.0) << z;
  // Between beats, or without a contact force (the tool is not pressing), nothing either.
  EXPECT_FALSE(pulse.beating(0.5));
  EXPECT_EQ(pulse.force(0.5, Vec3(0, 0, 0.01), kUp).norm(), 0.0);
  EXPECT_EQ(pulse.force(t, Vec3(0, 0, 0.01), Vec3::Zero()).norm(), 0.0);
}

TEST(Pulse, FadesMonotonicallyWithDistance) {
  const PulseForce pulse(config(60.0, 0.2));
  double previous = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= 400; ++k) {
    const double d = 1e-4 * k;  // 0 to 4 cm, past the range
    const double f = pulse.force(0.05, Vec3(0, 0, d), kUp).norm();
    if (d < 0.03) {
      EXPECT_LT(f, previous) << d;  // strictly inside the range
    } else {
      EXPECT_EQ(f, 0.0) << d;
    }
    previous = f;
  }
  // Straight above the source the law is A · (1 − d/range)², from A at the source.
  EXPECT_NEAR(pulse.force(0.05, Vec3(0, 0, 0.0), kUp).norm(), 0.3, 1e-12);
  EXPECT_NEAR(pulse.force(0.05, Vec3(0, 0, 0.015), kUp).norm(), 0.3 * 0.25, 1e-12);
}

TEST(Pulse, PushesAlongTheContactForceAndDependsOnOrientation) {
  const PulseForce pulse(config(60.0, 0.2));
  const Vec3 tool(0, 0, 0.01);
  const Vec3 straight = pulse.force(0.05, tool, Vec3(0, 0, 3.0));
  EXPECT_NEAR(straight.normalized().dot(kUp), 1.0, 1e-12);
  // Pressing at 60° to the direction of the vessel feels half; from the side or from behind
  // (the contact pushes the finger towards the source) nothing.
  const Vec3 tilted(std::sin(M_PI / 3), 0, std::cos(M_PI / 3));
  EXPECT_NEAR(pulse.force(0.05, tool, tilted).norm(), 0.5 * straight.norm(), 1e-12);
  EXPECT_NEAR(pulse.force(0.05, tool, tilted).normalized().dot(tilted), 1.0, 1e-12);
  EXPECT_EQ(pulse.force(0.05, tool, Vec3(1, 0, 0)).norm(), 0.0);
  EXPECT_EQ(pulse.force(0.05, tool, -kUp).norm(), 0.0);
  // The strongest source counts, not their number: ten sources at one spot feel like one.
  const PulseForce many(config(60.0, 0.2, std::vector<Vec3>(10, Vec3::Zero())));
  EXPECT_DOUBLE_EQ(many.force(0.05, tool, kUp).norm(), straight.norm());
}

TEST(Pulse, NeverNaN) {
  const PulseForce pulse(config(60.0, 0.2));
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const Vec3 bad(nan, 0, 0), huge(inf, 0, 0);
  for (const double t : {0.05, nan, inf, -inf, -3.7, 1e12}) {
    for (const Vec3& tool : {Vec3(0, 0, 0), Vec3(0, 0, 0.01), bad, huge}) {
      for (const Vec3& push : {kUp, Vec3(Vec3::Zero()), bad, huge, Vec3(0, 0, 1e-300)}) {
        const Vec3 f = pulse.force(t, tool, push);
        EXPECT_TRUE(f.allFinite());
        EXPECT_LE(f.norm(), 0.3 + 1e-12);
      }
    }
  }
}

TEST(Pulse, NoAllocationPerFrame) {
  const PulseForce pulse(config(72.0, 0.2, std::vector<Vec3>(50, Vec3(0, 0, -0.01))));
  testing::AllocationCounter counter;
  double sum = 0.0;
  for (int k = 0; k < 2000; ++k) sum += pulse.force(k * kHapticPeriod, Vec3(0, 0, 0.001 * (k % 7)), kUp).norm();
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(sum, 0.0);
}

TEST(Pulse, BadParametersAreRejected) {
  EXPECT_THROW(PulseForce(config(0.0, 0.2)), std::invalid_argument);
  EXPECT_THROW(PulseForce(config(72.0, 0.0)), std::invalid_argument);
  EXPECT_THROW(PulseForce(config(72.0, 1.0)), std::invalid_argument);
  EXPECT_THROW(PulseForce(config(72.0, 0.2, {})), std::invalid_argument);
  PulseConfig c = config(72.0, 0.2);
  c.range = -1.0;
  EXPECT_THROW(PulseForce{c}, std::invalid_argument);
  c = config(72.0, 0.2, {Vec3(std::nan(""), 0, 0)});
  EXPECT_THROW(PulseForce{c}, std::invalid_argument);
}

TEST(PulseSources, LieOnTheCentrelineOfATube) {
  // A tube of radius 3 mm along a tilted axis from a to b: rings of 16 points every 2 mm.
  const Vec3 a(0.01, -0.02, -0.01), b(0.05, 0.06, -0.012);
  const Vec3 axis = (b - a).normalized();
  const Vec3 u = axis.cross(Vec3::UnitZ()).normalized(), v = axis.cross(u);
  std::vector<Vec3> nodes;
  const int rings = 45;
  for (int r = 0; r < rings; ++r)
    for (int k = 0; k < 16; ++k) {
      const double phi = 2 * M_PI * k / 16;
      nodes.push_back(a + (b - a) * r / (rings - 1.0) + 0.003 * (std::cos(phi) * u + std::sin(phi) * v));
    }
  const std::vector<Vec3> sources = pulse_sources_along_axis(nodes, 8);
  ASSERT_EQ(sources.size(), 8u);
  // A source at the centre of each eighth of the segment a–b (up to rounding; the axis's
  // sign, and so the order, is the eigen solver's choice).
  for (int k = 0; k < 8; ++k) {
    double nearest = 1.0;
    for (const Vec3& s : sources) nearest = std::min(nearest, (s - (a + (b - a) * (k + 0.5) / 8.0)).norm());
    EXPECT_LT(nearest, 1e-12) << k;
  }
  EXPECT_THROW((void)pulse_sources_along_axis({}, 3), std::invalid_argument);
  EXPECT_THROW((void)pulse_sources_along_axis(nodes, 0), std::invalid_argument);
}

}  // namespace
}  // namespace tactus::haptics
