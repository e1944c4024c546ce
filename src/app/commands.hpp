#pragma once
// Each subcommand registers its options on the CLI and returns the action to run.
#include <CLI/CLI.hpp>
#include <functional>

namespace tactus::app {

/// Runs after parsing; returns the process exit code. Throws InputError for user errors.
using Action = std::function<int()>;

Action add_version(CLI::App& app);
Action add_inspect(CLI::App& app);
Action add_mesh(CLI::App& app);
Action add_run(CLI::App& app);
Action add_solve(CLI::App& app);
Action add_bench(CLI::App& app);
Action add_replay(CLI::App& app);
Action add_export(CLI::App& app);
Action add_precompute(CLI::App& app);
Action add_snapshot(CLI::App& app);
Action add_curves(CLI::App& app);
Action add_fit(CLI::App& app);

}  // namespace tactus::app
