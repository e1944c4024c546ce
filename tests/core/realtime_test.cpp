// Real-time requests must never throw and must say what they obtained. The test machine may
// or may not grant SCHED_FIFO, so the checks hold either way; each request runs on its own
// thread so the test process keeps its normal scheduling.
#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

#include "core/realtime.hpp"

namespace tactus {
namespace {

template <class Fn>
void on_new_thread(Fn fn) {
  std::thread t(fn);
  t.join();
}

TEST(Realtime, FifoRequestReportsWhatItGot) {
  on_new_thread([] {
    const RealtimeResult r = make_current_thread_realtime(RealtimeRequest{10, -1});
    EXPECT_FALSE(r.message.empty());
    EXPECT_FALSE(r.pinned);
    int policy = -1;
    sched_param param{};
    ASSERT_EQ(pthread_getschedparam(pthread_self(), &policy, &param), 0);
    if (r.fifo) {
      EXPECT_EQ(policy, SCHED_FIFO);
      EXPECT_EQ(param.sched_priority, 10);
      // Priority 0 returns the thread to the normal scheduler.
      const RealtimeResult normal = make_current_thread_realtime(RealtimeRequest{});
      EXPECT_FALSE(normal.fifo);
      ASSERT_EQ(pthread_getschedparam(pthread_self(), &policy, &param), 0);
      EXPECT_EQ(policy, SCHED_OTHER);
    } else {
      EXPECT_NE(policy, SCHED_FIFO);
      EXPECT_NE(r.message.find("SCHED_FIFO"), std::string::npos) << r.message;
    }
  });
}

TEST(Realtime, NormalRequestChangesNothing) {
  on_new_thread([] {
    const RealtimeResult r = make_current_thread_realtime(RealtimeRequest{});
    EXPECT_FALSE(r.fifo);
    EXPECT_FALSE(r.pinned);
    EXPECT_FALSE(r.message.empty());
  });
}

TEST(Realtime, PinningToAnAllowedCpuHoldsItThere) {
  cpu_set_t allowed;
  ASSERT_EQ(sched_getaffinity(0, sizeof(allowed), &allowed), 0);
  int cpu = 0;
  while (cpu < CPU_SETSIZE && !CPU_ISSET(cpu, &allowed)) ++cpu;
  ASSERT_LT(cpu, CPU_SETSIZE);
  on_new_thread([cpu] {
    const RealtimeResult r = make_current_thread_realtime(RealtimeRequest{0, cpu});
    EXPECT_FALSE(r.message.empty());
    if (r.pinned) {
      for (int i = 0; i < 100; ++i) ASSERT_EQ(sched_getcpu(), cpu);
    }
  });
}

TEST(Realtime, InvalidRequestsAreRefusedWithAReason) {
  on_new_thread([] {
    for (const RealtimeRequest request : {RealtimeRequest{-3, -1}, RealtimeRequest{1000, -1}}) {
      const RealtimeResult r = make_current_thread_realtime(request);
      EXPECT_FALSE(r.fifo);
      EXPECT_NE(r.message.find("outside"), std::string::npos) << r.message;
    }
    for (const int cpu : {-2, CPU_SETSIZE, CPU_SETSIZE - 1}) {
      const RealtimeResult r = make_current_thread_realtime(RealtimeRequest{0, cpu});
      EXPECT_FALSE(r.pinned) << cpu;
      EXPECT_NE(r.message.find("not pinned"), std::string::npos) << r.message;
    }
  });
}

/// The calling thread's niceness (Linux keeps one per thread).
int thread_nice() { return getpriority(PRIO_PROCESS, static_cast<id_t>(gettid())); }

TEST(Realtime, ANiceRequestLowersThisThreadOnlyAndIsRefusedOutsideItsRange) {
  const int before = thread_nice();
  ASSERT_LT(before, 19) << "the test needs room to raise the niceness";
  on_new_thread([before] {
    const RealtimeResult r = make_current_thread_realtime(RealtimeRequest{0, -1, before + 1});
    EXPECT_FALSE(r.fifo);
    EXPECT_EQ(r.nice, before + 1);
    EXPECT_EQ(thread_nice(), before + 1);
    EXPECT_NE(r.message.find("nice " + std::to_string(before + 1)), std::string::npos) << r.message;
    // Without privileges a thread cannot become less nice: asking for less keeps what it has.
    const RealtimeResult kept = make_current_thread_realtime(RealtimeRequest{0, -1, before});
    EXPECT_EQ(kept.nice, before + 1);
    EXPECT_EQ(thread_nice(), before + 1);
    for (const int nice : {-1, 20}) {
      const RealtimeResult refused = make_current_thread_realtime(RealtimeRequest{0, -1, nice});
      EXPECT_NE(refused.message.find("outside 0–19"), std::string::npos) << refused.message;
      EXPECT_EQ(thread_nice(), before + 1);
    }
  });
  EXPECT_EQ(thread_nice(), before);
}

TEST(Realtime, ThreadNameIsTruncatedTo15Characters) {
  on_new_thread([] {
    name_current_thread("tactus-haptic-loop-1");
    char name[32] = {};
    ASSERT_EQ(pthread_getname_np(pthread_self(), name, sizeof(name)), 0);
    EXPECT_STREQ(name, "tactus-haptic-l");
    name_current_thread("sim");
    ASSERT_EQ(pthread_getname_np(pthread_self(), name, sizeof(name)), 0);
    EXPECT_STREQ(name, "sim");
    name_current_thread(nullptr);  // ignored
    ASSERT_EQ(pthread_getname_np(pthread_self(), name, sizeof(name)), 0);
    EXPECT_STREQ(name, "sim");
  });
}

TEST(Realtime, TimerSlackIsMinimizedForThisThreadOnly) {
  const int before = prctl(PR_GET_TIMERSLACK, 0, 0, 0, 0);
  on_new_thread([] {
    ASSERT_TRUE(minimize_timer_slack());
    EXPECT_EQ(prctl(PR_GET_TIMERSLACK, 0, 0, 0, 0), 1);
  });
  EXPECT_EQ(prctl(PR_GET_TIMERSLACK, 0, 0, 0, 0), before);
}

/// Kibibytes of locked memory of this process (VmLck in /proc/self/status); -1 if unknown.
long locked_kib() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmLck:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

TEST(Realtime, LockMemoryReportsWhetherPagesAreLocked) {
  // Granted or refused are both fine, but the answer must be true. Sanitizers intercept
  // mlockall (locking their shadow memory would take terabytes) and lock nothing.
  const bool locked = lock_memory();
  const long kib = locked_kib();
  if (locked) {
#ifndef TACTUS_SANITIZED
    if (kib >= 0) {
      EXPECT_GT(kib, 0);
    }
#endif
    EXPECT_EQ(munlockall(), 0);  // the rest of the test process runs unlocked
  } else if (kib >= 0) {
    EXPECT_EQ(kib, 0);
  }
}

#if defined(__GLIBC__) && !defined(TACTUS_SANITIZED)
long minor_faults() {
  rusage usage{};
  getrusage(RUSAGE_THREAD, &usage);
  return usage.ru_minflt;
}

/// Allocates `bytes`, writes each of its pages and frees it.
void touch_and_free(std::size_t bytes) {
  volatile char* block = static_cast<volatile char*>(std::malloc(bytes));
  ASSERT_NE(block, nullptr);
  for (std::size_t i = 0; i < bytes; i += 4096) block[i] = 1;
  std::free(const_cast<char*>(block));
}

TEST(Realtime, FreedMemoryIsKeptForTheNextAllocation) {
  ASSERT_TRUE(keep_freed_memory());
  // 8 MiB: glibc's default would map it on its own and unmap it when freed, and the next
  // 8 MiB (taken from the heap once its threshold has risen) would fault its 2,048 pages in.
  constexpr std::size_t kBytes = std::size_t{8} << 20;
  touch_and_free(kBytes);
  const long before = minor_faults();
  touch_and_free(kBytes);
  EXPECT_LT(minor_faults() - before, 64);
}
#else
TEST(Realtime, FreedMemoryIsKeptForTheNextAllocation) { GTEST_SKIP() << "the allocator is not glibc's"; }
#endif

}  // namespace
}  // namespace tactus
