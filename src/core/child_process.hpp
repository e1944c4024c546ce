#pragma once
// Running work that may not end (a third-party mesher on a hard input) in a forked child
// process, so that a deadline or a memory cap can stop it without leaving the caller's
// memory in an unknown state. The child's result comes back as bytes through a pipe.
#include <cstddef>
#include <functional>
#include <string>

namespace tactus {

struct ChildLimits {
  double seconds = 0.0;           ///< wall-clock deadline; 0 = none
  std::size_t memory_bytes = 0;   ///< the child's address-space cap (RLIMIT_AS); 0 = none
  std::string progress_label;     ///< shown while waiting (see core/progress.hpp); empty = none
};

enum class ChildOutcome {
  finished,   ///< work() returned; `output` holds its bytes
  timed_out,  ///< killed at the deadline
  failed,     ///< work() threw (std::bad_alloc included) or the child died of a signal
};

struct ChildResult {
  ChildOutcome outcome = ChildOutcome::failed;
  std::string output;
  int signal = 0;  ///< the signal that ended the child, if one did
};

/// Runs `work` in a child process under `limits` and waits for it: the child is always
/// reaped (killed first at the deadline), the pipe always closed. Meant for
/// single-threaded work that touches no shared state (files, sockets) while it runs.
ChildResult run_in_child(const std::function<std::string()>& work, const ChildLimits& limits);

}  // namespace tactus
