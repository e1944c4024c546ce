#pragma once
// Where the hand will be one simulation step ahead (seed 002 §IV: the force thread predicts
// the finger's motion, so that the global step prepares the region the finger is about to
// touch). A least-squares line or parabola in time through the last samples of the haptic
// loop, evaluated `horizon` seconds after the newest: averaging over a window keeps device
// noise and tremor from being extrapolated, and the parabola follows a hand that speeds up
// or turns. Fixed storage: add() and predict() allocate nothing.
#include <array>

#include "core/math.hpp"

namespace tactus::haptics {

enum class Extrapolation { linear, quadratic };

class MotionPredictor {
 public:
  static constexpr int kMaxSamples = 64;

  /// Fits over the samples of the last `window` seconds (at least 2, or 3 for the parabola,
  /// at most kMaxSamples). Throws InputError for a window that is not positive and finite.
  explicit MotionPredictor(Extrapolation kind = Extrapolation::quadratic, double window = 0.01);

  /// A sample at time t [s] (increasing); a non-finite one, or one not after the last, is
  /// ignored.
  void add(double t, const Vec3& position) noexcept;
  /// The position `horizon` seconds after the newest sample; the newest sample itself while
  /// too few samples span the window, and nothing at all before the first (zero).
  [[nodiscard]] Vec3 predict(double horizon) const noexcept;
  void reset() noexcept { count_ = 0; }

 private:
  Extrapolation kind_;
  double window_;
  std::array<double, kMaxSamples> t_{};
  std::array<Vec3, kMaxSamples> p_{};
  int head_ = 0, count_ = 0;  // newest at head_ − 1
};

}  // namespace tactus::haptics
