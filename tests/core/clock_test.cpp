// now_ns, sleep_until and LoopTimer. Timing is checked only for "never early" and loose
// sanity bounds: the machine running the tests is shared and noisy.
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>

#include "core/clock.hpp"

namespace tactus {
namespace {

constexpr Nanos kMicro = 1'000;
constexpr Nanos kMilli = 1'000'000;

TEST(Clock, NowIsMonotonicAndAdvances) {
  Nanos previous = now_ns();
  for (int i = 0; i < 10000; ++i) {
    const Nanos t = now_ns();
    ASSERT_GE(t, previous);
    previous = t;
  }
  const Nanos start = now_ns();
  sleep_until(start + 2 * kMilli);
  EXPECT_GE(now_ns() - start, 2 * kMilli);
}

TEST(SleepUntil, NeverReturnsBeforeTheDeadline) {
  const Nanos spin_windows[] = {0, 20 * kMicro, 50 * kMicro, 5 * kMilli, -kMilli};
  const Nanos offsets[] = {-kMilli, 0, 1, 10 * kMicro, 100 * kMicro, 700 * kMicro};
  int early = 0;
  for (int repeat = 0; repeat < 5; ++repeat) {
    for (Nanos spin : spin_windows) {
      for (Nanos offset : offsets) {
        const Nanos deadline = now_ns() + offset;
        sleep_until(deadline, spin);
        if (now_ns() < deadline) ++early;
      }
    }
  }
  EXPECT_EQ(early, 0);
}

TEST(SleepUntil, PastDeadlineReturnsPromptly) {
  const Nanos start = now_ns();
  for (int i = 0; i < 1000; ++i) sleep_until(start - kMilli, 50 * kMicro);
  sleep_until(0);
  EXPECT_LT(now_ns() - start, 500 * kMilli);  // sanity bound only: no sleeping happened
}

TEST(LoopTimer, DeadlinesFollowTheFixedGrid) {
  LoopTimer timer(kMilli, 10 * kMilli);
  EXPECT_EQ(timer.period(), kMilli);
  EXPECT_EQ(timer.deadline(), 10 * kMilli);
  for (int k = 1; k <= 100; ++k) {
    // The loop finishes some time within each period: no drift, no skipping.
    timer.advance(timer.deadline() + (k * 37 % 900) * kMicro);
    EXPECT_EQ(timer.deadline(), 10 * kMilli + k * kMilli);
  }
  EXPECT_EQ(timer.skipped_periods(), 0);
  EXPECT_EQ(timer.rebases(), 0);
}

TEST(LoopTimer, SlightlyLateLoopRunsAtOnceToCatchUp) {
  LoopTimer timer(kMilli, 0, 1);
  // The iteration for deadline 0 overran to 1.6 ms: deadline 1 ms is 0.6 periods ago.
  timer.advance(1'600 * kMicro);
  EXPECT_EQ(timer.deadline(), kMilli);
  EXPECT_EQ(timer.rebases(), 0);
  // The catch-up iteration ends at 1.7 ms: back on schedule at 2 ms.
  timer.advance(1'700 * kMicro);
  EXPECT_EQ(timer.deadline(), 2 * kMilli);
  EXPECT_EQ(timer.skipped_periods(), 0);
}

TEST(LoopTimer, RebasesAfterALongStallInsteadOfBursting) {
  LoopTimer timer(kMilli, 0, 2);
  // Stalled for 57.3 ms after deadline 0: deadlines 1..57 ms have all passed.
  timer.advance(57'300 * kMicro);
  EXPECT_EQ(timer.rebases(), 1);
  EXPECT_EQ(timer.skipped_periods(), 57);
  EXPECT_EQ(timer.deadline(), 58 * kMilli);  // the first grid point after now: phase kept
  timer.advance(58'100 * kMicro);
  EXPECT_EQ(timer.deadline(), 59 * kMilli);
  EXPECT_EQ(timer.rebases(), 1);

  // Exactly at the tolerance (2 periods late) is still caught up, one more period is not.
  LoopTimer edge(kMilli, 0, 2);
  edge.advance(3 * kMilli);
  EXPECT_EQ(edge.rebases(), 0);
  EXPECT_EQ(edge.deadline(), kMilli);
  edge.advance(5 * kMilli + 1);
  EXPECT_EQ(edge.rebases(), 1);
  EXPECT_EQ(edge.deadline(), 6 * kMilli);
  EXPECT_EQ(edge.skipped_periods(), 4);
}

TEST(LoopTimer, ZeroToleranceRebasesWheneverADeadlineWasMissed) {
  LoopTimer timer(kMilli, 0, 0);
  timer.advance(kMilli);  // exactly on the next deadline: not missed
  EXPECT_EQ(timer.rebases(), 0);
  timer.advance(2 * kMilli + 1);
  EXPECT_EQ(timer.rebases(), 1);
  EXPECT_EQ(timer.deadline(), 3 * kMilli);
}

TEST(LoopTimer, WaitSleepsToEachDeadlineAndReportsLateness) {
  const Nanos period = 500 * kMicro;
  const Nanos start = now_ns() + period;
  LoopTimer timer(period, start, 1000);  // tolerate any stall: the grid must stay exact
  for (int k = 0; k < 20; ++k) {
    const Nanos deadline = timer.deadline();
    EXPECT_EQ(deadline, start + k * period);
    const Nanos lateness = timer.wait(k % 2 == 0 ? 0 : 50 * kMicro);
    EXPECT_GE(lateness, 0);
    EXPECT_GE(now_ns(), deadline);
  }
  EXPECT_EQ(timer.deadline(), start + 20 * period);
}

TEST(LoopTimer, RejectsNonPositivePeriodAndNegativeTolerance) {
  EXPECT_THROW(LoopTimer(0, 0), std::invalid_argument);
  EXPECT_THROW(LoopTimer(-kMilli, 0), std::invalid_argument);
  EXPECT_THROW(LoopTimer(kMilli, 0, -1), std::invalid_argument);
}

TEST(LoopTimer, HugeToleranceNeverOverflows) {
  LoopTimer timer(kNanosPerSecond, 0, INT64_MAX / 2);
  timer.advance(1000 * kNanosPerSecond);
  EXPECT_EQ(timer.rebases(), 0);
  EXPECT_EQ(timer.deadline(), kNanosPerSecond);
}

}  // namespace
}  // namespace tactus
