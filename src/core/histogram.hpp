#pragma once
// Latency histogram for loop instrumentation: records durations in nanoseconds into
// log-linear buckets (128 linear steps per power of two, as HdrHistogram does), so every
// percentile is within 0.4% of the exact order statistic, from 1 ns up to about 18 minutes.
// All storage is allocated by the constructor: record() never allocates, and copying into
// an existing histogram reuses its storage. Not thread-safe: each loop owns its histograms.
#include <cstdint>
#include <vector>

#include "core/clock.hpp"

namespace tactus {

class LatencyHistogram {
 public:
  LatencyHistogram();

  /// Adds one duration. Negative values are recorded as 0; values of 2^40 ns (about 18
  /// minutes) and more share the top bucket (min and max stay exact).
  void record(Nanos value);

  [[nodiscard]] std::uint64_t count() const { return count_; }
  /// Exact smallest and largest recorded values; 0 when empty.
  [[nodiscard]] Nanos min() const { return count_ == 0 ? 0 : min_; }
  [[nodiscard]] Nanos max() const { return count_ == 0 ? 0 : max_; }
  /// Arithmetic mean of the recorded values; 0 when empty.
  [[nodiscard]] double mean() const;
  /// Sample standard deviation of the recorded values (exact, not from the buckets); 0 for
  /// fewer than two.
  [[nodiscard]] double standard_deviation() const;
  /// The value below which p percent of the recorded values lie (the order statistic of rank
  /// ceil(p/100 · count), at least 1), within 0.4% (or 1 ns); percentile(0) is min(),
  /// percentile(100) is max(); 0 when empty. Throws std::invalid_argument unless 0 <= p <= 100.
  [[nodiscard]] Nanos percentile(double p) const;

  /// How many recorded values lie below `value`, to the resolution of the buckets: the values
  /// in the buckets below value's own (so within 1/128 of value, exact below 128 ns).
  [[nodiscard]] std::uint64_t count_below(Nanos value) const;

  /// Adds every value recorded in `other`.
  void merge(const LatencyHistogram& other);
  /// Forgets every value; keeps the storage.
  void reset();

 private:
  std::vector<std::uint64_t> buckets_;
  std::uint64_t count_ = 0;
  double sum_ = 0.0;
  double sum_squares_ = 0.0;
  Nanos min_ = 0;
  Nanos max_ = 0;
};

struct LatencySummary {
  std::uint64_t count = 0;
  Nanos min = 0;
  Nanos p50 = 0;
  Nanos p99 = 0;
  Nanos p999 = 0;
  Nanos max = 0;
  double mean = 0.0;
};

[[nodiscard]] LatencySummary summarize(const LatencyHistogram& histogram);

}  // namespace tactus
