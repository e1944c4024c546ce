#include "core/child_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <system_error>

#include "core/progress.hpp"

namespace tactus {
namespace {

bool write_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

[[noreturn]] void child_main(int fd, const std::function<std::string()>& work, const ChildLimits& limits) {
  if (limits.memory_bytes > 0) {
    const rlimit cap{limits.memory_bytes, limits.memory_bytes};
    ::setrlimit(RLIMIT_AS, &cap);
  }
  int code = 0;
  try {
    const std::string out = work();
    if (!write_all(fd, out.data(), out.size())) code = 2;
  } catch (...) {
    code = 3;
  }
  // No exit handlers or stream flushes: they belong to the parent.
  ::_exit(code);
}

/// Kills (if asked) and reaps the child and closes the pipe, whichever way the wait ends.
struct ChildGuard {
  pid_t pid;
  int fd;
  bool reaped = false;
  int status = 0;

  void reap(bool kill_first) {
    if (reaped) return;
    if (kill_first) ::kill(pid, SIGKILL);
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    reaped = true;
  }
  ~ChildGuard() {
    if (fd >= 0) ::close(fd);
    reap(true);
  }
};

}  // namespace

ChildResult run_in_child(const std::function<std::string()>& work, const ChildLimits& limits) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw std::system_error(errno, std::generic_category(), "pipe");
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw std::system_error(err, std::generic_category(), "fork");
  }
  if (pid == 0) {
    ::close(fds[0]);
    child_main(fds[1], work, limits);
  }
  ::close(fds[1]);
  ChildGuard child{pid, fds[0]};

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const bool bounded = limits.seconds > 0.0;
  const auto deadline = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(limits.seconds));
  // Progress in tenths of a second of the allowed time (or of a notional ten minutes).
  const double shown_total = bounded ? limits.seconds : 600.0;
  std::unique_ptr<Progress> progress;
  if (!limits.progress_label.empty())
    progress = std::make_unique<Progress>(limits.progress_label, static_cast<std::size_t>(shown_total * 10.0) + 1);

  ChildResult result;
  char buffer[1 << 16];
  for (;;) {
    int wait_ms = 200;
    if (bounded) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
      if (left <= 0) {
        child.reap(true);
        if (progress) progress->finish();
        result.outcome = ChildOutcome::timed_out;
        return result;
      }
      wait_ms = static_cast<int>(std::min<long long>(left, 200));
    }
    pollfd p{child.fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, wait_ms);
    if (ready < 0 && errno != EINTR) throw std::system_error(errno, std::generic_category(), "poll");
    if (ready > 0) {
      const ssize_t n = ::read(child.fd, buffer, sizeof buffer);
      if (n == 0) break;  // the child closed its end: done
      if (n < 0 && errno != EINTR && errno != EAGAIN)
        throw std::system_error(errno, std::generic_category(), "read");
      if (n > 0) result.output.append(buffer, static_cast<std::size_t>(n));
    }
    if (progress) {
      const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
      progress->update(static_cast<std::size_t>(std::min(elapsed, shown_total) * 10.0));
    }
  }
  child.reap(false);
  if (progress) progress->finish();
  if (WIFSIGNALED(child.status)) {
    result.signal = WTERMSIG(child.status);
    result.outcome = ChildOutcome::failed;
  } else {
    result.outcome = WIFEXITED(child.status) && WEXITSTATUS(child.status) == 0 ? ChildOutcome::finished
                                                                               : ChildOutcome::failed;
  }
  return result;
}

}  // namespace tactus
