// `tactus precompute SCENE -o SPACE.h5`: builds the configuration space of the scene's
// [precompute] table on the local cores, or over MPI ranks under mpirun / srun, with a
// checkpoint journal that --resume continues (docs/precompute.md).
// `tactus precompute SCENE --online-speed`: the largest tool speed on-line construction
// sustains on this machine's cores (no file).
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "app/commands.hpp"
#include "core/input_file.hpp"
#include "core/clock.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/parallel.hpp"
#include "core/progress.hpp"
#include "physics/fem/tet_fem.hpp"
#include "precompute/builder.hpp"
#include "precompute/distributed.hpp"
#include "precompute/journal.hpp"
#include "precompute/model_identity.hpp"
#include "precompute/online.hpp"
#include "precompute/pair.hpp"
#include "precompute/probe.hpp"
#include "precompute/refinement.hpp"
#include "precompute/space_file.hpp"
#include "precompute/time_left.hpp"
#include "compile/bodies.hpp"
#include "scene/scene.hpp"

namespace tactus::app {
namespace {

/// The message with each number (digits, a decimal point, an exponent) replaced by '#', so
/// failures that differ only in their values group together.
std::string without_numbers(const std::string& text) {
  auto digit = [](char c) { return c >= '0' && c <= '9'; };
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    if (!digit(text[i])) {
      out += text[i++];
      continue;
    }
    while (i < text.size() && (digit(text[i]) || text[i] == '.')) ++i;
    if (i + 1 < text.size() && text[i] == 'e') {
      std::size_t j = i + 1;
      if (text[j] == '+' || text[j] == '-') ++j;
      if (j < text.size() && digit(text[j])) {
        while (j < text.size() && digit(text[j])) ++j;
        i = j;
      }
    }
    out += '#';
  }
  return out;
}

namespace pc = precompute;

/// "N points, the first at grid point (i, j, k) = (x, y, z) mm: REASON", for a group of N
/// failures that differ only in their numbers (those of the first are given).
std::string failure_line(const pc::Space& space, std::size_t point, int count) {
  const std::array<int, 3> c = space.grid.cell(point);
  const Vec3 x = 1e3 * space.grid.point(point);
  const std::string reason = space.reason[point].empty() ? std::string("no reason recorded") : space.reason[point];
  return fmt::format("{} at grid point ({}, {}, {}) = ({:.2f}, {:.2f}, {:.2f}) mm: {}",
                     count == 1 ? std::string("1 point") : fmt::format("{} points, the first", count), c[0], c[1],
                     c[2], x.x(), x.y(), x.z(), reason);
}

struct PrecomputeArgs {
  std::string scene, output;
  bool resume = false;
  unsigned threads = 0;
  std::size_t stop_after = 0;
  double reissue_floor = 60.0;
  double reissue_factor = 10.0;
  unsigned in_flight = 1;
  bool online_speed = false;
  double online_first = 4.0;  ///< [mm/s]
  double online_dwell = 0.5;  ///< [s]
};

std::string read_text(const std::string& path) { return read_input_file(path); }

std::string duration_text(double seconds) {
  if (!(seconds >= 0.0) || seconds > 1e7) return "?";
  const auto s = static_cast<long>(seconds + 0.5);
  if (s >= 3600) return fmt::format("{}h{:02}m", s / 3600, (s / 60) % 60);
  if (s >= 60) return fmt::format("{}m{:02}s", s / 60, s % 60);
  return fmt::format("{}s", s);
}

/// Points done, rate and time left: redrawn on a terminal, a line per tenth otherwise. The
/// time left comes from `estimate` (the cost of the points still pending, precompute/
/// time_left.hpp) once it has one, from the mean rate until then.
class ProgressLine {
 public:
  /// `quiet`: no lines when not on a terminal (a level of many, which its summary reports).
  ProgressLine(std::size_t total, std::size_t already, const pc::TimeLeftEstimate& estimate, const pc::Space& space,
               bool quiet)
      : total_(total), already_(already), estimate_(estimate), space_(space), quiet_(quiet) {}
  void update(std::size_t done) {
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double rate = elapsed > 0.0 ? static_cast<double>(done - std::min(done, already_)) / elapsed : 0.0;
    double left = estimate_.seconds_left(space_.status, elapsed);
    if (left < 0.0) left = rate > 0.0 ? static_cast<double>(total_ - done) / rate : -1.0;
    const std::string text =
        fmt::format("precompute: {}/{} points, {:.2f} points/s, {} left", done, total_, rate, duration_text(left));
    if (terminal_) {
      if (now - last_ < std::chrono::milliseconds(100) && done < total_) return;
      last_ = now;
      std::fprintf(stderr, "\r%s   ", text.c_str());
      std::fflush(stderr);
    } else if (!quiet_ &&
               10 * done / std::max<std::size_t>(total_, 1) > 10 * reported_ / std::max<std::size_t>(total_, 1)) {
      reported_ = done;
      log::info("{}", text);
    }
  }
  void finish() {
    if (terminal_) std::fprintf(stderr, "\n");
  }

 private:
  std::size_t total_, already_, reported_ = 0;
  const pc::TimeLeftEstimate& estimate_;
  const pc::Space& space_;
  bool quiet_ = false;
  bool terminal_ = Progress::terminal_attached();
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(), last_{};
};

/// The build's outcome: points, failures grouped, time and efficiency; for a level of many
/// (`compact`), its points and failures alone.
void print_summary(const pc::Space& space, const pc::BuildStats& stats, double cpu_seconds, std::size_t resumed,
                   const std::string& where, bool compact) {
  if (!compact)
    std::printf("configuration space: %zu points (%d x %d x %d, spacing %.4g m)\n", space.grid.size(),
                space.grid.counts[0], space.grid.counts[1], space.grid.counts[2], space.grid.spacing);
  std::printf("  %ssolved %zu, failed %zu, unreachable %zu%s%s\n",
              compact ? fmt::format("{} points: ", space.grid.size()).c_str() : "", space.count(pc::PointStatus::solved),
              space.count(pc::PointStatus::failed), space.count(pc::PointStatus::unreachable),
              resumed ? fmt::format(" ({} taken from the journal)", resumed).c_str() : "",
              compact ? fmt::format(", {:.2f} s wall", stats.wall_seconds).c_str() : "");
  // Failures that differ only in their numbers are one line: how many, then the first of
  // them in full with its grid point, so the numbers are never lost to the grouping.
  struct FailureGroup {
    int count = 0;
    std::size_t first = 0;
  };
  std::map<std::string, FailureGroup> groups;
  for (std::size_t p = 0; p < space.grid.size(); ++p)
    if (space.status[p] == pc::PointStatus::failed || space.status[p] == pc::PointStatus::unreachable) {
      FailureGroup& g = groups[without_numbers(space.reason[p])];
      if (g.count++ == 0) g.first = p;
    }
  for (const auto& [pattern, g] : groups) std::printf("    %s\n", failure_line(space, g.first, g.count).c_str());
  if (compact) return;
  const double per_point = stats.computed ? stats.solve_seconds / static_cast<double>(stats.computed) : 0.0;
  std::printf("  %zu solves in %.2f s wall on %u %s: %.3f solver-seconds per point (wall time of a solve), %.3f "
              "CPU-seconds per point (getrusage, %s)\n",
              stats.computed, stats.wall_seconds, stats.workers, where.c_str(), per_point,
              stats.computed ? cpu_seconds / static_cast<double>(stats.computed) : 0.0,
              stats.solver_cpu_seconds > 0.0 ? "summed over every rank" : "this process");
  // CPU time, not solver wall time: a solver that waits for a core still counts its wall time.
  const double busy = stats.solver_cpu_seconds > 0.0 ? stats.solver_cpu_seconds : cpu_seconds;
  if (stats.wall_seconds > 0.0)
    std::printf("  parallel efficiency %.0f%% (solver CPU time / (workers x wall time))\n",
                100.0 * busy / (stats.workers * stats.wall_seconds));
}

/// --online-speed: the largest tool speed on-line construction sustains on this machine
/// (docs/precompute.md, "On-line construction").
int run_online_speed(const PrecomputeArgs& a, const physics::Body& body, const pc::SpaceSettings& settings) {
  pc::OnlineSpeedOptions o;
  o.workers = a.threads ? a.threads : std::max(1u, std::thread::hardware_concurrency());
  o.first = a.online_first * 1e-3;
  o.dwell = a.online_dwell;
  const pc::Space layout = pc::make_space(body, settings, "");
  const pc::ToolPath path = pc::scripted_path(layout.grid, layout.start);
  std::printf("on-line construction: %zu grid points (%d x %d x %d, spacing %.4g m), %u solver threads\n",
              layout.grid.size(), layout.grid.counts[0], layout.grid.counts[1], layout.grid.counts[2],
              layout.grid.spacing, o.workers);
  std::printf("  scripted path: %.1f mm through %zu waypoints, after at least %.2f s at the start point and until "
              "its neighbourhood is solved\n",
              1e3 * path.length(), path.waypoints.size(), o.dwell);
  o.on_trial = [&](const pc::DriveResult& r, const pc::Space&) {
    std::printf("  %7.2f mm/s: %5.1f%% of %zu queries complete (moved after %.2f s), %zu points solved, "
                "max force step %.3g N%s\n",
                1e3 * r.speed, 100.0 * r.fraction(), r.queries, r.wait, r.solved, r.max_step,
                r.finite ? "" : ", NON-FINITE");
    std::fflush(stdout);
  };
  const pc::SpeedSearch s = pc::online_speed(body, settings, o);
  if (!s.bounded)
    std::printf("maximum tool speed: at least %.2f mm/s (no speed up to the search's 1 m/s ceiling failed: the grid is "
                "solved before the tool gets far)\n",
                1e3 * s.max_speed);
  else if (s.max_speed > 0.0)
    std::printf("maximum tool speed: %.2f mm/s (at least %.0f%% of 1 kHz force queries while moving found their "
                "cell complete)\n",
                1e3 * s.max_speed, 100.0 * o.criterion);
  else
    std::printf("maximum tool speed: below %.2f mm/s, the first speed tried\n", a.online_first);
  return 0;
}

/// One space built, and the journal that holds it until its file is written.
struct BuiltSpace {
  pc::Space space;
  std::filesystem::path journal_path;
  int unresponsive = 0;  ///< MPI ranks that never answered
};

/// Builds one space (a point space, or one level of a probe or two-point space: `one_of_many`,
/// reported in a line and its failures) with its checkpoint journal, and refines it where the
/// settings ask. Nothing when --stop-after cut it short. Solver ranks serve the scheduler and
/// return their (empty) space.
std::optional<BuiltSpace> build_space(const PrecomputeArgs& a, pc::distributed::Session& session,
                                      const physics::Body& body, const pc::SpaceSettings& settings,
                                      const std::string& scene_text, const std::filesystem::path& journal_path,
                                      bool one_of_many);
int finish_output(const std::filesystem::path& output, pc::distributed::Session& session,
                  const std::vector<std::filesystem::path>& journals, int unresponsive);

/// "level K of N: ...", what a level of a probe or two-point space holds.
std::string level_title(const pc::SpaceSettings& level, std::size_t k, std::size_t count) {
  const std::string head = fmt::format("level {} of {}: ", k + 1, count);
  if (level.probe.enabled())
    return head + fmt::format("the probe leaning {:.1f}, {:.1f} degrees", level.tilt.x() * 180.0 / std::numbers::pi,
                              level.tilt.y() * 180.0 / std::numbers::pi);
  const char* own = level.finger == 0 ? "the first point" : "the second point";
  if (level.held_node < 0) return head + fmt::format("{}, the other free", own);
  return head + fmt::format("{}, the other held at ({:.1f}, {:.1f}, {:.1f}) mm", own, 1e3 * level.held_at.x(),
                            1e3 * level.held_at.y(), 1e3 * level.held_at.z());
}

int run_precompute(const PrecomputeArgs& a) {
  pc::distributed::Session session;
  const scene::Model model = scene::load_scene(a.scene);
  if (!model.precompute)
    throw InputError(SourceLocation{a.scene, {}, {}, {}}, "the scene has no [precompute] table (docs/scene-format.md)");
  const pc::SpaceSettings& settings = *model.precompute;
  std::size_t index = 0;
  while (model.bodies[index].name != settings.body) ++index;
  const physics::Body body = compile::make_physics_body(model, index);
  if (a.online_speed) {
    if (session.size() > 1)
      throw InputError("--online-speed runs its solvers as threads on one machine: start it without mpirun");
    if (settings.probe.enabled() || settings.pair.enabled())
      throw InputError(SourceLocation{a.scene, {}, {}, {}},
                       fmt::format("--online-speed measures on-line construction, which builds point spaces; this "
                                   "[precompute] table has {}",
                                   settings.probe.enabled() ? "a probe" : "a second point"));
    set_thread_limit(1);
    return run_online_speed(a, body, settings);
  }
  if (a.output.empty()) throw InputError("-o/--output is required (the configuration space file to write)");
  // The inner element loops run on one thread: the parallelism is across configurations.
  set_thread_limit(1);
  const std::filesystem::path output(a.output);
  const std::string scene_text = read_text(a.scene);
  // The space's levels one after another: a point space has one, a probe space one per lean
  // (precompute/probe.hpp), a two-point space 2 + nA + nB (precompute/pair.hpp), each with
  // its own journal, so that a killed build resumes in the level it was in. The file is
  // written once all are built.
  const std::vector<pc::SpaceSettings> level_list = pc::space_levels(settings, body.model->rest_positions());
  const std::size_t count = level_list.size();
  const auto started = std::chrono::steady_clock::now();
  std::vector<pc::Space> levels;
  std::vector<std::filesystem::path> journals;
  int unresponsive = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const pc::SpaceSettings& level = level_list[k];
    if (k > 0 && !session.decide(true)) return 0;  // rank 0 stopped: the solver ranks end too
    if (count > 1 && session.rank() == 0) std::printf("%s\n", level_title(level, k, count).c_str());
    const std::string journal =
        count == 1 ? output.string() + ".journal" : fmt::format("{}.level-{}.journal", a.output, k);
    auto built = build_space(a, session, body, level, scene_text, journal, count > 1);
    if (!built) {
      if (k + 1 < count) (void)session.decide(false);
      return 3;
    }
    if (session.rank() > 0) continue;  // a solver rank keeps no level
    unresponsive = built->unresponsive;
    if (unresponsive > 0 && k + 1 < count) {
      // A hung rank takes part in nothing more: the levels built are in their journals.
      log::error("{} rank(s) never answered; ending the job after level {} (continue with --resume)",
                 unresponsive, k + 1);
      std::fflush(stdout);
      session.abort_job(4);
    }
    levels.push_back(std::move(built->space));
    journals.push_back(built->journal_path);
  }
  if (session.rank() > 0) return 0;
  if (count > 1) {
    std::size_t points = 0, solved = 0;
    for (const pc::Space& level : levels) {
      points += level.point_count();
      solved += level.count(pc::PointStatus::solved);
    }
    std::printf("%zu levels: %zu points, %zu solved, %zu failed or unreachable, %.1f s wall\n", count, points, solved,
                points - solved, std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  }
  pc::write_space_levels(output, levels);
  return finish_output(output, session, journals, unresponsive);
}

/// After the file is written: removes its journals and says so. A hung rank would keep
/// MPI_Finalize from returning: the file is complete, so the job ends.
int finish_output(const std::filesystem::path& output, pc::distributed::Session& session,
                  const std::vector<std::filesystem::path>& journals, int unresponsive) {
  if (session.rank() > 0) return 0;
  std::error_code ec;
  for (const auto& j : journals) std::filesystem::remove(j, ec);
  std::printf("wrote %s\n", output.string().c_str());
  if (unresponsive > 0) {
    log::error("{} rank(s) never answered; the space is complete, ending the job", unresponsive);
    std::fflush(stdout);
    session.abort_job(4);
  }
  return 0;
}

std::optional<BuiltSpace> build_space(const PrecomputeArgs& a, pc::distributed::Session& session,
                                      const physics::Body& body, const pc::SpaceSettings& settings,
                                      const std::string& scene_text, const std::filesystem::path& journal_path,
                                      bool one_of_many) {
  pc::Space space = pc::make_space(body, settings, scene_text);
  auto make_solver = [&] { return std::make_unique<pc::ConfigurationSolver>(body, settings); };

  if (session.rank() > 0) {
    auto solver = make_solver();
    pc::distributed::serve(*solver, space, session);
    return BuiltSpace{std::move(space), journal_path, 0};
  }

  std::error_code ec;
  std::optional<pc::Journal> journal;
  if (std::filesystem::exists(journal_path, ec)) {
    if (!a.resume)
      throw InputError(SourceLocation{journal_path.string(), {}, {}, {}},
                       "an interrupted build left this journal: pass --resume to continue it, or delete it");
    journal.emplace(pc::Journal::resume(journal_path, space));
    log::info("resuming: {} of {} points from the journal", journal->recovered(), space.grid.size());
  } else {
    if (a.resume) log::info("no journal at {}: building from the start", journal_path.string());
    journal.emplace(pc::Journal::create(journal_path, space));
  }
  const std::size_t resumed = journal->recovered();

  pc::TimeLeftEstimate estimate(space.grid, space.start);
  ProgressLine progress(space.grid.size(), resumed, estimate, space, one_of_many);
  pc::BuildOptions options;
  options.threads = a.threads ? a.threads : std::max(1u, std::thread::hardware_concurrency());
  options.stop_after = a.stop_after;
  options.reissue_floor = a.reissue_floor;
  options.reissue_factor = a.reissue_factor;
  options.in_flight = a.in_flight;
  options.on_result = [&](const pc::PointResult& r) {
    journal->append(r);
    estimate.record(r);
  };
  options.on_progress = [&](std::size_t done, std::size_t) { progress.update(done); };
  const double cpu0 = process_cpu_seconds();
  pc::BuildStats stats;
  std::string where;
  if (session.size() > 1) {
    stats = pc::distributed::schedule(space, options, session);
    where = fmt::format("solver ranks (MPI, {} ranks in all)", session.size());
  } else {
    stats = pc::build_local(space, make_solver, options);
    where = stats.workers == 1 ? "thread" : "threads";
  }
  progress.finish();
  // Under MPI the solves ran on the other ranks: each reports its own CPU time at the stop.
  const double cpu = process_cpu_seconds() - cpu0 + stats.solver_cpu_seconds;
  print_summary(space, stats, cpu, resumed, where, one_of_many);
  if (stats.retried)
    std::printf("  %zu failed transitions tried again from another neighbour\n", stats.retried);
  if (stats.reissued || stats.late || stats.unresponsive)
    std::printf("  reissued %zu transitions after a timeout; ignored %zu late answers; %d ranks unresponsive\n",
                stats.reissued, stats.late, stats.unresponsive);
  if (stats.stopped) {
    std::printf("stopped after %zu solves as asked; continue with --resume\n", stats.computed);
    return std::nullopt;
  }
  if (space.settings.refine_points > 0) {
    // Not journaled: a build killed while refining resumes from the full grid and refines again.
    pc::RefineOptions refine;
    refine.points = static_cast<std::size_t>(space.settings.refine_points);
    refine.threads = options.threads;
    const pc::RefineStats r = pc::refine_local(space, make_solver, refine);
    std::printf("refined %zu cells: %zu points more (%zu not solved) in %.1f s\n", r.cells, r.points, r.failed,
                r.wall_seconds);
  }
  // The journal stays until the file holding this space is written (finish_output).
  journal->close();
  return BuiltSpace{std::move(space), journal_path, stats.unresponsive};
}

}  // namespace

Action add_precompute(CLI::App& app) {
  auto a = std::make_shared<PrecomputeArgs>();
  app.add_option("scene", a->scene, "Scene file (TOML) with a [precompute] table")->required()->check(CLI::ExistingFile);
  app.add_option("-o,--output", a->output, "Configuration space file (HDF5); required unless --online-speed");
  app.add_flag("--resume", a->resume, "Continue an interrupted build from its journal (OUTPUT.journal)");
  app.add_option("--threads", a->threads, "Worker threads without MPI (default: every core)")
      ->check(CLI::Range(1u, 4096u));
  app.add_flag("--online-speed", a->online_speed,
               "Measure the largest tool speed on-line construction sustains here (no file written)");
  app.add_option("--online-first", a->online_first, "First speed the --online-speed search tries [mm/s]")
      ->check(CLI::Range(0.01, 1000.0));
  app.add_option("--online-dwell", a->online_dwell, "Seconds at the start point before the tool moves")
      ->check(CLI::Range(0.0, 60.0));
  app.add_option("--in-flight", a->in_flight,
                 "MPI: transitions a solver rank may owe at once (2 hides a far rank's latency; default 1)")
      ->check(CLI::Range(1u, 8u));
  // After how many seconds at least an unanswered transition goes to another rank (MPI).
  app.add_option("--reissue-floor", a->reissue_floor, "")->group("")->check(CLI::Range(0.01, 1e6));
  // The timeout's multiple of the median solve time; 0 makes the floor the whole timeout
  // (tests, whose solve times swing with the machine's load).
  app.add_option("--reissue-factor", a->reissue_factor, "")->group("")->check(CLI::Range(0.0, 1e6));
  // For tests of resume: behave as if killed after this many solves.
  app.add_option("--stop-after", a->stop_after, "")->group("");
  app.footer("Under mpirun or srun with N > 1 ranks, rank 0 schedules and ranks 1..N-1 solve. "
             "Design, file layout and cluster use: docs/precompute.md");
  return [a] { return run_precompute(*a); };
}

}  // namespace tactus::app
