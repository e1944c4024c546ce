#include "runtime/session.hpp"

#include <fmt/format.h>

#include "core/error.hpp"
#include "runtime/loop_set.hpp"

namespace tactus::runtime {

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
  report.visual = options.visual != nullptr;
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
    report.devices[i].passivity_frames = loops.haptic[i]->passivity().frames_acted();
    report.devices[i].passivity_energy = loops.haptic[i]->passivity().removed();
    if (const haptics::NeedleInsertion* needle = loops.haptic[i]->needle())
      report.needles.push_back(needle_report(model, model.devices[i].name, *needle));
  }
  report.loops.push_back(loops.simulation->stats());
  report.loops.push_back(loops.interaction->stats());
  for (std::size_t i = 0; i < loops.haptic.size(); ++i)
    report.parts.push_back({"haptic[" + model.devices[i].name + "]: device read -> force written",
                            loops.haptic[i]->device_to_force()});
  // Parts a scene never exercises (no patch, no embedded body, no needle) are left out.
  for (const auto& p : loops.simulation->parts())
    if (p.time.count() > 0) report.parts.push_back({"simulation: " + p.name, p.time});
  for (const auto& p : loops.interaction->parts())
    if (p.time.count() > 0) report.parts.push_back({"interaction: " + p.name, p.time});
  report.dropped_steps = loops.simulation->dropped_steps();
  for (std::size_t b = 0; b < loops.cspaces.size(); ++b)
    if (const auto& c = loops.cspaces[b]; c && c->online()) {
      const CspaceBody::OnlineCounts n = c->online_counts();
      report.cspace_notes.push_back(fmt::format(
          "on-line space of body '{}': {} of {} grid points solved during the run; {} of {} force queries in the grid "
          "found their cell complete ({:.1f}%)",
          model.bodies[b].name, n.solved, n.points, n.complete, n.queries,
          n.queries ? 100.0 * static_cast<double>(n.complete) / static_cast<double>(n.queries) : 0.0));
    }
  return report;
}

}  // namespace tactus::runtime
