#pragma once
// A small persistent worker pool for data-parallel loops. parallel_for splits a range into
// one contiguous chunk per thread; callers whose chunks write disjoint outputs get results
// independent of the thread count, which lockstep replay relies on.
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
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

/// The threads of one run_team call: how many there are, and a barrier they share.
class Team {
 public:
  explicit Team(unsigned members) : members_(members) {}
  Team(const Team&) = delete;
  Team& operator=(const Team&) = delete;
  [[nodiscard]] unsigned members() const { return members_; }
  /// Returns once every member has called it (this round). Writes made before it by any
  /// member are visible after it to all. Spins for a few tens of microseconds (the phases it
  /// separates are short), then blocks.
  void sync();

 private:
  unsigned members_;
  std::atomic<unsigned> arrived_{0};
  std::atomic<std::uint32_t> round_{0};
};

namespace detail {
using ChunkFn = void (*)(void* context, std::size_t begin, std::size_t end);
using MemberFn = void (*)(void* context, unsigned member, Team& team);
void run_team(unsigned wanted, MemberFn fn, void* context);
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

/// Calls fn(member, team) on team.members() threads at once, member = 0 .. members - 1 (the
/// caller is member 0): up to `wanted`, as many as thread_count() allows, and 1 where the
/// pool is busy, in a nested call or limited to one thread. All members run concurrently, so
/// they may wait for each other with team.sync(). fn must not throw (a member that left early
/// would leave the others waiting); work split by a fixed rule over members gives results
/// independent of their number.
template <class Fn>
void run_team(unsigned wanted, Fn&& fn) {
  using F = std::remove_reference_t<Fn>;
  detail::run_team(
      wanted, [](void* context, unsigned member, Team& team) { (*static_cast<F*>(context))(member, team); },
      const_cast<void*>(static_cast<const void*>(&fn)));
}

}  // namespace tactus
