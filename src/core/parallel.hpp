#pragma once
// A small persistent worker pool for data-parallel loops. parallel_for splits a range into
// one contiguous chunk per thread; callers whose chunks write disjoint outputs get results
// independent of the thread count, which lockstep replay relies on.
#include <chrono>
#include <cstddef>
#include <type_traits>
#include <utility>

namespace tactus {

/// Caps the threads parallel_for uses: 0 = std::thread::hardware_concurrency(), 1 = serial
/// (no workers). Rebuilds the pool; must not run while a parallel_for is in flight.
void set_thread_limit(unsigned limit);
/// How long idle workers and a waiting caller spin before they block (default 0: block at
/// once). Worth some microseconds only where the threads have cores to themselves.
void set_spin_wait(std::chrono::microseconds wait);
/// Threads parallel_for uses now (the calling thread included), at least 1.
[[nodiscard]] unsigned thread_count();

namespace detail {
using ChunkFn = void (*)(void* context, std::size_t begin, std::size_t end);
/// Runs fn over [begin, end) in chunks of at least min_chunk; rethrows the exception of the
/// lowest failing chunk after every chunk has finished.
void run_parallel(std::size_t begin, std::size_t end, std::size_t min_chunk, ChunkFn fn, void* context);
}  // namespace detail

/// Calls fn(chunk_begin, chunk_end) on disjoint contiguous chunks covering [begin, end),
/// concurrently on up to thread_count() threads (the caller runs the first chunk). Ranges
/// shorter than 2 * min_chunk, and calls from inside a chunk, run serially on the caller.
/// No allocation: fn is passed by reference, not wrapped in std::function.
template <class Fn>
void parallel_for(std::size_t begin, std::size_t end, Fn&& fn, std::size_t min_chunk = 1) {
  using F = std::remove_reference_t<Fn>;
  detail::run_parallel(
      begin, end, min_chunk,
      [](void* context, std::size_t b, std::size_t e) { (*static_cast<F*>(context))(b, e); },
      const_cast<void*>(static_cast<const void*>(&fn)));
}

}  // namespace tactus
