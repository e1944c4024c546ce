#include "runtime/session.hpp"

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/reproducible.hpp"
#include "runtime/loop_set.hpp"

namespace tactus::runtime {

void check_runnable(const scene::Model& model, const SessionOptions& options) {
  if (model.devices.empty())
    throw InputError(SourceLocation{model.source, {}, {}, {}}, "the scene has no device: nothing drives the haptic loop");
  for (const auto& [name, motion] : options.replay)
    if (!model.find_device(name))
      throw InputError(SourceLocation{motion.source, {}, {}, {}},
                       fmt::format("the recording's device '{}' is not in the scene", name));
}

void start_report(const scene::Model& model, const SessionOptions& options, const Loops& loops, SessionReport& report) {
  report.scene = model.name;
  report.scheduling = options.scheduling;
  report.visual = options.visual != nullptr;
  report.level_budget = model.level_selection.haptic_budget;
  for (const auto& object : loops.touchables.objects) {
    if (!object) continue;
    TouchableReport t{model.bodies[static_cast<std::size_t>(object->body)].name, object->body, {}};
    for (const auto& l : object->levels->levels)
      t.levels.push_back({l.mesh.triangles.size(), haptics::LevelChooser::level_cost(l), l.error.hausdorff, l.cost.query_p50});
    report.touchables.push_back(std::move(t));
  }
  for (std::size_t i = 0; i < model.devices.size(); ++i)
    report.devices.push_back({model.devices[i].name, loops.haptic[i]->device().kind(), {}, 0, 0.0, 0});
}

SessionReport run_session(const scene::Model& model, const SessionOptions& options) {
  fix_dense_blocking();  // lockstep runs sum alike on every machine
  fix_blas_threads();
  check_runnable(model, options);

  SessionReport report;
  Loops loops = build_loops(model, options);
  start_report(model, options, loops, report);
  Recorder recorder(model, options, loops.channel_ptrs(), loops.simulation->steps(), report);
  if (loops.vtk) recorder.add_vtk(*loops.vtk, *loops.nodes);

  const Nanos wall0 = now_ns();
  if (options.scheduling == Scheduling::lockstep)
    run_lockstep(model, options, loops, recorder, report);
  else
    run_real_time(model, options, loops, recorder, report);
  report.wall_time = static_cast<double>(now_ns() - wall0) * 1e-9;
  recorder.close();
  complete_report(model, loops, report);
  return report;
}

void complete_report(const scene::Model& model, const Loops& loops, SessionReport& report) {
  for (std::size_t i = 0; i < loops.haptic.size(); ++i) {
    LoopStats s = loops.haptic[i]->stats();
    s.name = "haptic[" + model.devices[i].name + "]";
    report.loops.push_back(std::move(s));
    report.devices[i].safety = loops.haptic[i]->safety_counters();
    report.devices[i].dropped_frames = loops.haptic[i]->dropped_frames();
    report.devices[i].passivity_frames = loops.haptic[i]->passivity().frames_acted();
    report.devices[i].passivity_energy = loops.haptic[i]->passivity().removed();
    report.devices[i].has_patch = loops.channels[i]->patch != nullptr;
    report.devices[i].patch_reach = loops.haptic[i]->patch_reach();
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
  report.caught_up_steps = loops.simulation->caught_up_steps();
  // A tool outside a space's grid box feels nothing there: say so, and for how long.
  for (std::size_t b = 0; b < loops.cspaces.size(); ++b)
    if (const auto& c = loops.cspaces[b]) {
      const compile::CspaceBody::BoxCounts n = c->box_counts();
      const std::uint64_t all = n.inside + n.outside;
      if (all == 0 || n.outside == 0) continue;
      report.cspace_notes.push_back(
          n.inside == 0
              ? fmt::format("space of body '{}': the tool never entered its grid box in {} force queries; outside "
                            "the box the space renders no force (docs/precompute.md)",
                            model.bodies[b].name, all)
              : fmt::format("space of body '{}': the tool was outside its grid box in {} of {} force queries "
                            "({:.1f}%; no force there), first inside at t = {:.3f} s",
                            model.bodies[b].name, n.outside, all,
                            100.0 * static_cast<double>(n.outside) / static_cast<double>(all), n.first_inside));
    }
  for (std::size_t b = 0; b < loops.cspaces.size(); ++b)
    if (const auto& c = loops.cspaces[b]; c && c->online()) {
      const compile::CspaceBody::OnlineCounts n = c->online_counts();
      report.cspace_notes.push_back(fmt::format(
          "on-line space of body '{}': {} of {} grid points solved during the run; {} of {} force queries in the grid "
          "found their cell complete ({:.1f}%)",
          model.bodies[b].name, n.solved, n.points, n.complete, n.queries,
          n.queries ? 100.0 * static_cast<double>(n.complete) / static_cast<double>(n.queries) : 0.0));
    }
}

}  // namespace tactus::runtime
