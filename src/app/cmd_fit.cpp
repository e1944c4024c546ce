// `tactus fit EXPERIMENT.toml...`: material parameters fitted to measured indentation curves
// by simulating the experiments with the engine (docs/fitting.md).
#include <fmt/format.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "fitting/experiment.hpp"
#include "fitting/fit.hpp"
#include "fitting/indentation.hpp"
#include "fitting/plot.hpp"

namespace tactus::app {
namespace {

struct FitArgs {
  std::vector<std::string> experiments;
  std::string output, plot, name = "fitted";
};

/// Experiment `e`'s data against its fit, as a PNG at `path`.
void write_fit_plot(const fitting::Experiment& e, const fitting::ExperimentFit& x, const std::filesystem::path& path) {
  fitting::CurvePlot p;
  const bool loading = e.kind == fitting::CurveKind::depth_force;
  const bool creep = e.kind == fitting::CurveKind::time_depth;
  p.title = creep ? fmt::format("{} fit: RMS {:.3g} mm ({:.2f} %)", e.model_name(), 1e3 * x.rms,
                                100.0 * x.relative_rms)
                  : fmt::format("{} fit: RMS {:.3g} N ({:.2f} %)", e.model_name(), x.rms, 100.0 * x.relative_rms);
  p.x_label = loading ? "depth [mm]" : "time [s]";
  p.x_scale = loading ? 1e3 : 1.0;
  p.y_label = creep ? "depth [mm]" : "force [N]";
  p.y_scale = creep ? 1e3 : 1.0;
  p.x = e.x;
  p.data = e.y;
  p.fit = x.model;
  p.fit_label = fmt::format("{} (engine)", e.model_name());
  fitting::write_plot(path, p);
  std::fprintf(stderr, "plot written to %s\n", path.string().c_str());
}

}  // namespace

Action add_fit(CLI::App& app) {
  auto a = std::make_shared<FitArgs>();
  app.add_option("experiments", a->experiments,
                 "Experiment file(s) (TOML, docs/fitting.md); several: one material fitted to all of them")
      ->required();
  app.add_option("-o,--output", a->output, "Write the fitted [materials.NAME] block here (default: stdout only)");
  app.add_option("--plot", a->plot,
                 "PNG of the data against the fit (default: each experiment's stem + _fit.png; one experiment only)");
  app.add_option("--name", a->name, "The material's name in the block (default 'fitted')");
  app.footer("Experiment keys, CSV columns and the method: docs/fitting.md");
  return [a] {
    if (!a->plot.empty() && a->experiments.size() > 1)
      throw InputError("--plot names one PNG: with several experiments each gets its own (its stem + _fit.png)");
    std::vector<fitting::Experiment> experiments;
    for (const auto& file : a->experiments) experiments.push_back(fitting::read_experiment(file));
    std::vector<std::unique_ptr<fitting::IndentationModel>> models;
    std::vector<const fitting::Experiment*> experiment_ptrs;
    std::vector<const fitting::IndentationModel*> model_ptrs;
    std::size_t points = 0;
    for (const auto& e : experiments) {
      models.push_back(std::make_unique<fitting::IndentationModel>(e));
      experiment_ptrs.push_back(&e);
      model_ptrs.push_back(models.back().get());
      points += e.x.size();
    }
    std::fprintf(stderr, "fitting %zu points of %zu experiment(s) with a %zu-tet specimen%s...\n", points,
                 experiments.size(), models.front()->mesh().tets.size(), experiments.size() > 1 ? " (the first)" : "");
    const fitting::FitResult r = fitting::fit(experiment_ptrs, model_ptrs);
    const std::string block = fitting::material_toml(experiments.front(), r, a->name);
    std::fputs(fitting::summary(experiment_ptrs, r).c_str(), stderr);
    std::fputs(block.c_str(), stdout);
    if (!a->output.empty()) {
      std::ofstream out(a->output, std::ios::binary);
      out << block;
      out.flush();
      if (!out) throw InputError(SourceLocation{a->output, {}, {}, {}}, "cannot write the file");
    }
    for (std::size_t k = 0; k < experiments.size(); ++k)
      write_fit_plot(experiments[k], r.experiments[k],
                     a->plot.empty() ? std::filesystem::path(a->experiments[k]).replace_extension().string() + "_fit.png"
                                     : a->plot);
    if (!r.converged) std::fprintf(stderr, "warning: the fit did not converge: %s\n", r.status.c_str());
    return 0;
  };
}

}  // namespace tactus::app
