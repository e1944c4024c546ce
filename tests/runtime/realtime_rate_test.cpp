// A real-time run measured on the wall clock. It runs alone (RUN_SERIAL), so that the rate it
// measures is the engine's and not that of the tests beside it.
#include <gtest/gtest.h>

#include <string>

#include "runtime/session.hpp"
#include "scene/scene.hpp"

namespace tactus::runtime {
namespace {

std::string notes(const SessionReport& r) {
  std::string text;
  for (const std::string& note : r.realtime_notes) text += note + "\n";
  return text;
}

TEST(RealtimeRate, TheHapticLoopKeepsItsRateWhileTheSimulationOverruns) {
#if defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "ThreadSanitizer slows every loop 5-15x: a rate test measures the sanitizer";
#endif
  // A block far too big for a 500 Hz simulation on this machine: every step overruns, and the
  // haptic loop must keep its 1 kHz on the last published surface.
  std::string text(scene::default_scene_text());
  text.replace(text.find("simulation = 100"), 16, "simulation = 500");
  text.replace(text.find("cells = [10, 10, 4]"), 19, "cells = [24, 24, 8]");
  const scene::Model m = scene::parse_scene(text, "overrun.toml");
  SessionOptions o;
  o.scheduling = Scheduling::real_time;
  o.duration = 1.5;
  const SessionReport r = run_session(m, o);
  const LoopStats& haptic = r.loops[0];
  const LoopStats& sim = r.loops[1];
  EXPECT_GT(sim.overruns, 0u) << "the simulation was meant to be too slow";
  EXPECT_LT(static_cast<double>(sim.steps), 0.9 * 500 * r.simulated_time);
  // Generous: a shared, possibly sanitized machine; a haptic loop tied to the simulation
  // would run at its rate (well under 500 Hz here).
  EXPECT_GT(static_cast<double>(haptic.steps), 0.6 * 1000 * r.simulated_time) << notes(r);
  // What lets the haptic loop win a shared core: a lower SCHED_FIFO priority for the
  // simulation, or off SCHED_FIFO a higher niceness.
  bool yields = false;
  for (const std::string& note : r.realtime_notes) {
    if (note.rfind("simulation: ", 0) != 0) continue;
    yields = note.find("SCHED_FIFO priority 70;") != std::string::npos || note.find("nice 10") != std::string::npos;
  }
  EXPECT_TRUE(yields) << notes(r);
}

}  // namespace
}  // namespace tactus::runtime
