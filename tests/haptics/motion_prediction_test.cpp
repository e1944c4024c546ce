// The hand's motion one simulation step ahead: a line and a parabola fitted over the last
// samples reproduce the motions they can represent exactly, stay put with too few samples,
// and smooth over noise rather than extrapolate it.
#include "haptics/motion_prediction.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/counting_allocator.hpp"
#include "core/error.hpp"

namespace tactus::haptics {
namespace {

constexpr double kFrame = 1e-3;

TEST(MotionPrediction, LinesAndParabolasAreExtrapolatedExactly) {
  MotionPredictor line(Extrapolation::linear), parabola(Extrapolation::quadratic);
  const Vec3 p0(0.01, -0.02, 0.3), v(0.05, 0.01, -0.02), a(0.8, -0.4, 0.2);
  MotionPredictor line_on_curve(Extrapolation::linear);
  for (int k = 0; k < 30; ++k) {
    const double t = 1.0 + k * kFrame;
    line.add(t, p0 + v * t);
    parabola.add(t, p0 + v * t + 0.5 * a * t * t);
    line_on_curve.add(t, p0 + v * t + 0.5 * a * t * t);
  }
  const double t_end = 1.0 + 29 * kFrame, h = 0.01;
  EXPECT_LT((line.predict(h) - (p0 + v * (t_end + h))).norm(), 1e-12);
  const Vec3 curve = p0 + v * (t_end + h) + 0.5 * a * (t_end + h) * (t_end + h);
  EXPECT_LT((parabola.predict(h) - curve).norm(), 1e-11);
  // A line through a parabola misses by about ½|a|·h·(h + window): tens of micrometres here.
  EXPECT_GT((line_on_curve.predict(h) - curve).norm(), 1e-5);
}

TEST(MotionPrediction, TooFewSamplesGiveTheNewest) {
  MotionPredictor p(Extrapolation::quadratic);
  EXPECT_EQ(p.predict(0.01), Vec3::Zero());
  p.add(0.0, Vec3(1, 2, 3));
  p.add(0.001, Vec3(1, 2, 4));
  EXPECT_EQ(p.predict(0.01), Vec3(1, 2, 4));  // a parabola needs three
  p.add(0.001, Vec3(9, 9, 9));                // not after the last: ignored
  p.add(0.002, Vec3(NAN, 0, 0));              // not finite: ignored
  EXPECT_EQ(p.predict(0.01), Vec3(1, 2, 4));
  EXPECT_THROW(MotionPredictor(Extrapolation::linear, 0.0), InputError);
}

TEST(MotionPrediction, NoiseIsAveragedNotExtrapolated) {
  // A hand at rest with 10 µm of sensor noise: the prediction 10 ms ahead stays within a few
  // noise amplitudes of the rest position, where extrapolating the last two samples could
  // throw it 10 × 20 µm away.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-1e-5, 1e-5);
  MotionPredictor p(Extrapolation::linear, 0.01);
  double worst = 0.0;
  for (int k = 0; k < 2000; ++k) {
    p.add(k * kFrame, Vec3(noise(rng), noise(rng), noise(rng)));
    if (k > 20) worst = std::max(worst, p.predict(0.01).norm());
  }
  EXPECT_LT(worst, 6e-5);
}

TEST(MotionPrediction, AddAndPredictAllocateNothing) {
  MotionPredictor p;
  testing::AllocationCounter counter;
  for (int k = 0; k < 200; ++k) {
    p.add(k * kFrame, Vec3(k, 0, 0));
    (void)p.predict(0.01);
  }
  EXPECT_EQ(counter.count(), 0u);
}

}  // namespace
}  // namespace tactus::haptics
