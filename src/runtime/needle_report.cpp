#include "runtime/needle_report.hpp"

#include <algorithm>
#include <map>

#include <fmt/format.h>

#include "core/text.hpp"

namespace tactus::runtime {

NeedleReport needle_report(const scene::Model& model, const std::string& device,
                           const haptics::NeedleInsertion& needle) {
  NeedleReport r;
  r.device = device;
  const auto& layers = needle.config().layers;
  r.layers = layers.size();
  r.touched = needle.touched();
  for (const haptics::NeedleRupture& rupture : needle.ruptures()) {
    const haptics::NeedleLayer& l = layers[rupture.layer];
    r.ruptures.push_back({model.bodies[l.body].name, rupture.t, rupture.force, l.rupture_force});
  }
  r.planned = needle.config().planned.has_value();
  r.max_deviation = needle.max_deviation();
  r.last_deviation = needle.last_deviation();
  return r;
}

std::string format_needle_report(const NeedleReport& r) {
  // Each insertion at a new site tears its layers anew: count the layers and the sites.
  std::map<std::string, std::size_t> torn;
  for (const NeedleRuptureReport& p : r.ruptures) ++torn[p.layer];
  std::size_t sites = 0;
  for (const auto& [layer, times] : torn) sites = std::max(sites, times);
  // A needle that never touched a layer (a palpation-only scenario) has nothing to report.
  if (!r.touched) return fmt::format("\nneedle ({}): never touched a layer\n", r.device);
  std::string out = fmt::format("\nneedle ({}): {} of {} layers passed", r.device, torn.size(), r.layers);
  out += sites > 1 ? fmt::format(", {} ruptures at {} insertion sites\n", r.ruptures.size(), sites) : "\n";
  for (std::size_t i = 0; i < r.ruptures.size(); ++i) {
    const NeedleRuptureReport& p = r.ruptures[i];
    out += fmt::format("  {}. {:<20} ruptured at t = {:.4f} s, force {:.3f} N (threshold {:.3f} N)\n", i + 1, p.layer,
                       p.t, p.force, p.threshold);
  }
  out += fmt::format("  lateral deviation from the {} path: max {:.3f} mm, last {:.3f} mm\n",
                     r.planned ? "planned" : "puncture", r.max_deviation * 1e3, r.last_deviation * 1e3);
  return out;
}

std::string needle_report_json(const NeedleReport& r) {
  std::string ruptures;
  for (std::size_t i = 0; i < r.ruptures.size(); ++i) {
    const NeedleRuptureReport& p = r.ruptures[i];
    ruptures += fmt::format("{}{{\"layer\": {}, \"t_s\": {}, \"force_n\": {}, \"threshold_n\": {}}}",
                            i ? ", " : "", text::json_quoted(p.layer), p.t, p.force, p.threshold);
  }
  return fmt::format("{{\"device\": {}, \"layers\": {}, \"touched\": {}, \"ruptures\": [{}], \"planned_path\": {}, "
                     "\"max_deviation_m\": {}, \"last_deviation_m\": {}}}",
                     text::json_quoted(r.device), r.layers, r.touched ? "true" : "false", ruptures,
                     r.planned ? "true" : "false", r.max_deviation, r.last_deviation);
}

}  // namespace tactus::runtime
