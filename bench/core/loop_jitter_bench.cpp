// How late a fixed-rate loop wakes up: runs a loop (1 kHz by default) for N seconds per mode
// and prints lateness percentiles (wake-up time minus deadline) in microseconds:
//   sleep        clock_nanosleep to the absolute deadline
//   sleep+spin   sleep until deadline − spin window, then busy-wait
// each with the default timer slack (Linux may delay a normal thread's wake-up by up to
// 50 µs to batch timers) and with minimize_timer_slack(), then
//   fifo+sleep   as sleep, on a SCHED_FIFO thread (skipped when not permitted)
//   fifo+spin    as sleep+spin, on a SCHED_FIFO thread
// Each mode runs on its own thread; CPU % is that thread's CPU time over the run.
#include <CLI/CLI.hpp>
#include <sys/resource.h>
#include <sys/utsname.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "core/clock.hpp"
#include "core/histogram.hpp"
#include "core/realtime.hpp"

namespace tactus {
namespace {

struct Options {
  double seconds = 5.0;
  double rate_hz = 1000.0;
  double spin_us = 50.0;
  int priority = 80;
  int cpu = -1;
};

struct Mode {
  const char* name;
  bool spin;
  bool min_slack;
  bool fifo;
};

struct ModeResult {
  bool ran = false;
  std::string note;
  LatencySummary lateness;
  std::int64_t skipped_periods = 0;
  double cpu_percent = 0.0;
};

Nanos thread_cpu_ns() {
  rusage usage{};
  getrusage(RUSAGE_THREAD, &usage);
  const auto to_ns = [](const timeval& t) { return Nanos{t.tv_sec} * kNanosPerSecond + Nanos{t.tv_usec} * 1000; };
  return to_ns(usage.ru_utime) + to_ns(usage.ru_stime);
}

ModeResult run_mode(const Options& o, const Mode& mode) {
  ModeResult result;
  std::thread loop([&] {
    name_current_thread("bench-jitter");
    const RealtimeResult rt = make_current_thread_realtime(RealtimeRequest{mode.fifo ? o.priority : 0, o.cpu});
    result.note = rt.message;
    if (mode.fifo && !rt.fifo) return;  // not permitted: reported, not measured
    if (mode.min_slack && !minimize_timer_slack()) {
      result.note = "timer slack could not be changed";
      return;
    }

    const auto period = static_cast<Nanos>(1e9 / o.rate_hz);
    const Nanos spin = mode.spin ? static_cast<Nanos>(o.spin_us * 1e3) : 0;
    const auto iterations = static_cast<std::int64_t>(o.seconds * o.rate_hz);
    LatencyHistogram lateness;
    LoopTimer timer(period, now_ns() + period);
    const Nanos cpu_start = thread_cpu_ns();
    const Nanos wall_start = now_ns();
    for (std::int64_t i = 0; i < iterations; ++i) lateness.record(timer.wait(spin));
    const Nanos wall = now_ns() - wall_start;
    result.cpu_percent = 100.0 * static_cast<double>(thread_cpu_ns() - cpu_start) / static_cast<double>(wall);
    result.lateness = summarize(lateness);
    result.skipped_periods = timer.skipped_periods();
    result.ran = true;
    // Back to the normal scheduler before the thread ends (it ends right away anyway).
    make_current_thread_realtime(RealtimeRequest{});
  });
  loop.join();
  return result;
}

std::string first_line_with(const char* path, const std::string& key) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) return line.substr(line.find(':') + 1);
  return "";
}

std::string read_line(const char* path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

double us(Nanos ns) { return static_cast<double>(ns) / 1e3; }

}  // namespace
}  // namespace tactus

int main(int argc, char** argv) {
  using namespace tactus;
  Options o;
  CLI::App app("Wake-up lateness of a fixed-rate loop: plain sleep, sleep-then-spin, SCHED_FIFO");
  app.add_option("--seconds", o.seconds, "Seconds per mode")->check(CLI::Range(0.01, 3600.0));
  app.add_option("--rate", o.rate_hz, "Loop rate [Hz]")->check(CLI::Range(1.0, 100'000.0));
  app.add_option("--spin-us", o.spin_us, "Spin window of the sleep+spin modes [µs]")->check(CLI::Range(0.0, 1e6));
  app.add_option("--priority", o.priority, "SCHED_FIFO priority of the fifo modes")->check(CLI::Range(1, 99));
  app.add_option("--cpu", o.cpu, "Pin the loop thread to this CPU (-1: no pinning)")->check(CLI::Range(-1, 1023));
  CLI11_PARSE(app, argc, argv);

  utsname host{};
  uname(&host);
  std::printf("# %s %s, %u CPUs,%s; load average at start: %s\n", host.sysname, host.release,
              std::thread::hardware_concurrency(), first_line_with("/proc/cpuinfo", "model name").c_str(),
              read_line("/proc/loadavg").c_str());
  std::printf("# %.0f Hz loop, %.1f s per mode, spin window %.0f µs, FIFO priority %d, CPU %d\n\n", o.rate_hz,
              o.seconds, o.spin_us, o.priority, o.cpu);

  const Mode modes[] = {{"sleep", false, false, false},           {"sleep+spin", true, false, false},
                        {"sleep, slack 1 ns", false, true, false}, {"sleep+spin, slack 1 ns", true, true, false},
                        {"fifo+sleep", false, false, true},       {"fifo+spin", true, false, true}};
  std::vector<std::string> notes;
  std::printf("| mode | wake-ups | p50 µs | p99 µs | p99.9 µs | max µs | mean µs | skipped periods | CPU %% |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (const Mode& mode : modes) {
    const ModeResult r = run_mode(o, mode);
    if (!r.ran) {
      std::printf("| %s | not run | | | | | | | |\n", mode.name);
      notes.push_back(std::string(mode.name) + ": " + r.note);
      continue;
    }
    const LatencySummary& s = r.lateness;
    std::printf("| %s | %llu | %.1f | %.1f | %.1f | %.1f | %.1f | %lld | %.1f |\n", mode.name,
                static_cast<unsigned long long>(s.count), us(s.p50), us(s.p99), us(s.p999), us(s.max), s.mean / 1e3,
                static_cast<long long>(r.skipped_periods), r.cpu_percent);
    std::fflush(stdout);
  }
  for (const std::string& note : notes) std::printf("\n%s\n", note.c_str());
  std::printf("\n# load average at end: %s\n", read_line("/proc/loadavg").c_str());
  return 0;
}
