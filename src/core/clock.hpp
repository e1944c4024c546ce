#pragma once
// Monotonic time in integer nanoseconds, precise waiting, and the fixed-period schedule of
// a real-time loop.
#include <cstdint>

namespace tactus {

/// Nanoseconds: a time on the monotonic clock or a duration.
using Nanos = std::int64_t;

inline constexpr Nanos kNanosPerSecond = 1'000'000'000;

/// Now on CLOCK_MONOTONIC (the steady clock: never jumps with wall-clock changes).
[[nodiscard]] Nanos now_ns();

/// Returns at or after `deadline` (a now_ns() time), never before. Sleeps with an absolute
/// clock_nanosleep until `deadline - spin_window`, then busy-waits the rest: the kernel's
/// wake-up is late by tens of microseconds, the spin is not. spin_window <= 0: sleep only
/// (still never early). A deadline in the past returns at once.
void sleep_until(Nanos deadline, Nanos spin_window = 0);

/// CPU time this process has used so far, user plus system, over all its threads
/// (getrusage) [s].
[[nodiscard]] double process_cpu_seconds();

/// One CPU pause in a busy-wait loop (x86 `pause`; a yield elsewhere).
void cpu_relax();

/// The schedule of a loop that runs once per period: deadline k is start + k·period. A loop
/// late by a little runs at once to get back in phase; a loop more than `max_late_periods`
/// behind (a stall, a debugger) gives up the missed periods instead of running them in a
/// burst, and counts them.
class LoopTimer {
 public:
  /// period > 0; first_deadline is the first time to wait for; max_late_periods >= 0.
  /// Throws std::invalid_argument otherwise.
  LoopTimer(Nanos period, Nanos first_deadline, std::int64_t max_late_periods = 1);

  [[nodiscard]] Nanos period() const { return period_; }
  /// The deadline the loop waits for next.
  [[nodiscard]] Nanos deadline() const { return deadline_; }

  /// Moves to the next period. If `now` is then more than max_late_periods past the new
  /// deadline, skips whole periods so the deadline is the first one after `now`.
  void advance(Nanos now);

  /// sleep_until(deadline(), spin_window), then advance(); returns how late it woke
  /// (>= 0) relative to the deadline it waited for.
  Nanos wait(Nanos spin_window = 0);

  /// Periods given up by re-basing, and how many times that happened.
  [[nodiscard]] std::int64_t skipped_periods() const { return skipped_periods_; }
  [[nodiscard]] std::int64_t rebases() const { return rebases_; }

 private:
  Nanos period_;
  Nanos deadline_;
  std::int64_t max_late_periods_;
  std::int64_t skipped_periods_ = 0;
  std::int64_t rebases_ = 0;
};

}  // namespace tactus
