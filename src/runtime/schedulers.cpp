#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "core/progress.hpp"
#include "core/realtime.hpp"
#include "runtime/loop_set.hpp"

namespace tactus::runtime {
namespace {

/// The slower loops need no sub-millisecond timing: they spin only briefly.
constexpr Nanos kOtherLoopSpin = 20'000;

double run_length(const SessionOptions& o) { return o.duration > 0.0 ? o.duration : o.max_duration; }

}  // namespace

void lockstep_catch_up(const scene::Model& m, Loops& loops, Recorder& recorder, LockstepCursor& c, double t) {
  const double sim_rate = m.rates.simulation, inter_rate = m.rates.interaction;
  while (static_cast<double>(c.simulation_steps) / sim_rate <= t) {
    const Nanos now = now_ns();
    loops.simulation->step(static_cast<double>(c.simulation_steps) / sim_rate, now, now, false);
    ++c.simulation_steps;
    recorder.drain();
  }
  while (static_cast<double>(c.interaction_steps) / inter_rate <= t) {
    const Nanos now = now_ns();
    loops.interaction->step(static_cast<double>(c.interaction_steps) / inter_rate, now, now, false);
    ++c.interaction_steps;
  }
}

void lockstep_haptic_frames(Loops& loops, double t) {
  for (auto& h : loops.haptic) {
    const Nanos now = now_ns();
    h->step(t, now, now, false);
  }
}

void run_lockstep(const scene::Model& m, const SessionOptions& o, Loops& loops, Recorder& recorder,
                  SessionReport& report) {
  const double end = run_length(o);
  const double haptic_rate = m.rates.haptic;
  LockstepCursor cursor;
  bool stopped = false;
  double t = 0.0;
  std::optional<Progress> progress;
  const auto total_steps = static_cast<std::uint64_t>(std::floor(end * haptic_rate + 1e-9)) + 1;
  if (!o.progress.empty()) progress.emplace(o.progress, total_steps);
  // Times are integer multiples of each period (k / rate), never accumulated sums, so
  // every run visits the same instants in the same order.
  for (std::uint64_t k = 0;; ++k) {
    t = static_cast<double>(k) / haptic_rate;
    if (t > end + 1e-12) break;
    lockstep_catch_up(m, loops, recorder, cursor, t);
    if (o.emergency_stop_at && !stopped && t >= *o.emergency_stop_at) {
      for (auto& h : loops.haptic) h->request_emergency_stop();
      stopped = true;
    }
    lockstep_haptic_frames(loops, t);
    if (progress && (k & 63) == 0) progress->update(k);
    if (o.duration <= 0.0 && loops.all_finished(t)) break;
    if (o.interrupt && (k & 63) == 0 && o.interrupt->load()) break;
  }
  if (progress) progress->finish();
  report.simulated_time = t;
}

void run_real_time(const scene::Model& m, const SessionOptions& o, Loops& loops, Recorder& recorder,
                   SessionReport& report) {
  std::atomic<bool> stop{false};
  std::atomic<std::size_t> finished{0};
  std::exception_ptr failure;
  std::mutex mutex;  // guards failure and the notes; never taken inside a loop's steady state
  const Nanos t0 = now_ns() + 20'000'000;  // every loop starts on the same first deadline
  const int priority = o.realtime_priority.value_or(m.realtime.priority);
  const int low_priority = priority > 10 ? priority - 10 : 0;
  // Off SCHED_FIFO the other loops run nicer than the haptic threads: a simulation step that
  // overruns then takes what the haptic loop leaves of a shared core, not half of it.
  constexpr int kOtherLoopNice = 10;
  const int haptic_cpu = o.haptic_cpu.value_or(m.realtime.haptic_cpu);
  const auto haptic_period = static_cast<Nanos>(std::llround(1e9 / m.rates.haptic));
  // A dedicated core spins through the whole period: the wait never sleeps.
  const Nanos haptic_spin = m.realtime.dedicated_core && !o.spin_window
                                ? haptic_period
                                : o.spin_window.value_or(static_cast<Nanos>(std::llround(m.realtime.spin * 1e9)));

  auto run_loop = [&](const std::string& name, double rate, RealtimeRequest request, Nanos spin, auto&& step) {
    name_current_thread(name.c_str());
    minimize_timer_slack();  // else timed wake-ups may come up to 50 µs late
    const RealtimeResult rt = make_current_thread_realtime(request);
    {
      std::lock_guard lock(mutex);
      report.realtime_notes.push_back(name + ": " + rt.message);
    }
    LoopTimer timer(static_cast<Nanos>(std::llround(1e9 / rate)), t0);
    try {
      while (!stop.load(std::memory_order_relaxed)) {
        const Nanos deadline = timer.deadline();
        timer.wait(spin);
        const Nanos start = now_ns();
        // The period's number over the rate: the very instants a lockstep run visits (a
        // scaled nanosecond count rounds differently, and a lockstep replay of this run's
        // recording would then read each pose one frame late).
        const std::int64_t period_index = (deadline - t0) / timer.period();
        step(static_cast<double>(period_index) / rate, deadline, start);
      }
    } catch (...) {
      std::lock_guard lock(mutex);
      if (!failure) failure = std::current_exception();
      stop = true;
    }
  };

  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < loops.haptic.size(); ++i) {
    threads.emplace_back([&, i] {
      HapticLoop& h = *loops.haptic[i];
      bool done = false;
      run_loop(fmt::format("haptic{}", i), m.rates.haptic, RealtimeRequest{priority, haptic_cpu}, haptic_spin,
               [&](double t, Nanos deadline, Nanos start) {
                 h.step(t, deadline, start, true);
                 if (!done && h.finished(t)) {
                   done = true;
                   finished.fetch_add(1);
                 }
               });
    });
  }
  threads.emplace_back([&] {
    run_loop("simulation", m.rates.simulation, RealtimeRequest{low_priority, -1, kOtherLoopNice}, kOtherLoopSpin,
             [&](double t, Nanos deadline, Nanos start) { loops.simulation->step(t, deadline, start, true); });
  });
  threads.emplace_back([&] {
    run_loop("interaction", m.rates.interaction, RealtimeRequest{low_priority, -1, kOtherLoopNice}, kOtherLoopSpin,
             [&](double t, Nanos deadline, Nanos start) { loops.interaction->step(t, deadline, start, true); });
  });
  // The recorder runs on this thread: it drains the rings and decides when to stop.
  const double end = run_length(o);
  bool stopped = false;
  Nanos last_flush = now_ns();
  double t = 0.0;
  while (!stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    const Nanos now = now_ns();
    t = static_cast<double>(now - t0) * 1e-9;
    recorder.drain();
    if (now - last_flush > 50'000'000) {  // at most 50 ms of frames lost to a crash
      recorder.flush();
      last_flush = now;
    }
    if (o.emergency_stop_at && !stopped && t >= *o.emergency_stop_at) {
      for (auto& h : loops.haptic) h->request_emergency_stop();
      stopped = true;
    }
    if (t >= end || (o.duration <= 0.0 && finished.load() == loops.haptic.size())) stop = true;
    if (o.interrupt && o.interrupt->load()) stop = true;
  }
  // The run ends when the stop is decided, not when the last thread has finished its step
  // (a long simulation step may still be running).
  report.simulated_time = t;
  for (auto& th : threads) th.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace tactus::runtime
