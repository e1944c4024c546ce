#pragma once
// Per-loop instrumentation: period, compute time and start lateness histograms, missed
// deadlines and overruns. Each loop owns its LoopStats and records into it without
// allocating; the session reads them once the loops have stopped.
#include <cstdint>
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

}  // namespace tactus::runtime
