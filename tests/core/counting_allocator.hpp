#pragma once
// Counts heap allocations per thread, for tests that assert a code region (a haptic-loop
// step, a lock-free hand-over) allocates nothing. Linking counting_allocator.cpp into a test
// executable replaces the global operator new and delete (every overload) with versions that
// count and forward to malloc; under ASan, malloc is still checked.
//
//   tactus::testing::AllocationCounter counter;
//   code_under_test();
//   EXPECT_EQ(counter.count(), 0u);
//
// Only operator new is counted (direct malloc calls are not); only the calling thread's.
#include <cstdint>

namespace tactus::testing {

/// Calls of any operator new made by the calling thread since it started.
[[nodiscard]] std::uint64_t thread_allocation_count();
/// Bytes requested from operator new by the calling thread since it started.
[[nodiscard]] std::uint64_t thread_allocated_bytes();

/// Allocations made by the constructing thread between construction and count(). Use it on
/// one thread only.
class AllocationCounter {
 public:
  AllocationCounter() : start_count_(thread_allocation_count()), start_bytes_(thread_allocated_bytes()) {}

  [[nodiscard]] std::uint64_t count() const { return thread_allocation_count() - start_count_; }
  [[nodiscard]] std::uint64_t bytes() const { return thread_allocated_bytes() - start_bytes_; }

 private:
  std::uint64_t start_count_;
  std::uint64_t start_bytes_;
};

}  // namespace tactus::testing
