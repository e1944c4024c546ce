// The `tactus` command. Exit codes: 0 success, 1 user error (bad file, key or flag),
// 2 internal error. Errors are one line on stderr.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/realtime.hpp"
#include "core/reproducible.hpp"

namespace {

struct Subcommand {
  CLI::App* app;
  tactus::app::Action action;
};

}  // namespace

int main(int argc, char** argv) {
  // The same numbers on every machine: a recording replays bit for bit elsewhere.
  tactus::fix_dense_blocking();
  tactus::fix_blas_threads();
  tactus::keep_freed_memory();
  CLI::App cli{"Tactus: real-time haptic interaction with deformable objects", "tactus"};
  cli.require_subcommand(1);
  bool verbose = false;
  bool quiet = false;
  cli.add_flag("-v,--verbose", verbose, "Print debug messages");
  cli.add_flag("-q,--quiet", quiet, "Print errors only");

  std::vector<Subcommand> subcommands;
  auto add = [&](tactus::app::Action (*registrar)(CLI::App&), const char* name, const char* help) {
    CLI::App* sub = cli.add_subcommand(name, help);
    subcommands.push_back({sub, registrar(*sub)});
  };
  add(tactus::app::add_version, "version", "Print the version and build information");
  add(tactus::app::add_inspect, "inspect", "Summarize and check a mesh or scene file");
  add(tactus::app::add_mesh, "mesh", "Convert, generate or tetrahedralize meshes");
  add(tactus::app::add_run, "run", "Run a scene (the built-in default without one) through the haptic loops");
  add(tactus::app::add_bench, "bench", "Run a scene for a fixed time and print the loop timing table");
  add(tactus::app::add_replay, "replay", "Re-run a recording's scene with its device motion and compare the forces");
  add(tactus::app::add_export, "export", "Write a recording's frames, steps and events as CSV");
  add(tactus::app::add_solve, "solve", "Solve a scene's bodies to equilibrium or a time; probes and reactions");
  add(tactus::app::add_precompute, "precompute", "Build a scene's configuration space (HDF5), locally or under mpirun");
  add(tactus::app::add_snapshot, "snapshot", "Render a scene at a time of a lockstep run to PNG, offscreen");
  add(tactus::app::add_curves, "curves", "Press a scene's tissues and write seed 000's force and viscoelastic curves (CSV, PNG)");
  add(tactus::app::add_fit, "fit", "Fit material parameters to a measured indentation or relaxation curve (TOML + CSV)");

  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return cli.exit(e);  // --help
    std::fprintf(stderr, "tactus: %s (see 'tactus --help')\n", e.what());
    return 1;
  }

  tactus::log::init(verbose ? tactus::log::Level::debug
                            : quiet ? tactus::log::Level::quiet : tactus::log::Level::info);
  try {
    for (const auto& s : subcommands)
      if (s.app->parsed()) return s.action();
    return 2;
  } catch (const tactus::InputError& e) {
    std::fprintf(stderr, "tactus: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tactus: internal error: %s\n", e.what());
    return 2;
  }
}
