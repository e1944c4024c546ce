#include "runtime/session.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

#include "core/error.hpp"
#include "core/realtime.hpp"
#include "core/version.hpp"
#include "runtime/haptic_loop.hpp"
#include "runtime/interaction_loop.hpp"
#include "runtime/recording_writer.hpp"
#include "runtime/simulation_loop.hpp"

namespace tactus::runtime {
namespace {

constexpr std::size_t kFrameRingCapacity = 1 << 15;
/// The slower loops need no sub-millisecond timing: they spin only briefly.
constexpr Nanos kOtherLoopSpin = 20'000;

/// The tool a device drives, and which of its fingers when the tool has two.
struct DrivenTool {
  const scene::Tool* tool = nullptr;
  std::size_t finger = 0;
};

DrivenTool tool_of(const scene::Model& m, std::size_t device) {
  for (const scene::Tool& tool : m.tools)
    for (std::size_t k = 0; k < tool.devices.size(); ++k)
      if (tool.devices[k] == device) return {&tool, k};
  return {};
}

const scene::Algorithm* algorithm_of(const scene::Model& m, const scene::Tool& tool) {
  for (const scene::Algorithm& a : m.algorithms)
    if (a.enabled && &m.tools[a.tool] == &tool) return &a;
  return nullptr;
}

std::vector<std::size_t> bodies_of(const scene::Model& m, const scene::Algorithm& a) {
  if (!a.bodies.empty()) return a.bodies;
  std::vector<std::size_t> all(m.bodies.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  return all;
}

/// The contact modulus of the finger against the stiffest tissue it may touch.
double tissue_contact_modulus(const scene::Model& m, const std::vector<std::size_t>& bodies,
                              const scene::FingerProperties& finger) {
  double e_star = 0.0;
  for (std::size_t b : bodies) {
    const auto& mat = m.bodies[b].material;
    const double e = mat ? m.materials[*mat].young_modulus : 1e12;  // a rigid body
    const double nu = mat ? m.materials[*mat].poisson_ratio : 0.3;
    e_star = std::max(e_star, haptics::contact_modulus(finger.young_modulus, finger.poisson_ratio, e, nu));
  }
  return e_star;
}

struct DeviceSetup {
  HapticConfig config;
  std::vector<std::size_t> bodies;
  double reach = 0.0;
};

DeviceSetup setup_device(const scene::Model& m, std::size_t index) {
  const scene::Device& d = m.devices[index];
  DeviceSetup s;
  s.config.device = static_cast<std::uint16_t>(index);
  s.config.rate = m.rates.haptic;
  s.config.map = workspace_map(d);
  s.config.safety.max_force = d.max_force;
  // The watchdog must not trip on a healthy simulation: allow a few of its periods.
  s.config.safety.watchdog_timeout =
      std::max(0.1, 3.0 / m.rates.simulation + 3.0 / m.rates.interaction);

  const DrivenTool driven = tool_of(m, index);
  if (!driven.tool) return s;  // a device with no tool is read and recorded, and feels nothing
  const scene::Tool& tool = *driven.tool;
  const scene::FingerProperties* finger = nullptr;
  if (const auto* one = std::get_if<scene::SphereTool>(&tool.shape)) {
    s.config.spheres.push_back({Vec3::Zero(), one->radius});
    finger = &one->finger;
  } else if (const auto* set = std::get_if<scene::SphereSetTool>(&tool.shape)) {
    for (const auto& sp : set->spheres) s.config.spheres.push_back({sp.center, sp.radius});
    finger = &set->finger;
  } else if (const auto* two = std::get_if<scene::TwoFingersTool>(&tool.shape)) {
    s.config.spheres.push_back({Vec3::Zero(), two->radius});
    finger = &two->finger;
  } else {
    throw InputError(SourceLocation{m.source, {}, {}, {}},
                     fmt::format("tool '{}': a {} tool cannot be rendered by this version yet", tool.name,
                                 scene::tool_type_name(tool.shape)));
  }

  const scene::Algorithm* a = algorithm_of(m, tool);
  if (!a) {
    s.config.spheres.clear();
    return s;
  }
  s.bodies = bodies_of(m, *a);
  if (const auto* p = std::get_if<scene::ProxyParams>(&a->params)) {
    s.config.law.law = haptics::NormalLaw::linear;
    s.config.law.stiffness = std::min(p->stiffness, d.max_stiffness);
    s.config.damping = p->damping;
  } else if (std::get_if<scene::HertzFingerParams>(&a->params)) {
    // Flat-tissue Hertz (curvature from the tissue surface is part of the contact layer).
    s.config.law.law = haptics::NormalLaw::hertz;
    const double radius = s.config.spheres.front().radius;
    s.config.law.hertz_factor = haptics::hertz_factor(tissue_contact_modulus(m, s.bodies, *finger), radius);
  } else if (const auto* pad = std::get_if<scene::FingerpadParams>(&a->params)) {
    s.config.law.law = haptics::NormalLaw::fingerpad;
    s.config.law.b = pad->b;
    s.config.law.m = pad->m;
  } else {
    throw InputError(SourceLocation{m.source, {}, {}, {}},
                     fmt::format("algorithm '{}': type '{}' cannot be rendered by this version yet", a->name,
                                 scene::algorithm_type_name(a->params)));
  }
  double extent = 0.0;
  for (const auto& sp : s.config.spheres) extent = std::max(extent, sp.offset.norm() + sp.radius);
  s.reach = 2.0 * extent + 0.01;
  return s;
}

/// Moves what the loops produced into the recording and the report.
class Recorder {
 public:
  Recorder(const scene::Model& m, const SessionOptions& o, std::vector<DeviceChannels*> devices,
           SpscRing<SimulationStep>& steps, SessionReport& report)
      : devices_(std::move(devices)), steps_(steps), report_(report), keep_(o.keep_frames),
        record_steps_(m.recording.timings), record_events_(m.recording.events) {
    if (!o.record) return;
    RecordingHeader h;
    h.scene_name = m.name;
    h.scene_source = o.scene_source.empty() ? m.source : o.scene_source;
    h.scene_text = o.scene_text;
    h.mode = o.scheduling == Scheduling::lockstep ? "lockstep" : "realtime";
    h.haptic_rate = m.rates.haptic;
    h.simulation_rate = m.rates.simulation;
    for (const auto& d : m.devices) h.devices.push_back(d.name);
    h.start_unix_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                          std::chrono::system_clock::now().time_since_epoch())
                          .count();
    h.tactus_version = kVersion;
    writer_.emplace(*o.record, h);
  }

  /// Drains every ring; returns whether anything was moved.
  bool drain() {
    bool any = false;
    HapticFrame f;
    LoopEvent e;
    for (DeviceChannels* d : devices_) {
      while (d->frames.try_pop(f)) {
        any = true;
        ++report_.recorded_frames;
        if (writer_) writer_->append(f);
        if (keep_) report_.frames.push_back(f);
        auto& dev = report_.devices[f.device];
        dev.max_force_sent = std::max(dev.max_force_sent, f.force.norm());
        dev.contact_frames += f.contact;
      }
      while (d->events.try_pop(e)) {
        any = true;
        ++report_.events[std::string(event_kind_name(e.kind))];
        if (writer_ && record_events_) writer_->append(Event{e.t, e.kind, e.device, e.value, {}});
      }
    }
    SimulationStep s;
    while (steps_.try_pop(s)) {
      any = true;
      if (writer_ && record_steps_) writer_->append(s);
    }
    return any;
  }
  void flush() {
    if (writer_) writer_->flush();
  }
  void close() {
    drain();
    if (writer_) {
      writer_->close();
      report_.recording_bytes = writer_->bytes_written();
    }
  }

 private:
  std::vector<DeviceChannels*> devices_;
  SpscRing<SimulationStep>& steps_;
  SessionReport& report_;
  bool keep_;
  // Frames are always whole (pose, force and contact together: a replay needs them).
  bool record_steps_, record_events_;
  std::optional<RecordingWriter> writer_;
};

/// Everything a run owns, built before any loop starts.
struct Loops {
  std::vector<std::unique_ptr<DeviceChannels>> channels;
  std::vector<std::unique_ptr<HapticLoop>> haptic;
  std::unique_ptr<TripleBuffer<SurfaceSnapshot>> surfaces;
  std::unique_ptr<SimulationLoop> simulation;
  std::unique_ptr<InteractionLoop> interaction;

  [[nodiscard]] std::vector<DeviceChannels*> channel_ptrs() const {
    std::vector<DeviceChannels*> out;
    for (const auto& c : channels) out.push_back(c.get());
    return out;
  }
  [[nodiscard]] bool all_finished(double t) const {
    return std::all_of(haptic.begin(), haptic.end(), [t](const auto& h) { return h->finished(t); });
  }
};

Loops build_loops(const scene::Model& m, const SessionOptions& o) {
  Loops loops;
  std::vector<InteractionTarget> targets;
  for (std::size_t i = 0; i < m.devices.size(); ++i) {
    DeviceSetup setup = setup_device(m, i);
    std::unique_ptr<haptics::Device> device;
    if (const auto it = o.replay.find(m.devices[i].name); it != o.replay.end())
      device = std::make_unique<haptics::ReplayDevice>(it->second.poses, device_limits(m.devices[i]), it->second.source);
    else
      device = make_device(m, i, static_cast<unsigned>(i));
    loops.channels.push_back(std::make_unique<DeviceChannels>(kFrameRingCapacity));
    DeviceChannels& ch = *loops.channels.back();
    if (!setup.config.spheres.empty()) targets.push_back({&ch, setup.bodies, setup.reach});
    loops.haptic.push_back(std::make_unique<HapticLoop>(std::move(setup.config), std::move(device), ch));
  }
  // The simulation publishes into a buffer pre-sized with the rest surfaces.
  loops.simulation = std::make_unique<SimulationLoop>(m, loops.channel_ptrs());
  loops.surfaces = std::make_unique<TripleBuffer<SurfaceSnapshot>>(loops.simulation->initial_snapshot());
  loops.simulation->add_output(*loops.surfaces);
  loops.interaction = std::make_unique<InteractionLoop>(m, std::move(targets), *loops.surfaces);
  return loops;
}

double run_length(const SessionOptions& o) { return o.duration > 0.0 ? o.duration : o.max_duration; }

void run_lockstep(const scene::Model& m, const SessionOptions& o, Loops& loops, Recorder& recorder,
                  SessionReport& report) {
  const double end = run_length(o);
  const double haptic_rate = m.rates.haptic, sim_rate = m.rates.simulation, inter_rate = m.rates.interaction;
  std::uint64_t sim_steps = 0, inter_steps = 0;
  bool stopped = false;
  double t = 0.0;
  // Times are integer multiples of each period (k / rate), never accumulated sums, so
  // every run visits the same instants in the same order.
  for (std::uint64_t k = 0;; ++k) {
    t = static_cast<double>(k) / haptic_rate;
    if (t > end + 1e-12) break;
    while (static_cast<double>(sim_steps) / sim_rate <= t) {
      const Nanos now = now_ns();
      loops.simulation->step(static_cast<double>(sim_steps) / sim_rate, now, now, false);
      ++sim_steps;
      recorder.drain();
    }
    while (static_cast<double>(inter_steps) / inter_rate <= t) {
      const Nanos now = now_ns();
      loops.interaction->step(static_cast<double>(inter_steps) / inter_rate, now, now, false);
      ++inter_steps;
    }
    if (o.emergency_stop_at && !stopped && t >= *o.emergency_stop_at) {
      for (auto& h : loops.haptic) h->request_emergency_stop();
      stopped = true;
    }
    for (auto& h : loops.haptic) {
      const Nanos now = now_ns();
      h->step(t, now, now, false);
    }
    if (o.duration <= 0.0 && loops.all_finished(t)) break;
    if (o.interrupt && (k & 63) == 0 && o.interrupt->load()) break;
  }
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
        step(static_cast<double>(deadline - t0) * 1e-9, deadline, start);
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
    run_loop("simulation", m.rates.simulation, RealtimeRequest{low_priority, -1}, kOtherLoopSpin,
             [&](double t, Nanos deadline, Nanos start) { loops.simulation->step(t, deadline, start, true); });
  });
  threads.emplace_back([&] {
    run_loop("interaction", m.rates.interaction, RealtimeRequest{low_priority, -1}, kOtherLoopSpin,
             [&](double t, Nanos deadline, Nanos start) { loops.interaction->step(t, deadline, start, true); });
  });
  // The recorder runs on this thread: it drains the rings and decides when to stop.
  const double end = run_length(o);
  bool stopped = false;
  Nanos last_flush = now_ns();
  while (!stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    const Nanos now = now_ns();
    const double t = static_cast<double>(now - t0) * 1e-9;
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
  for (auto& th : threads) th.join();
  if (failure) std::rethrow_exception(failure);
  report.simulated_time = static_cast<double>(now_ns() - t0) * 1e-9;
}

}  // namespace

SessionReport run_session(const scene::Model& model, const SessionOptions& options) {
  if (model.devices.empty())
    throw InputError(SourceLocation{model.source, {}, {}, {}}, "the scene has no device: nothing drives the haptic loop");
  for (const auto& [name, motion] : options.replay)
    if (!model.find_device(name))
      throw InputError(SourceLocation{motion.source, {}, {}, {}},
                       fmt::format("the recording's device '{}' is not in the scene", name));

  SessionReport report;
  report.scene = model.name;
  report.scheduling = options.scheduling;
  Loops loops = build_loops(model, options);
  for (std::size_t i = 0; i < model.devices.size(); ++i)
    report.devices.push_back({model.devices[i].name, loops.haptic[i]->device().kind(), {}, 0, 0.0, 0});
  Recorder recorder(model, options, loops.channel_ptrs(), loops.simulation->steps(), report);

  const Nanos wall0 = now_ns();
  if (options.scheduling == Scheduling::lockstep)
    run_lockstep(model, options, loops, recorder, report);
  else
    run_real_time(model, options, loops, recorder, report);
  report.wall_time = static_cast<double>(now_ns() - wall0) * 1e-9;
  recorder.close();

  for (std::size_t i = 0; i < loops.haptic.size(); ++i) {
    LoopStats s = loops.haptic[i]->stats();
    s.name = "haptic[" + model.devices[i].name + "]";
    report.loops.push_back(std::move(s));
    report.devices[i].safety = loops.haptic[i]->safety_counters();
    report.devices[i].dropped_frames = loops.haptic[i]->dropped_frames();
  }
  report.loops.push_back(loops.simulation->stats());
  report.loops.push_back(loops.interaction->stats());
  for (std::size_t i = 0; i < loops.haptic.size(); ++i)
    report.parts.push_back({"haptic[" + model.devices[i].name + "]: device read -> force written",
                            loops.haptic[i]->device_to_force()});
  for (const auto& p : loops.simulation->parts()) report.parts.push_back({"simulation: " + p.name, p.time});
  for (const auto& p : loops.interaction->parts())
    if (p.time.count() > 0) report.parts.push_back({"interaction: " + p.name, p.time});
  report.dropped_steps = loops.simulation->dropped_steps();
  return report;
}

}  // namespace tactus::runtime
