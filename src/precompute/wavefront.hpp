#pragma once
// The order in which a space is built: a wavefront from the start point over the grid.
// Each point has a fixed list of candidate sources, its neighbours one grid edge closer to
// the start (the axis with the larger remaining offset first). A point becomes ready when
// its first candidate that has neither failed nor been tried is solved. A transition that
// fails is tried again from the next candidate (another path may go round what stopped the
// first: an element near inversion, a fold); the point fails only when every candidate it
// was tried from failed it, and is unreachable when no candidate was ever solved. The rule
// depends only on outcomes, not on timing, so any number of workers, in any order, builds
// the same space.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "precompute/grid.hpp"
#include "precompute/space.hpp"

namespace tactus::precompute {

struct Task {
  std::size_t point = 0;
  std::int64_t source = -1;  ///< -1: the start point, solved from rest
};

class Wavefront {
 public:
  /// `status`: what is known already (pending for a fresh build; a resumed build passes the
  /// journal's outcomes).
  Wavefront(const Grid& grid, std::size_t start, std::vector<PointStatus> status);

  /// A task whose source is solved, or nothing when none is ready now.
  std::optional<Task> next();
  /// Records a finished task's outcome (solved or failed). Returns whether the outcome is
  /// the point's last: false for a failure that is to be tried again from another candidate
  /// (the point stays pending; record nothing for it yet).
  bool complete(std::size_t point, PointStatus outcome);
  /// The source of point p's task out now (-1 for the start point, or before any; -2 while a
  /// failed point waits for its next candidate).
  [[nodiscard]] std::int64_t source_of(std::size_t p) const { return source_[p]; }
  /// Sources point p was tried from and failed, its latest task's included once it fails.
  [[nodiscard]] int failed_tries(std::size_t p) const;

  [[nodiscard]] std::size_t resolved() const { return resolved_; }  ///< not pending
  [[nodiscard]] std::size_t in_flight() const { return in_flight_; }
  [[nodiscard]] bool finished() const { return resolved_ == status_.size(); }
  [[nodiscard]] const std::vector<PointStatus>& status() const { return status_; }
  /// Points that became unreachable since the last call (to record them).
  std::vector<std::size_t> take_unreachable();

  /// Candidate sources of point p, in order of preference.
  [[nodiscard]] std::vector<std::size_t> candidates(std::size_t p) const;

 private:
  /// Queues p if it is ready, or marks it unreachable (and re-examines its dependants).
  void examine(std::size_t p);

  Grid grid_;
  std::size_t start_;
  std::vector<PointStatus> status_;
  std::vector<std::uint8_t> queued_;  ///< handed out or waiting in ready_
  std::vector<std::uint8_t> tried_;   ///< per point, bit k: a transition from candidate k failed
  std::vector<std::int64_t> source_;  ///< per point, the source of its latest task
  std::deque<Task> ready_;
  std::vector<std::size_t> unreachable_;
  std::size_t resolved_ = 0;
  std::size_t in_flight_ = 0;
};

}  // namespace tactus::precompute
