#include "precompute/wavefront.hpp"

#include <algorithm>
#include <bit>
#include <cstdlib>

namespace tactus::precompute {

Wavefront::Wavefront(const Grid& grid, std::size_t start, std::vector<PointStatus> status)
    : grid_(grid), start_(start), status_(std::move(status)) {
  status_.resize(grid_.size(), PointStatus::pending);
  queued_.assign(status_.size(), 0);
  tried_.assign(status_.size(), 0);
  source_.assign(status_.size(), -1);
  for (auto s : status_) resolved_ += s != PointStatus::pending;
  if (status_[start_] == PointStatus::pending) {
    ready_.push_back({start_, -1});
    queued_[start_] = 1;
  } else {
    // Points in order of their distance from the start, so that an unreachable point is
    // found before the points that depend on it are examined.
    const auto s = grid_.cell(start_);
    std::vector<std::size_t> order(status_.size());
    for (std::size_t p = 0; p < order.size(); ++p) order[p] = p;
    auto distance = [&](std::size_t p) {
      const auto c = grid_.cell(p);
      return std::abs(c[0] - s[0]) + std::abs(c[1] - s[1]) + std::abs(c[2] - s[2]);
    };
    std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return distance(a) < distance(b); });
    for (auto p : order)
      if (status_[p] == PointStatus::pending) examine(p);
  }
}

std::vector<std::size_t> Wavefront::candidates(std::size_t p) const {
  const auto c = grid_.cell(p);
  const auto s = grid_.cell(start_);
  int axes[3] = {0, 1, 2};
  // The axis with the larger remaining offset first: paths run close to the straight line
  // from the start.
  std::stable_sort(axes, axes + 3, [&](int a, int b) {
    return std::abs(c[static_cast<std::size_t>(a)] - s[static_cast<std::size_t>(a)]) >
           std::abs(c[static_cast<std::size_t>(b)] - s[static_cast<std::size_t>(b)]);
  });
  std::vector<std::size_t> out;
  for (int a : axes) {
    const auto ua = static_cast<std::size_t>(a);
    const int offset = c[ua] - s[ua];
    if (offset == 0) continue;
    auto n = c;
    n[ua] += offset > 0 ? -1 : 1;
    out.push_back(grid_.index(n[0], n[1], n[2]));
  }
  return out;
}

void Wavefront::examine(std::size_t first) {
  // A work list rather than recursion: a failure can make a long chain unreachable.
  std::vector<std::size_t> work{first};
  while (!work.empty()) {
    const std::size_t p = work.back();
    work.pop_back();
    if (status_[p] != PointStatus::pending || queued_[p] || p == start_) continue;
    bool waiting = false;
    const std::vector<std::size_t> from = candidates(p);
    for (std::size_t k = 0; k < from.size(); ++k) {
      const std::size_t q = from[k];
      if (tried_[p] & (1u << k)) continue;
      if (status_[q] == PointStatus::solved) {
        ready_.push_back({p, static_cast<std::int64_t>(q)});
        queued_[p] = 1;
        source_[p] = static_cast<std::int64_t>(q);
        waiting = true;
        break;
      }
      if (status_[q] == PointStatus::pending) {
        waiting = true;
        break;
      }
    }
    if (waiting) continue;
    // Every candidate failed, or was tried and failed this point: it is done.
    status_[p] = tried_[p] ? PointStatus::failed : PointStatus::unreachable;
    ++resolved_;
    if (status_[p] == PointStatus::unreachable) unreachable_.push_back(p);
    // Its dependants may now be unreachable, or ready from their next candidate.
    const auto c = grid_.cell(p);
    for (int a = 0; a < 3; ++a)
      for (int d : {-1, 1}) {
        auto n = c;
        n[static_cast<std::size_t>(a)] += d;
        if (grid_.contains(n[0], n[1], n[2])) work.push_back(grid_.index(n[0], n[1], n[2]));
      }
  }
}

std::optional<Task> Wavefront::next() {
  if (ready_.empty()) return std::nullopt;
  const Task t = ready_.front();
  ready_.pop_front();
  ++in_flight_;
  return t;
}

bool Wavefront::complete(std::size_t p, PointStatus outcome) {
  if (in_flight_ > 0) --in_flight_;
  if (outcome == PointStatus::failed && p != start_ && status_[p] == PointStatus::pending) {
    // Try the next candidate: examine() queues it, waits for it, or ends the point.
    const std::vector<std::size_t> from = candidates(p);
    for (std::size_t k = 0; k < from.size(); ++k)
      if (static_cast<std::int64_t>(from[k]) == source_[p]) tried_[p] |= static_cast<std::uint8_t>(1u << k);
    queued_[p] = 0;
    source_[p] = -2;  // no task out for it until examine() queues one: a late answer matches none
    examine(p);
    // Pending: queued again or waiting for a candidate. Otherwise no candidate was left and
    // examine() has recorded it failed and re-examined its neighbours.
    return status_[p] != PointStatus::pending;
  }
  if (status_[p] == PointStatus::pending) ++resolved_;
  status_[p] = outcome;
  const auto c = grid_.cell(p);
  for (int a = 0; a < 3; ++a)
    for (int d : {-1, 1}) {
      auto n = c;
      n[static_cast<std::size_t>(a)] += d;
      if (grid_.contains(n[0], n[1], n[2])) examine(grid_.index(n[0], n[1], n[2]));
    }
  return true;
}

int Wavefront::failed_tries(std::size_t p) const { return std::popcount(tried_[p]); }

std::vector<std::size_t> Wavefront::take_unreachable() {
  std::vector<std::size_t> out;
  out.swap(unreachable_);
  return out;
}

}  // namespace tactus::precompute
