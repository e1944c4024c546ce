#include "report/report.hpp"

#include <fmt/format.h>

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
  }
  if (!r.events.empty()) {
    out += "events:";
    for (const auto& [kind, n] : r.events) out += fmt::format(" {} {},", kind, n);
    out.back() = '\n';
  }
  if (r.recording_bytes > 0)
    out += fmt::format("recording: {} frames, {} bytes\n", r.recorded_frames, r.recording_bytes);
  for (const auto& note : r.realtime_notes) out += "  " + note + "\n";
  if (r.palpation) out += format_feedback(*r.palpation);
  for (const NeedleReport& n : r.needles) out += format_needle_report(n);
  for (const auto& note : r.cspace_notes) out += note + "\n";
  return out;
}

std::string report_json(const SessionReport& r) {
  std::string out = "{\n";
  out += fmt::format("  \"scene\": {},\n  \"scheduling\": \"{}\",\n  \"simulated_time_s\": {},\n  \"wall_time_s\": {},\n",
                     text::json_quoted(r.scene), r.scheduling == Scheduling::real_time ? "real_time" : "lockstep", r.simulated_time,
                     r.wall_time);
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
                       "\"passivity_energy_j\": {}}}{}\n",
                       text::json_quoted(d.name), text::json_quoted(d.kind), d.max_force_sent, d.contact_frames, s.clamped, s.non_finite,
                       s.ramp_in, s.ramp_out, s.watchdog_trips, s.device_stalls, s.emergency_stops, d.dropped_frames,
                       d.passivity_frames, d.passivity_energy, i + 1 < r.devices.size() ? "," : "");
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
  out += "\n}\n";
  return out;
}

}  // namespace tactus::report
