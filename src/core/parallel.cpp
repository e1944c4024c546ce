#include "core/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace tactus {
namespace {

/// True on pool workers and on a caller while it runs its own chunk: nested calls go serial.
thread_local bool t_inside_chunk = false;

/// How long both sides spin before blocking (set_spin_wait). Spinning saves the tens of
/// microseconds of a wake-up per dispatch, but only on cores nothing else wants: on a
/// shared, loaded machine a spinning worker steals the caller's time slices.
std::atomic<long> g_spin_us{0};

void pause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#else
  std::this_thread::yield();
#endif
}

/// Spins up to `spin` (default: the spin wait) until ready() holds; returns whether it did.
template <class Pred>
bool spin_until(Pred ready, std::chrono::microseconds spin = std::chrono::microseconds(g_spin_us.load(std::memory_order_relaxed))) {
  if (spin.count() <= 0) return ready();
  const auto deadline = std::chrono::steady_clock::now() + spin;
  for (int i = 0;; ++i) {
    if (ready()) return true;
    pause();
    if ((i & 63) == 63 && std::chrono::steady_clock::now() > deadline) return false;
  }
}

class Pool {
 public:
  explicit Pool(unsigned threads) : errors_(threads) {
    workers_.reserve(threads - 1);
    for (unsigned i = 1; i < threads; ++i) workers_.emplace_back([this, i] { work(i); });
  }
  Pool(const Pool&) = delete;
  Pool& operator=(const Pool&) = delete;
  ~Pool() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (auto& w : workers_) w.join();
  }

  [[nodiscard]] unsigned threads() const { return static_cast<unsigned>(workers_.size()) + 1; }

  /// Runs `chunks` chunks of [begin, end); chunk 0 on the caller.
  void run(std::size_t begin, std::size_t end, unsigned chunks, detail::ChunkFn fn, void* context) {
    begin_ = begin;
    end_ = end;
    chunks_ = chunks;
    fn_ = fn;
    context_ = context;
    pending_.store(static_cast<unsigned>(workers_.size()), std::memory_order_relaxed);
    {
      // The job fields above are published by this release; sleepers recheck under the lock.
      std::lock_guard lock(mutex_);
      generation_.fetch_add(1, std::memory_order_release);
    }
    wake_.notify_all();
    run_chunk(0);
    if (!spin_until([&] { return pending_.load(std::memory_order_acquire) == 0; })) {
      std::unique_lock lock(mutex_);
      done_.wait(lock, [&] { return pending_.load(std::memory_order_acquire) == 0; });
    }
    for (unsigned i = 0; i < chunks; ++i)
      if (errors_[i]) {
        std::exception_ptr e = std::move(errors_[i]);
        for (auto& other : errors_) other = nullptr;
        std::rethrow_exception(e);
      }
  }

 private:
  void run_chunk(unsigned index) {
    if (index >= chunks_) return;
    // Fixed chunk bounds: chunk i covers [begin + i n / k, begin + (i + 1) n / k).
    const std::size_t n = end_ - begin_;
    const std::size_t b = begin_ + n * index / chunks_, e = begin_ + n * (index + 1) / chunks_;
    const bool was_inside = std::exchange(t_inside_chunk, true);
    try {
      fn_(context_, b, e);
    } catch (...) {
      errors_[index] = std::current_exception();
    }
    t_inside_chunk = was_inside;
  }

  void work(unsigned index) {
    t_inside_chunk = true;
    std::uint64_t seen = 0;
    for (;;) {
      auto fresh = [&] { return generation_.load(std::memory_order_acquire) != seen; };
      if (!spin_until(fresh)) {
        std::unique_lock lock(mutex_);
        wake_.wait(lock, [&] { return stop_ || fresh(); });
        if (stop_) return;
      }
      seen = generation_.load(std::memory_order_acquire);
      run_chunk(index);
      if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
        std::lock_guard lock(mutex_);  // the caller may be between its check and its wait
        done_.notify_one();
      }
    }
  }

  std::vector<std::thread> workers_;
  std::vector<std::exception_ptr> errors_;  ///< one per chunk, so no lock is needed
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<unsigned> pending_{0};
  bool stop_ = false;
  // The current job, written by the caller before it bumps generation_.
  std::size_t begin_ = 0, end_ = 0;
  unsigned chunks_ = 0;
  detail::ChunkFn fn_ = nullptr;
  void* context_ = nullptr;
};

}  // namespace

void Team::sync() {
  if (members_ <= 1) return;
  const std::uint32_t round = round_.load(std::memory_order_acquire);
  if (arrived_.fetch_add(1, std::memory_order_acq_rel) + 1 == members_) {
    // The last to arrive opens the next round; the release publishes every member's writes.
    arrived_.store(0, std::memory_order_relaxed);
    round_.fetch_add(1, std::memory_order_acq_rel);
    round_.notify_all();
    return;
  }
  // A phase between two syncs lasts tens of microseconds: spin about that long (a wake-up
  // from a futex costs as much), then block.
  auto opened = [&] { return round_.load(std::memory_order_acquire) != round; };
  if (spin_until(opened, std::chrono::microseconds(50))) return;
  while (!opened()) round_.wait(round, std::memory_order_acquire);
}

namespace {

unsigned default_threads(unsigned limit) {
  const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
  return limit == 0 ? hardware : std::min(limit, hardware);
}

struct Global {
  std::mutex dispatch;  ///< one parallel_for at a time; others run serially
  std::unique_ptr<Pool> pool = std::make_unique<Pool>(default_threads(0));
};

Global& global() {
  static Global g;
  return g;
}

}  // namespace

void set_thread_limit(unsigned limit) {
  Global& g = global();
  std::lock_guard lock(g.dispatch);
  const unsigned threads = default_threads(limit);
  if (g.pool->threads() != threads) {
    g.pool.reset();
    g.pool = std::make_unique<Pool>(threads);
  }
}

unsigned thread_count() { return global().pool->threads(); }

void set_spin_wait(std::chrono::microseconds wait) { g_spin_us.store(static_cast<long>(wait.count())); }

namespace detail {

void run_team(unsigned wanted, MemberFn fn, void* context) {
  Global& g = global();
  if (!t_inside_chunk && wanted > 1 && g.pool->threads() > 1) {
    std::unique_lock lock(g.dispatch, std::try_to_lock);
    if (lock.owns_lock()) {
      const unsigned members = std::min(g.pool->threads(), wanted);
      Team team(members);
      struct Call {
        MemberFn fn;
        void* context;
        Team* team;
      } call{fn, context, &team};
      // One chunk per member over [0, members): chunk i is member i.
      g.pool->run(0, members, members, [](void* c, std::size_t member, std::size_t) {
        const auto* job = static_cast<Call*>(c);
        job->fn(job->context, static_cast<unsigned>(member), *job->team);
      }, &call);
      return;
    }
  }
  Team alone(1);
  fn(context, 0, alone);
}

void run_parallel(std::size_t begin, std::size_t end, std::size_t min_chunk, ChunkFn fn, void* context) {
  if (end <= begin) return;
  const std::size_t n = end - begin;
  min_chunk = std::max<std::size_t>(min_chunk, 1);
  Global& g = global();
  if (!t_inside_chunk && n >= 2 * min_chunk && g.pool->threads() > 1) {
    std::unique_lock lock(g.dispatch, std::try_to_lock);
    if (lock.owns_lock()) {
      const auto chunks = static_cast<unsigned>(std::min<std::size_t>(g.pool->threads(), n / min_chunk));
      g.pool->run(begin, end, chunks, fn, context);
      return;
    }
  }
  fn(context, begin, end);
}

}  // namespace detail

}  // namespace tactus
