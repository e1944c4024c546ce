#include "report/scenario_report.hpp"

#include <algorithm>
#include <variant>

#include <fmt/format.h>

#include "contact/grasp_state.hpp"

namespace tactus::report {

// A report reads what a run left: its loops' statistics, frames and events.
using namespace tactus::runtime;
namespace {

const PartStats* find_part(const SessionReport& report, const std::string& name) {
  for (const PartStats& p : report.parts)
    if (p.name == name) return &p;
  return nullptr;
}

/// "mean ± SD (n)" in microseconds, or a dash for a part that never ran.
std::string micros(const PartStats* p) {
  if (!p || p->time.count() == 0) return "—";
  return fmt::format("{:.1f} ± {:.1f} µs (n {})", p->time.mean() * 1e-3, p->time.standard_deviation() * 1e-3,
                     p->time.count());
}

std::string millis(const PartStats* p) {
  if (!p || p->time.count() == 0) return "—";
  return fmt::format("{:.3f} ± {:.3f} ms (n {})", p->time.mean() * 1e-6, p->time.standard_deviation() * 1e-6,
                     p->time.count());
}

}  // namespace

std::string format_scenario_measures(const scene::Model& model, const SessionReport& report, double visual_rate,
                                     double visual_rate_sd) {
  std::string s = "\nscenario measures (seed 003 Table 1: mean ± SD):\n";
  for (const scene::Device& d : model.devices) {
    s += fmt::format("  {}:\n", d.name);
    s += fmt::format("    CD   collision query, one object:  {}\n", micros(find_part(report, "interaction: " + d.name + ": query per body")));
    const bool needle = std::any_of(model.tools.begin(), model.tools.end(), [&](const scene::Tool& t) {
      return std::holds_alternative<scene::NeedleTool>(t.shape) && !t.devices.empty() &&
             model.devices[t.devices.front()].name == d.name;
    });
    // The hand's PS (seed 003's PS_LH, the nodes the hand drags): the simulation finds the
    // nodes its contact load and drag are spread over, every device's at once.
    s += needle ? fmt::format("    PS   proximity search (shaft nodes): {}\n", micros(find_part(report, "simulation: shaft node search")))
                : fmt::format("    PS   proximity search (nodes under the contact, every device's): {}\n",
                              micros(find_part(report, "simulation: contact loads")));
    s += fmt::format("    IN   interaction handling:         {}\n", micros(find_part(report, "interaction: " + d.name + ": interaction")));
    s += fmt::format("    haptic frame (read -> force sent): {}\n",
                     micros(find_part(report, "haptic[" + d.name + "]: device read -> force written")));
  }
  s += visual_rate >= 0.0 ? fmt::format("  FPS  visual loop: {:.1f} ± {:.1f} Hz\n", visual_rate, visual_rate_sd)
                          : "  FPS  visual loop: — (headless)\n";
  s += "simulation step (seed 003 Fig. 10: mean ± SD):\n";
  s += fmt::format("  solver step (animate):             {}\n", millis(find_part(report, "simulation: integrate")));
  s += fmt::format("  embedded surfaces (updateVis):     {}\n", millis(find_part(report, "simulation: embedded surfaces")));
  s += fmt::format("  surfaces published:                {}\n", millis(find_part(report, "simulation: publish surfaces")));
  s += fmt::format("  collision trees refit (updateGeo): {}\n", millis(find_part(report, "interaction: refit trees")));
  return s;
}

std::string force_trace_csv(const scene::Model& model, const SessionReport& report) {
  std::string csv = "t,device,force,contact\n";
  for (const HapticFrame& f : report.frames) {
    const std::string& device = f.device < model.devices.size() ? model.devices[f.device].name : std::string("?");
    csv += fmt::format("{:.4f},{},{:.5f},{}\n", f.t, device, f.force.norm(), int(f.contact));
  }
  return csv;
}

std::string contact_state_csv(const scene::Model& model, const SessionReport& report) {
  std::string csv = "t,device,state\n";
  for (const ContactStateChange& c : report.contact_states) {
    const std::string& device = c.device < model.devices.size() ? model.devices[c.device].name : std::string("?");
    csv += fmt::format("{:.4f},{},{}\n", c.t, device, contact::name(static_cast<contact::ContactState>(c.state)));
  }
  return csv;
}

std::string rupture_csv(const SessionReport& report) {
  std::string csv = "t,device,layer,force,threshold\n";
  for (const NeedleReport& n : report.needles)
    for (const NeedleRuptureReport& r : n.ruptures)
      csv += fmt::format("{:.4f},{},{},{:.4f},{:.4f}\n", r.t, n.device, r.layer, r.force, r.threshold);
  return csv;
}

}  // namespace tactus::report
