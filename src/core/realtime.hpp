#pragma once
// Real-time scheduling for the calling thread: SCHED_FIFO priority, CPU pinning, locked
// memory and a thread name for tools like top and perf. Each call reports what it obtained
// and falls back to the normal scheduler when the process is not allowed more (no
// CAP_SYS_NICE, no rtprio limit): a loop then runs, only with more jitter.
#include <string>

namespace tactus {

struct RealtimeRequest {
  int priority = 0;  ///< SCHED_FIFO priority 1–99; 0 = normal scheduler
  int cpu = -1;      ///< CPU to pin to; -1 = no pinning
  /// Niceness (0–19) for a thread left on the normal scheduler. A loop that may overrun (the
  /// simulation) runs nicer than the haptic loop, so on a shared core the haptic loop wins.
  /// Raising it needs no privilege; it is never lowered again for this thread.
  int nice = 0;
};

struct RealtimeResult {
  bool fifo = false;    ///< the thread now runs under SCHED_FIFO at the requested priority
  bool pinned = false;  ///< the thread now runs on the requested CPU only
  int nice = 0;         ///< the thread's niceness now
  std::string message;  ///< what was obtained, and why not when something was refused
};

/// Applies `request` to the calling thread. Never throws; what was refused stays as it was
/// (priority 0 returns a real-time thread to the normal scheduler).
RealtimeResult make_current_thread_realtime(const RealtimeRequest& request);

/// Locks the process's current and future pages in RAM (mlockall), so a loop never waits on
/// a page fault to disk. False when not permitted (RLIMIT_MEMLOCK, no CAP_IPC_LOCK).
bool lock_memory();

/// Keeps the memory the process frees for its next allocations (glibc's malloc: blocks up to
/// 32 MiB from the heap, not from a mapping of their own, and up to 256 MiB of free heap kept).
/// A solve or step that allocates what an earlier one freed then takes pages already mapped,
/// where it would fault each page in again (a few µs a page, over 10 µs on a virtual machine),
/// and a loop's frees unmap nothing, so the other loops' cores see no TLB shootdowns. Process
/// wide: `tactus` calls it first thing. False where the allocator is not glibc's or refused.
bool keep_freed_memory();

/// Lets the kernel wake the calling thread's timed sleeps on time: sets its timer slack to
/// 1 ns instead of the default 50 µs that Linux may add to batch wake-ups (SCHED_FIFO
/// threads have no slack anyway). Allowed without privileges; false if the kernel refused.
bool minimize_timer_slack();

/// Names the calling thread; Linux keeps the first 15 characters.
void name_current_thread(const char* name);

}  // namespace tactus
