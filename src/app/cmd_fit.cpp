// `tactus fit EXPERIMENT.toml`: material parameters fitted to a measured indentation curve
// by simulating the experiment with the engine (docs/fitting.md).
#include <fmt/format.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "fitting/experiment.hpp"
#include "fitting/fit.hpp"
#include "fitting/indentation.hpp"
#include "fitting/plot.hpp"

namespace tactus::app {
namespace {

struct FitArgs {
  std::string experiment, output, plot, name = "fitted";
};

}  // namespace

Action add_fit(CLI::App& app) {
  auto a = std::make_shared<FitArgs>();
  app.add_option("experiment", a->experiment, "Experiment file (TOML, docs/fitting.md)")->required();
  app.add_option("-o,--output", a->output, "Write the fitted [materials.NAME] block here (default: stdout only)");
  app.add_option("--plot", a->plot, "PNG of the data against the fit (default: EXPERIMENT's stem + _fit.png)");
  app.add_option("--name", a->name, "The material's name in the block (default 'fitted')");
  app.footer("Experiment keys, CSV columns and the method: docs/fitting.md");
  return [a] {
    const fitting::Experiment e = fitting::read_experiment(a->experiment);
    const fitting::IndentationModel model(e);
    std::fprintf(stderr, "fitting %zu points with a %zu-tet specimen...\n", e.x.size(), model.mesh().tets.size());
    const fitting::FitResult r = fitting::fit(e, model);
    const std::string block = fitting::material_toml(e, r, a->name);
    std::fputs(fitting::summary(e, r).c_str(), stderr);
    std::fputs(block.c_str(), stdout);
    if (!a->output.empty()) {
      std::ofstream out(a->output, std::ios::binary);
      out << block;
      out.flush();
      if (!out) throw InputError(SourceLocation{a->output, {}, {}, {}}, "cannot write the file");
    }
    fitting::CurvePlot p;
    const bool loading = e.kind == fitting::CurveKind::depth_force;
    const bool creep = e.kind == fitting::CurveKind::time_depth;
    p.title = creep ? fmt::format("{} fit: RMS {:.3g} mm ({:.2f} %)", physics::to_string(e.law), 1e3 * r.rms,
                                  100.0 * r.relative_rms)
                    : fmt::format("{} fit: RMS {:.3g} N ({:.2f} %)", physics::to_string(e.law), r.rms, 100.0 * r.relative_rms);
    p.x_label = loading ? "depth [mm]" : "time [s]";
    p.x_scale = loading ? 1e3 : 1.0;
    p.y_label = creep ? "depth [mm]" : "force [N]";
    p.y_scale = creep ? 1e3 : 1.0;
    p.x = e.x;
    p.data = e.y;
    p.fit = r.model;
    p.fit_label = fmt::format("{} (engine)", physics::to_string(e.law));
    const std::filesystem::path plot =
        a->plot.empty() ? std::filesystem::path(a->experiment).replace_extension().string() + "_fit.png" : a->plot;
    fitting::write_plot(plot, p);
    std::fprintf(stderr, "plot written to %s\n", plot.string().c_str());
    if (!r.converged) std::fprintf(stderr, "warning: the fit did not converge: %s\n", r.status.c_str());
    return 0;
  };
}

}  // namespace tactus::app
