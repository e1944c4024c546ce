#pragma once
// Per-loop instrumentation: period, compute time and start lateness histograms, missed
// deadlines and overruns. Each loop owns its LoopStats and records into it without
// allocating; the session reads them once the loops have stopped.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/clock.hpp"
#include "core/histogram.hpp"

namespace tactus::runtime {

struct LoopStats {
  std::string name;    ///< "haptic[hand]", "simulation", "interaction", "visual"
  double rate = 0.0;   ///< nominal [Hz]
  LatencyHistogram period;    ///< start-to-start interval (real time only)
  LatencyHistogram compute;   ///< time spent in the step
  LatencyHistogram lateness;  ///< start minus deadline (real time only)
  std::uint64_t steps = 0;
  std::uint64_t missed_deadlines = 0;  ///< started more than one period late
  std::uint64_t overruns = 0;          ///< compute time longer than the period

  /// Records one step that started at `start` (deadline `deadline`) and took `compute`.
  void record(Nanos deadline, Nanos start, Nanos compute_time, bool real_time);

 private:
  Nanos last_start_ = -1;
};

/// Extra named timings inside a loop (seed 003 Table 1: the simulation step's parts, the
/// per-object collision query).
struct PartStats {
  std::string name;
  LatencyHistogram time;
};

/// Times a step's parts with the clock its loop hands it, if any: the steps read no clock of
/// their own, and a step driven by hand (tests) passes none and records nothing.
struct PartTimer {
  Nanos (*clock)() = nullptr;
  Nanos start = 0;
  explicit PartTimer(Nanos (*c)()) : PartTimer(c, c ? c() : 0) {}
  PartTimer(Nanos (*c)(), Nanos from) : clock(c), start(from) {}
  /// Records the time since `start` into parts[part] (where there is one) and returns now,
  /// the next part's start (0 without a clock).
  Nanos record(std::span<PartStats> parts, std::size_t part) const {
    if (!clock) return 0;
    const Nanos now = clock();
    if (part < parts.size()) parts[part].time.record(now - start);
    return now;
  }
};

}  // namespace tactus::runtime
