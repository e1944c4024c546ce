#include "runtime/loop_stats.hpp"

namespace tactus::runtime {

void LoopStats::record(Nanos deadline, Nanos start, Nanos compute_time, bool real_time) {
  ++steps;
  compute.record(compute_time);
  const auto period_ns = static_cast<Nanos>(1e9 / rate);
  if (compute_time > period_ns) ++overruns;
  if (!real_time) return;
  const Nanos late = start > deadline ? start - deadline : 0;
  lateness.record(late);
  if (late > period_ns) ++missed_deadlines;
  if (last_start_ >= 0) period.record(start - last_start_);
  last_start_ = start;
}

}  // namespace tactus::runtime
