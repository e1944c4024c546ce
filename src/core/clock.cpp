#include "core/clock.hpp"

#include <sys/resource.h>

#include <cerrno>
#include <ctime>
#include <stdexcept>
#include <string>
#include <thread>

namespace tactus {
namespace {

timespec to_timespec(Nanos t) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(t / kNanosPerSecond);
  ts.tv_nsec = static_cast<long>(t % kNanosPerSecond);
  return ts;
}

}  // namespace

Nanos now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<Nanos>(ts.tv_sec) * kNanosPerSecond + static_cast<Nanos>(ts.tv_nsec);
}

double process_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#else
  std::this_thread::yield();
#endif
}

void sleep_until(Nanos deadline, Nanos spin_window) {
  if (spin_window < 0) spin_window = 0;
  const Nanos wake = deadline - spin_window;
  if (wake > 0 && now_ns() < wake) {
    const timespec ts = to_timespec(wake);
    // Absolute time: a signal (EINTR) just repeats the same wait, no drift.
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
  }
  // Covers the spin window, and makes "never early" hold whatever the sleep did.
  while (now_ns() < deadline) cpu_relax();
}

LoopTimer::LoopTimer(Nanos period, Nanos first_deadline, std::int64_t max_late_periods)
    : period_(period), deadline_(first_deadline), max_late_periods_(max_late_periods) {
  if (period <= 0) throw std::invalid_argument("LoopTimer: period must be positive, got " + std::to_string(period) + " ns");
  if (max_late_periods < 0)
    throw std::invalid_argument("LoopTimer: max_late_periods must be >= 0, got " + std::to_string(max_late_periods));
}

void LoopTimer::advance(Nanos now) {
  deadline_ += period_;
  const Nanos late = now - deadline_;
  Nanos tolerance = 0;
  if (__builtin_mul_overflow(max_late_periods_, period_, &tolerance)) return;  // never re-bases
  if (late > tolerance) {
    // Keep the phase: jump to the first deadline on the grid after now.
    const std::int64_t skip = late / period_ + 1;
    deadline_ += skip * period_;
    skipped_periods_ += skip;
    ++rebases_;
  }
}

Nanos LoopTimer::wait(Nanos spin_window) {
  const Nanos target = deadline_;
  sleep_until(target, spin_window);
  const Nanos woke = now_ns();
  advance(woke);
  return woke - target;
}

}  // namespace tactus
