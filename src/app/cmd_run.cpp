// `tactus run`, `tactus bench`, `tactus replay` and `tactus export`: running scenes through
// the loops, and the recordings they leave.
#include <atomic>
#include <csignal>
#include <cstdio>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <fstream>
#include <map>
#include <optional>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "app/commands.hpp"
#include "core/input_file.hpp"
#include "app/curves.hpp"
#include "core/error.hpp"
#include "offline/fem_bench.hpp"
#include "core/log.hpp"
#include "haptics/trajectory.hpp"
#include "runtime/devices.hpp"
#include "report/force_map.hpp"
#include "runtime/recording_csv.hpp"
#include "runtime/recording_hdf5.hpp"
#include "runtime/recording_reader.hpp"
#include "report/latency_plot.hpp"
#include "report/report.hpp"
#include "report/scenario_report.hpp"
#include "runtime/session.hpp"
#include "scene/scene.hpp"
#include "viewer/window.hpp"

namespace tactus::app {
namespace {

std::atomic<bool> g_interrupted{false};

extern "C" void on_interrupt(int) { g_interrupted.store(true); }

/// Ctrl-C and SIGTERM end a run cleanly (the recording is closed) instead of killing it.
void install_interrupt_handlers() {
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
}

struct LoadedScene {
  scene::Model model;
  std::string text;
  std::string source;
};

LoadedScene load(const std::string& path) {
  if (path.empty()) return {scene::default_scene(), std::string(scene::default_scene_text()), "built-in:default"};
  std::string text = read_input_file(path);
  return {scene::parse_scene(text, path), text, path};
}

/// --space FILE or --online: the scene with its [precompute] body rendered from that space
/// (or from one built during the run), written as a scene on top of the file (`[scene]
/// base`), so that a recording of the run holds a scene that replays the same way.
/// `body_keys` are the cspace body's keys after `kind`.
LoadedScene with_cspace(const LoadedScene& scene, const std::string& flag, const std::string& file,
                        const std::string& body_keys) {
  namespace fs = std::filesystem;
  if (scene.source.rfind("built-in:", 0) == 0)
    throw InputError(flag + ": name a scene file with a [precompute] table (the built-in scene has none)");
  if (!scene.model.precompute)
    throw InputError(SourceLocation{scene.source, {}, {}, {}},
                     flag + ": this scene has no [precompute] table, so no body of it has a space; run the scene the "
                            "space is built from");
  const std::string body = scene.model.precompute->body;
  for (const std::string& name : {file, scene.source, body})
    if (name.find_first_of("\"\\\n") != std::string::npos)
      throw InputError(flag + ": file or body names with quotes, backslashes or line breaks are not supported");
  const std::string text = fmt::format(
      "# {} with body '{}' rendered from a configuration space (tactus run {})\n"
      "[scene]\nbase = \"{}\"\n\n[bodies.\"{}\"]\nkind = \"cspace\"\n{}",
      scene.source, body, flag, fs::absolute(scene.source).string(), body, body_keys);
  return {scene::parse_scene(text, scene.source), text, scene.source};
}

LoadedScene with_space(const LoadedScene& scene, const std::string& space, std::string interpolation) {
  const auto& settings = scene.model.precompute;
  // By default the method the [precompute] table names (the one the space was built for).
  if (interpolation.empty())
    interpolation = settings ? std::string(precompute::to_string(settings->interpolation)) : "trilinear";
  // A two-point space is felt by the two tools its [precompute] table names.
  std::string tools;
  if (settings && settings->pair.enabled()) {
    if (scene.model.precompute_tools.size() != 2)
      throw InputError(SourceLocation{scene.source, {}, {}, {}},
                       "--space: the [precompute] table has a second point; name the tools that feel the two points "
                       "there, tools = [\"first\", \"second\"]");
    tools = fmt::format("tools = [\"{}\", \"{}\"]\n", scene.model.tools[scene.model.precompute_tools[0]].name,
                        scene.model.tools[scene.model.precompute_tools[1]].name);
  }
  return with_cspace(scene, "--space", space,
                     fmt::format("space = \"{}\"\ninterpolation = \"{}\"\n{}",
                                 std::filesystem::absolute(space).string(), interpolation, tools));
}

LoadedScene with_online_space(const LoadedScene& scene, int threads) {
  return with_cspace(scene, "--online", "", fmt::format("online = true\nworkers = {}\n", threads));
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw InputError(SourceLocation{path, {}, {}, {}}, "cannot create the file");
  out << text;
  if (!out) throw InputError(SourceLocation{path, {}, {}, {}}, "could not write the file");
}

/// Options shared by run and bench.
struct RunFlags {
  std::string scene;
  double duration = 0.0;
  bool lockstep = false;
  std::string record;
  std::string device;  ///< "replay:FILE"
  std::string json;
  std::optional<int> priority;
  std::optional<int> cpu;
  std::optional<double> spin_us;
  std::string space;          ///< --space: render the [precompute] body from this file
  std::string interpolation;  ///< with --space
  bool online = false;        ///< --online: build the [precompute] body's space during the run
  int online_threads = 1;
  std::string force_map;  ///< PNG of the first device's force map (run only)
  std::string trace;      ///< folder for the force-trace CSVs and plot (bench only)
  std::string plot;       ///< PNG of the loops' latency histograms (bench only)
  bool view = false;        ///< run in a window (run only; docs/viewer.md)
  double view_seconds = 0.0;
  double frame_budget_ms = 16.0;
  std::string view_script;
  bool no_mouse = false;
  std::string vtk;        ///< folder of the ParaView time series (run only)
  double vtk_rate = 30.0;  ///< its frames per second of simulated time
};

void add_run_flags(CLI::App& app, RunFlags& f, bool bench) {
  app.add_option("scene", f.scene, "Scene file (TOML); the built-in default scene without one")->check(CLI::ExistingFile);
  app.add_option("-d,--duration", f.duration,
                 bench ? "Seconds to run (default: a scenario's length when every device is scripted, else 10)"
                       : "Seconds to run (default: until every device has finished; at most 30 unless every device is scripted)")
      ->check(CLI::Range(0.0, 86400.0));
  app.add_flag("--lockstep", f.lockstep, "One thread, virtual time: reproducible bit for bit");
  app.add_option("--record", f.record, "Write every haptic frame, step and event to this recording");
  app.add_option("--device", f.device, "replay:FILE drives the scene's devices with a recording's motion");
  app.add_option("--json", f.json, "Also write the timing table as JSON to this file");
  app.add_option("--priority", f.priority,
                 "SCHED_FIFO priority of the haptic threads (0 = normal scheduler; default: the scene's, 80)")
      ->check(CLI::Range(0, 99));
  app.add_option("--cpu", f.cpu, "Pin the haptic threads to this CPU (-1 = no pinning; default: the scene's)")
      ->check(CLI::Range(-1, 1023));
  app.add_option("--spin-us", f.spin_us, "Spin this long before each haptic deadline instead of sleeping [µs]")
      ->check(CLI::Range(0.0, 10000.0));
  CLI::Option* space =
      app.add_option("--space", f.space,
                     "Render the body of the scene's [precompute] table from this configuration space (tactus "
                     "precompute's file) instead of simulating it")
          ->check(CLI::ExistingFile);
  app.add_option("--interpolation", f.interpolation,
                 "With --space: trilinear, rbf_cubic, rbf_thin_plate, polynomial, tricubic_hermite or rbf_hermite "
                 "(default: the [precompute] table's interpolation)")
      ->check(CLI::IsMember(
          {"trilinear", "rbf_cubic", "rbf_thin_plate", "polynomial", "tricubic_hermite", "rbf_hermite"}))
      ->needs(space);
  CLI::Option* online =
      app.add_flag("--online", f.online,
                   "Render the body of the scene's [precompute] table from a configuration space built during the "
                   "run, around the tool and ahead of it (docs/precompute.md, \"On-line construction\")")
          ->excludes(space);
  app.add_option("--online-threads", f.online_threads, "With --online: solver threads (default 1)")
      ->check(CLI::Range(1, 256))
      ->needs(online);
}

/// How long the scene's scripted devices play, when every device is scripted (a scenario);
/// none otherwise.
std::optional<double> scripted_length(const scene::Model& m) {
  if (m.devices.empty()) return std::nullopt;
  double longest = 0.0;
  for (const scene::Device& d : m.devices) {
    const auto* s = std::get_if<scene::ScriptedDevice>(&d.source);
    if (!s) return std::nullopt;
    const double length = haptics::duration(s->trajectory);
    if (!std::isfinite(length)) return std::nullopt;
    longest = std::max(longest, length);
  }
  return longest;
}

/// --trace DIR: the force magnitudes per frame, the ruptures and the two-finger contact states
/// as CSV, and their plot through scripts/plot_forces.py when matplotlib is there (seed 003
/// Figs. 7–8).
void write_trace(const RunFlags& f, const scene::Model& model, const runtime::SessionReport& report) {
  namespace fs = std::filesystem;
  fs::create_directories(f.trace);
  const fs::path forces = fs::path(f.trace) / (model.name + "_forces.csv");
  const fs::path ruptures = fs::path(f.trace) / (model.name + "_ruptures.csv");
  const fs::path states = fs::path(f.trace) / (model.name + "_states.csv");
  write_text(forces.string(), report::force_trace_csv(model, report));
  write_text(ruptures.string(), report::rupture_csv(report));
  write_text(states.string(), report::contact_state_csv(model, report));
  std::printf("force trace: %s, %s, %s\n", forces.c_str(), ruptures.c_str(), states.c_str());
  const fs::path script = f.scene.empty() ? fs::path("scripts/plot_forces.py")
                                          : fs::path(f.scene).parent_path() / ".." / "scripts" / "plot_forces.py";
  const std::string python = curves::find_matplotlib_python();
  if (!fs::exists(script) || python.empty()) {
    log::warn("no plot: {} (scripts/plot_forces.py with matplotlib, Debian python3-matplotlib)",
              python.empty() ? "no python3 with matplotlib" : "scripts/plot_forces.py not found");
    return;
  }
  const std::string command = fmt::format("'{}' '{}' '{}' '{}'", python, script.string(), f.trace, model.name);
  std::fflush(stdout);  // our lines first, then the script's
  if (std::system(command.c_str()) != 0) throw std::runtime_error("the force plot failed: " + command);
}

int run_with(const RunFlags& f, bool bench) {
  const LoadedScene scene = !f.space.empty() ? with_space(load(f.scene), f.space, f.interpolation)
                            : f.online       ? with_online_space(load(f.scene), f.online_threads)
                                             : load(f.scene);
  runtime::SessionOptions o;
  o.scheduling = f.lockstep ? runtime::Scheduling::lockstep : runtime::Scheduling::real_time;
  o.duration = f.duration;
  // Without -d: a scenario (every device scripted) plays to its end; bench runs 10 s else.
  if (f.duration <= 0.0) {
    if (const auto length = scripted_length(scene.model))
      o.max_duration = std::min(*length + 0.5, 3600.0);
    else if (bench)
      o.duration = 10.0;
  }
  if (!f.record.empty()) o.record = f.record;
  else if (!scene.model.recording.path.empty()) o.record = scene.model.recording.path;
  o.scene_text = scene.text;
  o.scene_source = scene.source;
  o.realtime_priority = f.priority;
  o.haptic_cpu = f.cpu;
  if (f.spin_us) o.spin_window = static_cast<Nanos>(*f.spin_us * 1e3);
  o.interrupt = &g_interrupted;
  if (!f.device.empty()) {
    constexpr std::string_view prefix = "replay:";
    if (f.device.rfind(prefix, 0) != 0)
      throw InputError(fmt::format("--device '{}': expected replay:FILE", f.device));
    const std::string file = f.device.substr(prefix.size());
    o.replay = runtime::recorded_motion(runtime::read_recording(file), file);
  }
  o.keep_frames = !f.force_map.empty() || !f.trace.empty();
  if (!f.vtk.empty()) {
    o.vtk = f.vtk;
    o.vtk_rate = f.vtk_rate;
  }
  if (!bench) std::fputs(scene::summarize(scene.model, !f.lockstep).c_str(), stdout);
  install_interrupt_handlers();
  std::optional<viewer::WindowReport> window;
  runtime::SessionReport report;
  if (f.view) {
    // The run lasts until the window closes unless a duration is given.
    if (f.duration <= 0.0) o.max_duration = 7.0 * 86400.0;
    viewer::WindowOptions w;
    w.seconds = f.view_seconds;
    w.frame_budget_ms = f.frame_budget_ms;
    if (!f.view_script.empty()) w.script = f.view_script;
    w.mouse = !f.no_mouse;
    w.scenes = viewer::scene_files(f.scene.empty() ? std::filesystem::path("scenes") : std::filesystem::path(f.scene).parent_path());
    window.emplace();
    report = viewer::run_with_window(scene.model, o, w, g_interrupted, *window);
  } else {
    report = runtime::run_session(scene.model, o);
  }
  std::fputs(report::format_report(report).c_str(), stdout);
  if (window) std::fputs(viewer::format_window_report(*window).c_str(), stdout);
  if (bench) std::fputs(report::format_scenario_measures(scene.model, report).c_str(), stdout);
  if (!f.trace.empty()) write_trace(f, scene.model, report);
  if (!f.plot.empty()) {
    report::write_latency_plot(f.plot, report.loops, o.scheduling == runtime::Scheduling::real_time);
    std::printf("latency plot: %s\n", f.plot.c_str());
  }
  if (o.record) log::info("recording written to {}", o.record->string());
  if (o.vtk) log::info("VTK series written to {}", o.vtk->string());
  if (!f.json.empty()) write_text(f.json, report::report_json(report));
  if (!f.force_map.empty())
    std::fputs(report::write_force_map_png(report::build_force_map(scene.model, 0, report.frames), f.force_map).c_str(),
               stdout);
  if (window && !window->next_scene.empty()) {
    // The panel's scene switcher: this run has ended cleanly (the closing window set the
    // interrupt flag to end it); the next one starts afresh.
    g_interrupted.store(false);
    RunFlags next = f;
    next.scene = window->next_scene;
    next.record.clear();     // a recording belongs to the run it was asked for
    next.space.clear();      // and so does a space
    next.view_script.clear();
    return run_with(next, bench);
  }
  return 0;
}

}  // namespace

Action add_run(CLI::App& app) {
  auto f = std::make_shared<RunFlags>();
  add_run_flags(app, *f, false);
  app.add_option("--force-map", f->force_map, "Write the first device's palpation force map to this PNG");
  CLI::Option* vtk = app.add_option("--vtk", f->vtk,
                                    "Write the run as a ParaView time series into this folder: NAME.pvd and one .vtu "
                                    "per body and device and frame (docs/outputs.md)");
  app.add_option("--vtk-rate", f->vtk_rate, "With --vtk: frames per second of simulated time (default 30)")
      ->check(CLI::Range(1e-3, 1e6))
      ->needs(vtk);
  CLI::Option* view = app.add_flag("--view", f->view,
               "Show the run in a window; the mouse drives the first device unless it is hardware or replayed");
  app.add_option("--view-seconds", f->view_seconds, "Close the window and end the run after this many seconds")
      ->check(CLI::Range(0.0, 86400.0))
      ->needs(view);
  app.add_option("--frame-budget", f->frame_budget_ms,
                 "With --view: the visual frame's budget in ms; the scene's resolution and the objects' levels "
                 "keep frames within it (0: full resolution always)")
      ->check(CLI::Range(0.0, 1000.0))
      ->needs(view);
  app.add_flag("--no-mouse", f->no_mouse, "With --view: keep the scene's own device (watch a scripted run)")->needs(view);
  // Synthetic input for tests (docs/viewer.md); not listed in --help.
  app.add_option("--view-script", f->view_script, "")->group("")->check(CLI::ExistingFile)->needs(view);
  return [f] { return run_with(*f, false); };
}

Action add_bench(CLI::App& app) {
  auto f = std::make_shared<RunFlags>();
  add_run_flags(app, *f, true);
  app.add_option("--trace", f->trace, "Write the force magnitudes and needle ruptures as CSV (and a PNG plot) here");
  app.add_option("--plot", f->plot,
                 "Write the loops' latency histograms (compute time and, in real time, period per loop) as a PNG");
  // --fem: the FEM bodies' implicit step alone (offline/fem_bench.hpp).
  auto fem = std::make_shared<bool>(false);
  auto o = std::make_shared<offline::FemBenchOptions>();
  auto law = std::make_shared<std::string>();
  auto solver = std::make_shared<std::string>();
  app.add_flag("--fem", *fem,
               "Time the scene's FEM bodies' implicit step alone (no devices, gravity only): ns per tet, "
               "linear iterations, and the shares of forces, assembly and solve");
  app.add_option("--steps", o->steps, "--fem: timed steps per body (default 200)")->check(CLI::Range(1, 1000000));
  app.add_option("--threads", o->threads, "--fem: element-loop threads (default: every core)")->check(CLI::Range(1u, 256u));
  app.add_option("--law", *law, "--fem: replace the FEM law (linear, corotational, stvk, neo_hookean, mooney_rivlin)");
  app.add_option("--solver", *solver, "--fem: replace the linear solver (cg, cholesky)")
      ->check(CLI::IsMember({"cg", "cholesky"}));
  app.add_option("--cg-tolerance", o->cg_tolerance, "--fem: replace CG's relative tolerance")
      ->check(CLI::Range(1e-16, 1.0));
  app.add_option("--factor-reuse", o->factor_reuse_steps,
                 "--fem: steps one Cholesky factorization serves (the bodies' factor_reuse_steps)")
      ->check(CLI::Range(1, 1000));
  return [f, fem, o, law, solver] {
    if (!*fem) return run_with(*f, true);
    if (!law->empty()) o->law = physics::parse_fem_law(*law);
    if (!solver->empty())
      o->solver = *solver == "cholesky" ? physics::LinearSolver::cholesky : physics::LinearSolver::conjugate_gradient;
    const LoadedScene scene = load(f->scene);
    std::fputs(offline::format_fem_bench(offline::bench_fem(scene.model, *o)).c_str(), stdout);
    return 0;
  };
}

Action add_replay(CLI::App& app) {
  auto file = std::make_shared<std::string>();
  auto realtime = std::make_shared<bool>(false);
  auto record = std::make_shared<std::string>();
  auto scene_dir = std::make_shared<std::string>();
  app.add_option("recording", *file, "A recording written by tactus run --record")->required()->check(CLI::ExistingFile);
  app.add_flag("--realtime", *realtime, "Replay on the wall clock instead of in lockstep");
  app.add_option("--record", *record, "Record the replay too");
  app.add_option("--scene-dir", *scene_dir,
                 "Folder the recorded scene's relative paths (base scene, meshes) resolve against; default: the "
                 "folder of the scene file it was recorded from")
      ->check(CLI::ExistingDirectory);
  return [file, realtime, record, scene_dir] {
    const runtime::Recording rec = runtime::read_recording(*file);
    if (!rec.truncation.empty()) log::warn("{}: {}; replaying what was kept", *file, rec.truncation);
    if (rec.frames.empty()) throw InputError(SourceLocation{*file, {}, {}, {}}, "the recording holds no haptic frame");
    // The scene is the recorded text; relative paths in it resolve against its original folder
    // (or the one given, for a recording moved to another machine).
    scene::LoadOptions load;
    load.base_dir = *scene_dir;
    const scene::Model model = scene::parse_scene(rec.header.scene_text, rec.header.scene_source, load);
    runtime::SessionOptions o;
    o.scheduling = *realtime ? runtime::Scheduling::real_time : runtime::Scheduling::lockstep;
    o.replay = runtime::recorded_motion(rec, *file);
    o.duration = rec.frames.back().t;
    o.keep_frames = true;
    o.scene_text = rec.header.scene_text;
    o.scene_source = rec.header.scene_source;
    if (!record->empty()) o.record = *record;
    o.interrupt = &g_interrupted;
    install_interrupt_handlers();
    const runtime::SessionReport report = runtime::run_session(model, o);
    std::fputs(report::format_report(report).c_str(), stdout);

    // Frame by frame against the recording: same device, same frame index.
    std::size_t compared = 0, identical = 0;
    double worst = 0.0;
    std::map<std::pair<std::uint16_t, std::uint64_t>, const runtime::HapticFrame*> replayed;
    for (const auto& fr : report.frames) replayed[{fr.device, fr.frame}] = &fr;
    for (const auto& fr : rec.frames) {
      const auto it = replayed.find({fr.device, fr.frame});
      if (it == replayed.end()) continue;
      ++compared;
      if (it->second->force == fr.force && it->second->torque == fr.torque) ++identical;
      worst = std::max(worst, (it->second->force - fr.force).norm());
    }
    std::printf("\nreplay of %s (%s recording): %zu of %zu frames compared, %zu forces identical bit for bit, "
                "largest force difference %.3g N\n",
                file->c_str(), rec.header.mode.c_str(), compared, rec.frames.size(), identical, worst);
    const bool expect_exact = rec.header.mode == "lockstep" && !*realtime;
    if (expect_exact && identical != compared) {
      std::fprintf(stderr, "tactus: the lockstep replay differs from the recording\n");
      return 3;
    }
    return 0;
  };
}

Action add_export(CLI::App& app) {
  struct ExportFlags {
    std::string file, csv, steps, events, hdf5, vtk, scene_dir;
    double vtk_rate = 30.0;
  };
  auto f = std::make_shared<ExportFlags>();
  app.add_option("recording", f->file, "A recording written by tactus run --record")->required()->check(CLI::ExistingFile);
  app.add_option("--csv", f->csv, "Haptic frames as CSV (one row per frame)");
  app.add_option("--steps", f->steps, "Simulation steps as CSV");
  app.add_option("--events", f->events, "Events as CSV");
  app.add_option("--hdf5", f->hdf5, "Frames, steps and events as HDF5 datasets with units (docs/recording-format.md)");
  CLI::Option* vtk = app.add_option(
      "--vtk", f->vtk,
      "Replay the recorded scene in lockstep with the recorded motion and write it as a ParaView time series into "
      "this folder (docs/outputs.md)");
  app.add_option("--vtk-rate", f->vtk_rate, "With --vtk: frames per second of simulated time (default 30)")
      ->check(CLI::Range(1e-3, 1e6))
      ->needs(vtk);
  app.add_option("--scene-dir", f->scene_dir,
                 "With --vtk: folder the recorded scene's relative paths resolve against (as tactus replay)")
      ->check(CLI::ExistingDirectory)
      ->needs(vtk);
  return [f] {
    if (f->csv.empty() && (!f->steps.empty() || !f->events.empty()))
      throw InputError("tactus export: --steps and --events come with --csv");
    if (f->csv.empty() && f->hdf5.empty() && f->vtk.empty())
      throw InputError("tactus export: name an output: --csv FILE, --hdf5 FILE or --vtk DIR");
    const runtime::Recording rec = runtime::read_recording(f->file);
    if (!rec.truncation.empty()) log::warn("{}: {}; exporting what was kept", f->file, rec.truncation);
    auto write = [](const std::string& path, auto&& writer) {
      std::ofstream out(path, std::ios::binary);
      if (!out) throw InputError(SourceLocation{path, {}, {}, {}}, "cannot create the file");
      writer(out);
      if (!out) throw InputError(SourceLocation{path, {}, {}, {}}, "could not write the file");
    };
    if (!f->csv.empty()) write(f->csv, [&](std::ostream& out) { runtime::write_frames_csv(rec, out); });
    if (!f->steps.empty()) write(f->steps, [&](std::ostream& out) { runtime::write_steps_csv(rec, out); });
    if (!f->events.empty()) write(f->events, [&](std::ostream& out) { runtime::write_events_csv(rec, out); });
    if (!f->hdf5.empty()) runtime::write_recording_hdf5(rec, f->hdf5);
    log::info("{} frames, {} steps, {} events exported", rec.frames.size(), rec.steps.size(), rec.events.size());
    if (f->vtk.empty()) return 0;

    // The recording holds the device motion and forces, not the bodies' nodes: the series
    // comes from replaying the recorded scene with that motion (what tactus replay runs).
    if (rec.frames.empty()) throw InputError(SourceLocation{f->file, {}, {}, {}}, "the recording holds no haptic frame");
    scene::LoadOptions load;
    load.base_dir = f->scene_dir;
    const scene::Model model = scene::parse_scene(rec.header.scene_text, rec.header.scene_source, load);
    runtime::SessionOptions o;
    o.scheduling = runtime::Scheduling::lockstep;
    o.replay = runtime::recorded_motion(rec, f->file);
    o.duration = rec.frames.back().t;
    o.keep_frames = true;
    o.vtk = f->vtk;
    o.vtk_rate = f->vtk_rate;
    o.interrupt = &g_interrupted;
    install_interrupt_handlers();
    const runtime::SessionReport report = runtime::run_session(model, o);
    std::size_t compared = 0, identical = 0;
    std::map<std::pair<std::uint16_t, std::uint64_t>, const runtime::HapticFrame*> replayed;
    for (const auto& fr : report.frames) replayed[{fr.device, fr.frame}] = &fr;
    for (const auto& fr : rec.frames)
      if (const auto it = replayed.find({fr.device, fr.frame}); it != replayed.end()) {
        ++compared;
        identical += it->second->force == fr.force && it->second->torque == fr.torque;
      }
    std::printf("vtk series: %llu frames, %llu bytes in %s (replayed in lockstep: %zu of %zu frames' forces "
                "identical to the recording's)\n",
                static_cast<unsigned long long>(report.vtk_frames), static_cast<unsigned long long>(report.vtk_bytes),
                f->vtk.c_str(), identical, compared);
    if (rec.header.mode != "lockstep")
      log::warn("{}: a real-time recording: the series is a lockstep re-simulation with the recorded motion, not the "
                "run's own bodies (their forces differ where the real-time loops' timing did)",
                f->file);
    else if (identical != compared)
      log::warn("{}: the lockstep replay differs from the recording in {} frames: the series is not the recorded run's",
                f->file, compared - identical);
    return 0;
  };
}

}  // namespace tactus::app
