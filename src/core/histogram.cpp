#include "core/histogram.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace tactus {
namespace {

// Values below 2^kSubBits each have their own bucket. Above, each power of two [2^e, 2^(e+1))
// is split into 2^kSubBits equal buckets of width 2^(e - kSubBits): at most 1/128 of the
// value, and the bucket's middle is within half of that.
constexpr int kSubBits = 7;
constexpr std::uint64_t kSubCount = std::uint64_t{1} << kSubBits;
constexpr int kTopExponent = 39;  // the last power of two with its own buckets: [2^39, 2^40)
constexpr std::size_t kBucketCount = (kTopExponent - kSubBits + 2) * kSubCount;

std::size_t bucket_of(std::uint64_t v) {
  if (v < kSubCount) return static_cast<std::size_t>(v);
  const int exponent = static_cast<int>(std::bit_width(v)) - 1;
  if (exponent > kTopExponent) return kBucketCount - 1;
  const int shift = exponent - kSubBits;
  const std::uint64_t sub = (v >> shift) - kSubCount;
  return static_cast<std::size_t>(static_cast<std::uint64_t>(shift + 1) * kSubCount + sub);
}

/// The middle value of bucket b (a value that lands in it).
std::uint64_t bucket_middle(std::size_t b) {
  if (b < kSubCount) return b;
  const int shift = static_cast<int>(b / kSubCount) - 1;
  const std::uint64_t sub = b % kSubCount;
  const std::uint64_t lowest = (kSubCount + sub) << shift;
  const std::uint64_t width = std::uint64_t{1} << shift;
  return lowest + (width - 1) / 2;
}

}  // namespace

LatencyHistogram::LatencyHistogram() : buckets_(kBucketCount, 0) {}

void LatencyHistogram::record(Nanos value) {
  if (value < 0) value = 0;
  ++buckets_[bucket_of(static_cast<std::uint64_t>(value))];
  if (count_ == 0) {
    min_ = max_ = value;
  } else {
    min_ = std::min(min_, value);
    max_ = std::max(max_, value);
  }
  ++count_;
  sum_ += static_cast<double>(value);
  sum_squares_ += static_cast<double>(value) * static_cast<double>(value);
}

std::uint64_t LatencyHistogram::count_below(Nanos value) const {
  if (value <= 0) return 0;
  const std::size_t end = bucket_of(static_cast<std::uint64_t>(value));
  std::uint64_t n = 0;
  for (std::size_t b = 0; b < end; ++b) n += buckets_[b];
  return n;
}

double LatencyHistogram::mean() const { return count_ == 0 ? 0.0 : sum_ / static_cast<double>(count_); }

double LatencyHistogram::standard_deviation() const {
  if (count_ < 2) return 0.0;
  const double n = static_cast<double>(count_);
  // Sample SD; the sums are exact enough for durations below 2^40 ns and counts of millions.
  return std::sqrt(std::max(0.0, (sum_squares_ - sum_ * sum_ / n) / (n - 1.0)));
}

Nanos LatencyHistogram::percentile(double p) const {
  if (!(p >= 0.0 && p <= 100.0))
    throw std::invalid_argument("LatencyHistogram::percentile: p must be in [0, 100], got " + std::to_string(p));
  if (count_ == 0) return 0;
  if (p == 0.0) return min_;
  if (p == 100.0) return max_;
  const double exact_rank = std::ceil(p / 100.0 * static_cast<double>(count_));
  const std::uint64_t rank = std::clamp<std::uint64_t>(static_cast<std::uint64_t>(exact_rank), 1, count_);
  std::uint64_t seen = 0;
  for (std::size_t b = 0; b < buckets_.size(); ++b) {
    seen += buckets_[b];
    if (seen >= rank) {
      // min and max are exact and bound every order statistic; they also make the top
      // (catch-all) bucket usable.
      return std::clamp(static_cast<Nanos>(bucket_middle(b)), min_, max_);
    }
  }
  return max_;
}

void LatencyHistogram::merge(const LatencyHistogram& other) {
  if (other.count_ == 0) return;
  for (std::size_t b = 0; b < buckets_.size(); ++b) buckets_[b] += other.buckets_[b];
  min_ = count_ == 0 ? other.min_ : std::min(min_, other.min_);
  max_ = count_ == 0 ? other.max_ : std::max(max_, other.max_);
  count_ += other.count_;
  sum_ += other.sum_;
  sum_squares_ += other.sum_squares_;
}

void LatencyHistogram::reset() {
  std::fill(buckets_.begin(), buckets_.end(), 0);
  count_ = 0;
  sum_ = sum_squares_ = 0.0;
  min_ = max_ = 0;
}

LatencySummary summarize(const LatencyHistogram& histogram) {
  LatencySummary s;
  s.count = histogram.count();
  s.min = histogram.min();
  s.p50 = histogram.percentile(50.0);
  s.p99 = histogram.percentile(99.0);
  s.p999 = histogram.percentile(99.9);
  s.max = histogram.max();
  s.mean = histogram.mean();
  return s;
}

}  // namespace tactus
