#pragma once
// Bounded single-producer single-consumer queue. Storage is allocated once at construction;
// push and pop never wait, never allocate (for T without heap members) and fail instead
// when the ring is full or empty. The caller decides what a failed push means (count it,
// drop it).
#include <atomic>
#include <bit>
#include <cstddef>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

namespace tactus {

template <class T>
class SpscRing {
 public:
  /// Holds at least `min_capacity` items: the capacity is rounded up to a power of two.
  explicit SpscRing(std::size_t min_capacity)
      : capacity_(rounded_capacity(min_capacity)), mask_(capacity_ - 1), slots_(std::make_unique<T[]>(capacity_)) {}

  SpscRing(const SpscRing&) = delete;
  SpscRing& operator=(const SpscRing&) = delete;

  [[nodiscard]] std::size_t capacity() const { return capacity_; }

  /// Producer thread only. False (and nothing stored) when the ring is full.
  bool try_push(const T& item) {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail - head_cache_ == capacity_) {
      // Looks full with the stale head: refresh it (acquire: the consumer is done reading).
      head_cache_ = head_.load(std::memory_order_acquire);
      if (tail - head_cache_ == capacity_) return false;
    }
    slots_[tail & mask_] = item;
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  /// Consumer thread only. False (and `out` untouched) when the ring is empty.
  bool try_pop(T& out) {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head == tail_cache_) {
      tail_cache_ = tail_.load(std::memory_order_acquire);
      if (head == tail_cache_) return false;
    }
    out = std::move(slots_[head & mask_]);
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  /// Items in the ring at some moment during the call; exact only when both sides are idle.
  [[nodiscard]] std::size_t size_approx() const {
    const std::size_t head = head_.load(std::memory_order_acquire);
    const std::size_t tail = tail_.load(std::memory_order_acquire);
    // Read in this order, tail >= head; but both sides may move between the two reads, so
    // the difference can exceed what the ring ever held at once.
    const std::size_t size = tail - head;
    return size > capacity_ ? capacity_ : size;
  }

 private:
  static constexpr std::size_t kCacheLine = 64;

  static std::size_t rounded_capacity(std::size_t min_capacity) {
    if (min_capacity == 0) throw std::invalid_argument("SpscRing: capacity must be at least 1");
    constexpr std::size_t kLargest = std::size_t{1} << (std::numeric_limits<std::size_t>::digits - 2);
    if (min_capacity > kLargest)
      throw std::invalid_argument("SpscRing: capacity " + std::to_string(min_capacity) + " is too large");
    return std::bit_ceil(min_capacity);
  }

  const std::size_t capacity_;
  const std::size_t mask_;
  const std::unique_ptr<T[]> slots_;

  // Indices count up forever (wrapping is harmless: capacity divides 2^64) and are masked
  // on access. Each side's index and its cached copy of the other side's index share a
  // line that the other side only reads.
  alignas(kCacheLine) std::atomic<std::size_t> tail_{0};  // written by the producer
  std::size_t head_cache_ = 0;                              // producer's view of head_
  alignas(kCacheLine) std::atomic<std::size_t> head_{0};  // written by the consumer
  std::size_t tail_cache_ = 0;                              // consumer's view of tail_
  // sizeof is a multiple of the alignment, so nothing else lands on the consumer's line.
};

}  // namespace tactus
