#include "core/parallel.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

namespace tactus {
namespace {

/// Restores the default thread count when a test ends.
struct ThreadLimit {
  explicit ThreadLimit(unsigned limit) { set_thread_limit(limit); }
  ~ThreadLimit() { set_thread_limit(0); }
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;
};

/// Per-index results of a floating-point kernel with a data-dependent number of steps.
std::vector<double> compute(std::size_t n) {
  std::vector<double> out(n);
  parallel_for(0, n, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      double x = 0.1 * static_cast<double>(i);
      for (std::size_t k = 0; k < i % 17; ++k) x = std::sin(x) + 0.5 * x;
      out[i] = x;
    }
  });
  return out;
}

TEST(ParallelFor, ResultsAreIdenticalForOneAndTwoThreads) {
  std::vector<double> serial, two;
  {
    ThreadLimit limit(1);
    EXPECT_EQ(thread_count(), 1u);
    serial = compute(10007);
  }
  {
    ThreadLimit limit(2);
    EXPECT_GE(thread_count(), 1u);
    EXPECT_LE(thread_count(), 2u);
    for (int repeat = 0; repeat < 20; ++repeat) {
      two = compute(10007);
      ASSERT_EQ(two, serial) << "repeat " << repeat;  // bit for bit
    }
  }
}

TEST(ParallelFor, CoversTheRangeOnceInDisjointChunks) {
  ThreadLimit limit(2);
  for (std::size_t n : {1u, 2u, 3u, 100u, 4097u}) {
    std::vector<std::atomic<int>> hits(n + 10);
    parallel_for(5, 5 + n, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) hits[i].fetch_add(1, std::memory_order_relaxed);
    });
    for (std::size_t i = 0; i < hits.size(); ++i) EXPECT_EQ(hits[i].load(), i >= 5 && i < 5 + n ? 1 : 0) << n << " " << i;
  }
}

TEST(ParallelFor, EmptyRangeReturnsWithoutCalling) {
  ThreadLimit limit(2);
  int calls = 0;
  parallel_for(7, 7, [&](std::size_t, std::size_t) { ++calls; });
  parallel_for(9, 3, [&](std::size_t, std::size_t) { ++calls; });
  EXPECT_EQ(calls, 0);
  // The pool still works afterwards.
  std::atomic<int> sum{0};
  parallel_for(0, 1000, [&](std::size_t b, std::size_t e) { sum += static_cast<int>(e - b); });
  EXPECT_EQ(sum.load(), 1000);
}

TEST(ParallelFor, ExceptionsPropagateToTheCaller) {
  for (unsigned threads : {1u, 2u}) {
    ThreadLimit limit(threads);
    EXPECT_THROW(parallel_for(0, 1000,
                              [](std::size_t b, std::size_t e) {
                                for (std::size_t i = b; i < e; ++i)
                                  if (i == 900) throw std::runtime_error("index 900");
                              }),
                 std::runtime_error);
    EXPECT_THROW(parallel_for(0, 1000, [](std::size_t, std::size_t) { throw std::logic_error("every chunk"); }),
                 std::logic_error);
    // No chunk is left running and the next call succeeds.
    std::atomic<int> sum{0};
    parallel_for(0, 1000, [&](std::size_t b, std::size_t e) { sum += static_cast<int>(e - b); });
    EXPECT_EQ(sum.load(), 1000) << threads;
  }
}

TEST(ParallelFor, NestedCallsRunSeriallyWithoutDeadlock) {
  ThreadLimit limit(2);
  std::vector<int> out(64, 0);
  parallel_for(0, 8, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      parallel_for(8 * i, 8 * i + 8, [&](std::size_t bb, std::size_t ee) {
        for (std::size_t j = bb; j < ee; ++j) out[j] = static_cast<int>(j);
      });
  });
  for (std::size_t j = 0; j < out.size(); ++j) EXPECT_EQ(out[j], static_cast<int>(j));
}

TEST(ParallelFor, SmallRangesBelowTheMinimumChunkRunOnTheCaller) {
  ThreadLimit limit(2);
  int calls = 0;  // not atomic: a single call on this thread is expected
  parallel_for(0, 100, [&](std::size_t b, std::size_t e) {
    ++calls;
    EXPECT_EQ(b, 0u);
    EXPECT_EQ(e, 100u);
  }, 64);
  EXPECT_EQ(calls, 1);
}

TEST(ParallelFor, ManyShortJobsInARow) {
  // The haptic pattern: thousands of tiny dispatches; none may be lost or hang, with
  // blocking waits and with spinning ones.
  ThreadLimit limit(2);
  for (int spin : {0, 50}) {
    set_spin_wait(std::chrono::microseconds(spin));
    std::vector<double> v(256, 0.0);
    for (int round = 0; round < 2000; ++round)
      parallel_for(0, v.size(), [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) v[i] += 1.0;
      });
    for (double x : v) EXPECT_EQ(x, 2000.0) << spin;
  }
  set_spin_wait(std::chrono::microseconds(0));
}

TEST(RunTeam, MembersRunTogetherAndSyncRoundByRound) {
  ThreadLimit limit(2);
  std::vector<int> slot(4, -1);
  std::atomic<unsigned> calls{0}, members_seen{0};
  std::atomic<int> mismatches{0};
  run_team(4, [&](unsigned member, Team& team) {
    ++calls;
    members_seen = team.members();
    for (int round = 0; round < 500; ++round) {
      slot[member] = round;
      team.sync();
      for (unsigned m = 0; m < team.members(); ++m) mismatches += slot[m] != round;
      team.sync();  // nobody writes the next round before all have read this one
    }
  });
  EXPECT_EQ(members_seen.load(), 2u);  // at most the pool's threads
  EXPECT_EQ(calls.load(), 2u);
  EXPECT_EQ(mismatches.load(), 0);
}

TEST(RunTeam, AloneWhereNoOtherThreadIsFree) {
  ThreadLimit limit(2);
  unsigned one = 0;
  run_team(1, [&](unsigned member, Team& team) { one = team.members() + member; });
  EXPECT_EQ(one, 1u);
  // Inside a parallel loop's chunk (the pool is taken) a team is its caller alone, and a
  // sync returns at once instead of waiting for members that will never come.
  std::vector<unsigned> nested(2, 0);
  parallel_for(0, 2, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      run_team(2, [&](unsigned, Team& team) {
        team.sync();
        nested[i] = team.members();
      });
  });
  EXPECT_EQ(nested, (std::vector<unsigned>{1, 1}));
}

}  // namespace
}  // namespace tactus
