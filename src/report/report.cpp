#include "report/report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>

#include "contact/grasp_state.hpp"
#include "core/text.hpp"

namespace tactus::report {

// A report reads what a run left: its loops' statistics, frames and events.
using namespace tactus::runtime;
namespace {

double us(Nanos ns) { return static_cast<double>(ns) * 1e-3; }

std::string summary_cells(const LatencyHistogram& h) {
  if (h.count() == 0) return fmt::format("{:>9} {:>9} {:>9} {:>9}", "-", "-", "-", "-");
  const LatencySummary s = summarize(h);
  return fmt::format("{:9.1f} {:9.1f} {:9.1f} {:9.1f}", us(s.p50), us(s.p99), us(s.p999), us(s.max));
}

std::string summary_json(const LatencyHistogram& h) {
  const LatencySummary s = summarize(h);
  return fmt::format(R"({{"count": {}, "min_us": {:.3f}, "p50_us": {:.3f}, "p99_us": {:.3f}, "p999_us": {:.3f}, "max_us": {:.3f}, "mean_us": {:.3f}}})",
                     s.count, us(s.min), us(s.p50), us(s.p99), us(s.p999), us(s.max), s.mean * 1e-3);
}

/// Each device's two-finger contact states (seed 002 Table I): the states held for at least
/// kSteadyState, in order (a contact that flickers at the simulation's updates would bury the
/// sequence; the recording keeps every change), then the time in each.
/// Per device, each touchable object's levels and the time its haptic loop rendered each (it
/// starts at the coarsest), and the budget used per 100 ms window.
std::string format_levels(const SessionReport& r) {
  if (r.touchables.empty()) return {};
  std::string out;
  for (std::size_t d = 0; d < r.devices.size(); ++d) {
    std::vector<double> costs;
    for (const auto& [device, cost] : r.level_costs)
      if (device == d) costs.push_back(cost);
    bool any = !costs.empty();
    for (const LevelSwitchRecord& s : r.level_switches) any = any || s.device == d;
    if (!any) continue;
    std::sort(costs.begin(), costs.end());
    out += fmt::format("impostor levels for {} (haptic budget {:.1f} µs a frame", r.devices[d].name, 1e6 * r.level_budget);
    if (!costs.empty())
      out += fmt::format("; the levels in use cost, per 100 ms: median {:.1f} µs, max {:.1f} µs",
                         1e6 * costs[costs.size() / 2], 1e6 * costs.back());
    out += "):\n";
    for (const TouchableReport& t : r.touchables) {
      std::vector<double> time_at(t.levels.size(), 0.0);
      std::size_t level = 0, switches = 0;
      double since = 0.0;
      for (const LevelSwitchRecord& s : r.level_switches) {
        if (s.device != d || s.body != t.body || s.level >= t.levels.size()) continue;
        time_at[level] += s.t - since;
        level = s.level;
        since = s.t;
        ++switches;
      }
      time_at[level] += std::max(0.0, r.simulated_time - since);
      out += fmt::format("  {}:", t.name);
      for (std::size_t l = 0; l < t.levels.size(); ++l) {
        const TouchableReport::Level& v = t.levels[l];
        out += fmt::format(" L{} {} tri, {:.1f} µs (query {:.2f} µs measured), {:.2f} mm, {:.2f} s;", l, v.triangles,
                           1e6 * v.cost, 1e6 * v.query_p50, 1e3 * v.hausdorff, time_at[l]);
      }
      out += fmt::format(" {} switches\n", switches);
    }
  }
  return out;
}

std::string format_contact_states(const SessionReport& r) {
  constexpr double kSteadyState = 0.02;  // [s]
  std::string out;
  for (std::size_t d = 0; d < r.devices.size(); ++d) {
    std::vector<ContactStateChange> trace;
    for (const ContactStateChange& c : r.contact_states)
      if (c.device == d) trace.push_back(c);
    if (trace.empty()) continue;
    std::array<double, 10> time_in{};
    std::string steady;
    std::uint8_t last_listed = 0;
    for (std::size_t i = 0; i < trace.size(); ++i) {
      const double end = i + 1 < trace.size() ? trace[i + 1].t : r.simulated_time;
      const double held = std::max(0.0, end - trace[i].t);
      if (trace[i].state < time_in.size()) time_in[trace[i].state] += held;
      if (held >= kSteadyState && trace[i].state != last_listed) {
        steady += fmt::format(" {} {:.3f},", contact::name(static_cast<contact::ContactState>(trace[i].state)), trace[i].t);
        last_listed = trace[i].state;
      }
    }
    out += fmt::format("contact states of {} (seed 002 Table I; {} changes, those held {:.0f} ms or more, from s):{}",
                       r.devices[d].name, trace.size(), 1e3 * kSteadyState, steady);
    out.back() = '\n';
    out += "  time in each:";
    for (std::uint8_t k = 1; k < time_in.size(); ++k)
      if (time_in[k] > 0.0) out += fmt::format(" {} {:.3f} s,", contact::name(static_cast<contact::ContactState>(k)), time_in[k]);
    out.back() = '\n';
  }
  return out;
}

}  // namespace

std::string format_report(const SessionReport& r) {
  const bool rt = r.scheduling == Scheduling::real_time;
  std::string out = fmt::format("\nrun of scene '{}': {} s of {} in {:.3f} s wall clock\n", r.scene, r.simulated_time,
                                rt ? "real time" : "lockstep virtual time", r.wall_time);
  out += fmt::format("\n{:<28} {:>7} {:>8}  {:^39}  {:^39}  {:>6} {:>8}\n", "loop", "rate Hz", "steps",
                     "compute time p50 / p99 / p99.9 / max µs", rt ? "period p50 / p99 / p99.9 / max µs" : "(period: virtual)",
                     "missed", "overruns");
  for (const LoopStats& l : r.loops) {
    const double achieved = rt && r.simulated_time > 0 ? static_cast<double>(l.steps) / r.simulated_time : l.rate;
    out += fmt::format("{:<28} {:>7.0f} {:>8}  {}  {}  {:>6} {:>8}\n", l.name, achieved, l.steps, summary_cells(l.compute),
                       rt ? summary_cells(l.period) : std::string(39, ' '), l.missed_deadlines, l.overruns);
  }
  if (r.caught_up_steps > 0)
    out += fmt::format("simulation: {} late steps spanned the missed periods too ([rates] catch_up)\n", r.caught_up_steps);
  if (rt) {
    out += fmt::format("\n{:<28} {:^39}\n", "start lateness", "p50 / p99 / p99.9 / max µs");
    for (const LoopStats& l : r.loops) out += fmt::format("{:<28} {}\n", l.name, summary_cells(l.lateness));
  }
  out += fmt::format("\n{:<44} {:^39}\n", "parts", "time p50 / p99 / p99.9 / max µs");
  for (const PartStats& p : r.parts) out += fmt::format("{:<44} {}\n", p.name, summary_cells(p.time));
  if (!r.visual) out += "visual loop: not running (headless)\n";  // a window reports its own loop

  out += "\ndevices\n";
  for (const DeviceReport& d : r.devices) {
    const auto& s = d.safety;
    out += fmt::format("  {} ({}): max force sent {:.3f} N, {} frames in contact, clamped {}, non-finite {}, ramps in {} "
                       "out {}, watchdog trips {}, device stalls {}, emergency stops {}, dropped frames {}, passivity control "
                       "{} frames ({:.3f} mJ kept from the hand)\n",
                       d.name, d.kind, d.max_force_sent, d.contact_frames, s.clamped, s.non_finite, s.ramp_in, s.ramp_out,
                       s.watchdog_trips, s.device_stalls, s.emergency_stops, d.dropped_frames, d.passivity_frames,
                       1e3 * d.passivity_energy);
    if (d.has_patch)
      out += fmt::format("    local patches: the tool strayed at most {:.2f} of the radius from a patch's centre, {} frames "
                         "beyond the radius\n",
                         d.patch_reach.max_fraction, d.patch_reach.frames_outside);
  }
  if (!r.events.empty()) {
    out += "events:";
    for (const auto& [kind, n] : r.events) out += fmt::format(" {} {},", kind, n);
    out.back() = '\n';
  }
  if (r.recording_bytes > 0)
    out += fmt::format("recording: {} frames, {} bytes\n", r.recorded_frames, r.recording_bytes);
  if (r.vtk_frames > 0) out += fmt::format("vtk series: {} frames, {} bytes\n", r.vtk_frames, r.vtk_bytes);
  for (const auto& note : r.realtime_notes) out += "  " + note + "\n";
  if (r.palpation) out += format_feedback(*r.palpation);
  for (const NeedleReport& n : r.needles) out += format_needle_report(n);
  out += format_contact_states(r);
  out += format_levels(r);
  for (const auto& note : r.cspace_notes) out += note + "\n";
  return out;
}

std::string report_json(const SessionReport& r) {
  std::string out = "{\n";
  out += fmt::format("  \"scene\": {},\n  \"scheduling\": \"{}\",\n  \"simulated_time_s\": {},\n  \"wall_time_s\": {},\n",
                     text::json_quoted(r.scene), r.scheduling == Scheduling::real_time ? "real_time" : "lockstep", r.simulated_time,
                     r.wall_time);
  out += fmt::format("  \"caught_up_steps\": {},\n", r.caught_up_steps);
  out += "  \"loops\": [\n";
  for (std::size_t i = 0; i < r.loops.size(); ++i) {
    const LoopStats& l = r.loops[i];
    out += fmt::format("    {{\"name\": {}, \"rate_hz\": {}, \"steps\": {}, \"missed_deadlines\": {}, \"overruns\": {}, "
                       "\"compute\": {}, \"period\": {}, \"lateness\": {}}}{}\n",
                       text::json_quoted(l.name), l.rate, l.steps, l.missed_deadlines, l.overruns, summary_json(l.compute),
                       summary_json(l.period), summary_json(l.lateness), i + 1 < r.loops.size() ? "," : "");
  }
  out += "  ],\n  \"parts\": [\n";
  for (std::size_t i = 0; i < r.parts.size(); ++i)
    out += fmt::format("    {{\"name\": {}, \"time\": {}}}{}\n", text::json_quoted(r.parts[i].name), summary_json(r.parts[i].time),
                       i + 1 < r.parts.size() ? "," : "");
  out += "  ],\n  \"devices\": [\n";
  for (std::size_t i = 0; i < r.devices.size(); ++i) {
    const DeviceReport& d = r.devices[i];
    const auto& s = d.safety;
    out += fmt::format("    {{\"name\": {}, \"kind\": {}, \"max_force_sent_n\": {}, \"contact_frames\": {}, "
                       "\"clamped\": {}, \"non_finite\": {}, \"ramp_in\": {}, \"ramp_out\": {}, \"watchdog_trips\": {}, "
                       "\"device_stalls\": {}, \"emergency_stops\": {}, \"dropped_frames\": {}, \"passivity_frames\": {}, "
                       "\"passivity_energy_j\": {}{}}}{}\n",
                       text::json_quoted(d.name), text::json_quoted(d.kind), d.max_force_sent, d.contact_frames, s.clamped, s.non_finite,
                       s.ramp_in, s.ramp_out, s.watchdog_trips, s.device_stalls, s.emergency_stops, d.dropped_frames,
                       d.passivity_frames, d.passivity_energy,
                       d.has_patch ? fmt::format(", \"patch_reach_max\": {}, \"frames_outside_patch\": {}",
                                                 d.patch_reach.max_fraction, d.patch_reach.frames_outside)
                                   : "",
                       i + 1 < r.devices.size() ? "," : "");
  }
  out += "  ],\n  \"events\": {";
  bool first = true;
  for (const auto& [kind, n] : r.events) {
    out += fmt::format("{}{}: {}", first ? "" : ", ", text::json_quoted(kind), n);
    first = false;
  }
  out += fmt::format("}},\n  \"recorded_frames\": {},\n  \"recording_bytes\": {}", r.recorded_frames, r.recording_bytes);
  if (r.palpation) out += ",\n  \"palpation\": " + feedback_json(*r.palpation);
  for (std::size_t i = 0; i < r.needles.size(); ++i)
    out += (i == 0 ? ",\n  \"needles\": [" : ", ") + needle_report_json(r.needles[i]) + (i + 1 == r.needles.size() ? "]" : "");
  if (!r.contact_states.empty()) {
    out += ",\n  \"contact_states\": [";
    for (std::size_t i = 0; i < r.contact_states.size(); ++i) {
      const ContactStateChange& c = r.contact_states[i];
      out += fmt::format("{}{{\"t\": {}, \"device\": {}, \"state\": \"{}\"}}", i == 0 ? "" : ", ", c.t,
                         text::json_quoted(c.device < r.devices.size() ? r.devices[c.device].name : std::string("?")),
                         contact::name(static_cast<contact::ContactState>(c.state)));
    }
    out += "]";
  }
  out += "\n}\n";
  return out;
}

}  // namespace tactus::report
