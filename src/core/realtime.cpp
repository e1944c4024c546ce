#include "core/realtime.hpp"

#include <malloc.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

namespace tactus {
namespace {

std::string error_text(int code) { return std::error_code(code, std::generic_category()).message(); }

/// Sets the scheduling policy; returns a description of the outcome.
std::string apply_priority(int priority, bool& fifo) {
  const pthread_t self = pthread_self();
  if (priority == 0) {
    int policy = SCHED_OTHER;
    sched_param param{};
    if (pthread_getschedparam(self, &policy, &param) == 0 && (policy == SCHED_FIFO || policy == SCHED_RR)) {
      param.sched_priority = 0;
      const int rc = pthread_setschedparam(self, SCHED_OTHER, &param);
      if (rc != 0) return "could not return to the normal scheduler: " + error_text(rc);
    }
    return "normal scheduler";
  }
  const int lowest = sched_get_priority_min(SCHED_FIFO);
  const int highest = sched_get_priority_max(SCHED_FIFO);
  if (priority < lowest || priority > highest) {
    return "SCHED_FIFO priority " + std::to_string(priority) + " is outside " + std::to_string(lowest) + "–" +
           std::to_string(highest) + "; normal scheduler kept";
  }
  sched_param param{};
  param.sched_priority = priority;
  const int rc = pthread_setschedparam(self, SCHED_FIFO, &param);
  if (rc == 0) {
    fifo = true;
    return "SCHED_FIFO priority " + std::to_string(priority);
  }
  std::string why = "SCHED_FIFO priority " + std::to_string(priority) + " refused (" + error_text(rc) + ")";
  if (rc == EPERM) {
    why += ": needs CAP_SYS_NICE or an rtprio limit of at least " + std::to_string(priority) +
           " (see docs/realtime.md)";
  }
  return why + "; normal scheduler kept";
}

/// The calling thread's niceness (Linux keeps one per thread).
int current_nice() {
  errno = 0;
  const int nice = getpriority(PRIO_PROCESS, static_cast<id_t>(gettid()));
  return errno == 0 ? nice : 0;
}

/// Raises the thread's niceness to `nice`; returns a description of the outcome.
std::string apply_nice(int nice) {
  if (nice < 0 || nice > 19) return "nice " + std::to_string(nice) + " is outside 0–19; not changed";
  const int current = current_nice();
  if (nice <= current) return "nice " + std::to_string(current);
  if (setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), nice) != 0) {
    return "nice " + std::to_string(nice) + " refused (" + error_text(errno) + ")";
  }
  return "nice " + std::to_string(nice);
}

/// Pins the thread to one CPU; returns a description of the outcome.
std::string apply_pinning(int cpu, bool& pinned) {
  if (cpu == -1) return "no CPU pinning";
  if (cpu < 0 || cpu >= CPU_SETSIZE) {
    return "CPU " + std::to_string(cpu) + " does not exist (0–" + std::to_string(CPU_SETSIZE - 1) + "); not pinned";
  }
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(static_cast<std::size_t>(cpu), &set);
  const int rc = pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
  if (rc == 0) {
    pinned = true;
    return "pinned to CPU " + std::to_string(cpu);
  }
  if (rc == EINVAL) return "CPU " + std::to_string(cpu) + " is offline or outside this process's CPU set; not pinned";
  return "pinning to CPU " + std::to_string(cpu) + " refused (" + error_text(rc) + "); not pinned";
}

}  // namespace

RealtimeResult make_current_thread_realtime(const RealtimeRequest& request) {
  RealtimeResult result;
  try {
    result.message = apply_priority(request.priority, result.fifo);
    if (!result.fifo && request.nice != 0) result.message += "; " + apply_nice(request.nice);
    result.nice = current_nice();
    result.message += "; " + apply_pinning(request.cpu, result.pinned);
  } catch (...) {
    // Only the message can fail (out of memory); what was applied is still reported.
  }
  return result;
}

bool lock_memory() { return mlockall(MCL_CURRENT | MCL_FUTURE) == 0; }

bool keep_freed_memory() {
#if defined(__GLIBC__)
  // 32 MiB is the largest mapping threshold glibc accepts on 64-bit systems.
  return mallopt(M_MMAP_THRESHOLD, 32 << 20) == 1 && mallopt(M_TRIM_THRESHOLD, 256 << 20) == 1;
#else
  return false;
#endif
}

bool minimize_timer_slack() { return prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL) == 0; }

void name_current_thread(const char* name) {
  if (name == nullptr) return;
  char truncated[16] = {};
  std::strncpy(truncated, name, sizeof(truncated) - 1);
  pthread_setname_np(pthread_self(), truncated);
}

}  // namespace tactus
