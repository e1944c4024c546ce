// tactus.ConfigurationSpace: a configuration space built by `tactus precompute`
// (precompute/space_file.hpp), read once and queried for the force (and the body's shape)
// at any tool position with the same interpolators the haptic loop uses.
#include <fmt/format.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <filesystem>
#include <thread>

#include "bindings.hpp"
#include "compile/bodies.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "precompute/builder.hpp"
#include "precompute/configuration_solver.hpp"
#include "precompute/interpolator.hpp"
#include "precompute/refinement.hpp"
#include "precompute/space_file.hpp"

namespace tactus::python {
namespace {

struct ConfigurationSpace {
  std::shared_ptr<const precompute::Space> space;
  precompute::Interpolator interpolator;
};

/// Query points as an (n, 3) array from one point (3,) or many (n, 3).
Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> points_of(const py::array_t<double>& p) {
  if (p.ndim() == 1 && p.shape(0) == 3) {
    Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> one(1, 3);
    for (py::ssize_t k = 0; k < 3; ++k) one(0, k) = p.at(k);
    return one;
  }
  if (p.ndim() != 2 || p.shape(1) != 3)
    throw py::value_error("points must have shape (3,) or (n, 3), in metres");
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> out(p.shape(0), 3);
  const auto r = p.unchecked<2>();
  for (py::ssize_t i = 0; i < p.shape(0); ++i)
    for (py::ssize_t k = 0; k < 3; ++k) out(i, k) = r(i, k);
  return out;
}

}  // namespace

void bind_cspace(py::module_& m) {
  py::class_<ConfigurationSpace, std::shared_ptr<ConfigurationSpace>>(
      m, "ConfigurationSpace",
      "A precomputed configuration space (`tactus precompute`), queried at tool positions with the haptic\n"
      "loop's interpolators. Forces are what the body exerts on the tool [N]; positions in metres.")
      .def(py::init([](const std::filesystem::path& path, const std::string& method) {
             auto space = std::make_shared<const precompute::Space>(precompute::read_space(path));
             if (space->settings.probe.enabled() || space->settings.pair.enabled())
               throw InputError(SourceLocation{path.string(), {}, {}, {}},
                                space->settings.probe.enabled()
                                    ? "a probe space (levels of leans): ConfigurationSpace reads point spaces only; a "
                                      "scene's cspace body renders probe spaces"
                                    : "a two-point space (levels of a second point): ConfigurationSpace reads point "
                                      "spaces only; a scene's cspace body renders two-point spaces");
             const precompute::Interpolation how = precompute::parse_interpolation(method);
             return std::make_shared<ConfigurationSpace>(ConfigurationSpace{space, precompute::Interpolator(space, how)});
           }),
           py::arg("path"), py::arg("method") = "trilinear",
           "Reads the space file (InputError naming the file and the reason when it cannot). `method`: trilinear,\n"
           "rbf_cubic, rbf_thin_plate, polynomial, tricubic_hermite or rbf_hermite (these two need a space with\n"
           "derivatives: one built by this version).")
      .def_property_readonly("method",
                             [](const ConfigurationSpace& c) { return std::string(precompute::to_string(c.interpolator.method())); })
      .def_property_readonly("body", [](const ConfigurationSpace& c) { return c.space->settings.body; })
      .def_property_readonly("spacing", [](const ConfigurationSpace& c) { return c.space->grid.spacing; },
                             "The grid's spacing [m].")
      .def_property_readonly("counts", [](const ConfigurationSpace& c) { return c.space->grid.counts; },
                             "Grid points along x, y and z.")
      .def_property_readonly(
          "points",
          [](const ConfigurationSpace& c) {
            std::vector<Vec3> p(c.space->point_count());
            for (std::size_t i = 0; i < p.size(); ++i) p[i] = c.space->position(i);
            return vec3_copy(p);
          },
          "The points (n, 3) [m]: the grid's, x fastest, then those refinement added (refine_points).")
      .def_property_readonly(
          "solved",
          [](const ConfigurationSpace& c) {
            py::array_t<bool> s(c.space->status.size());
            for (std::size_t i = 0; i < c.space->status.size(); ++i) s.mutable_at(i) = c.space->solved(i);
            return s;
          },
          "Whether each point was solved (n,).")
      .def_property_readonly(
          "point_forces", [](const ConfigurationSpace& c) { return vec3_copy(c.space->force); },
          "The force stored at each point (n, 3) [N]; zero where not solved.")
      .def_property_readonly(
          "point_stiffness",
          [](const ConfigurationSpace& c) {
            const auto n = static_cast<py::ssize_t>(c.space->point_count());
            py::array_t<double> k({n, py::ssize_t{3}, py::ssize_t{3}});
            auto w = k.mutable_unchecked<3>();
            for (py::ssize_t p = 0; p < n; ++p)
              for (py::ssize_t i = 0; i < 3; ++i)
                for (py::ssize_t j = 0; j < 3; ++j)
                  w(p, i, j) = c.space->force_gradient[static_cast<std::size_t>(p)](i, j);
            return k;
          },
          "∂force/∂x at each point (n, 3, 3) [N/m]: [p, i, k] = ∂F_i/∂x_k, the stiffness the tool feels\n"
          "there; zero where not solved or the file (version 1) has no derivatives.")
      .def(
          "force",
          [](const ConfigurationSpace& c, const py::array_t<double>& p) {
            const auto points = points_of(p);
            py::array_t<double> forces({points.rows(), Eigen::Index{3}});
            py::array_t<bool> valid(points.rows());
            auto f = forces.mutable_unchecked<2>();
            for (Eigen::Index i = 0; i < points.rows(); ++i) {
              const precompute::Query q = c.interpolator.force(points.row(i).transpose());
              for (py::ssize_t k = 0; k < 3; ++k) f(i, k) = q.force[k];
              valid.mutable_at(i) = q.valid;
            }
            return py::make_tuple(forces, valid);
          },
          py::arg("points"),
          "The interpolated force at each point, (forces (n, 3) [N], valid (n,)): valid is False where no\n"
          "solved grid point is near. Points outside the grid are clamped onto its box.")
      .def(
          "shape",
          [](const ConfigurationSpace& c, const py::array_t<double>& p) {
            const auto points = points_of(p);
            if (points.rows() != 1) throw py::value_error("shape() takes one point of shape (3,)");
            VecX displacement;
            const precompute::Query q = c.interpolator.shape(points.row(0).transpose(), displacement);
            const auto nodes = static_cast<py::ssize_t>(displacement.size() / 3);
            py::array_t<double> u({nodes, py::ssize_t{3}});
            auto w = u.mutable_unchecked<2>();
            for (py::ssize_t n = 0; n < nodes; ++n)
              for (py::ssize_t k = 0; k < 3; ++k) w(n, k) = displacement[3 * n + k];
            return py::make_tuple(vec3_copy({q.force}), u, q.valid);
          },
          py::arg("point"),
          "The interpolated force (1, 3) [N], the body's nodal displacements (nodes, 3) [m] and whether the\n"
          "point had solved neighbours.");
  m.def(
      "build_space",
      [](const ModelHandle& model, const std::filesystem::path& output, unsigned threads) {
        if (!model->precompute)
          throw InputError(SourceLocation{model->source, {}, {}, {}},
                           "the scene has no [precompute] table (docs/scene-format.md)");
        const precompute::SpaceSettings& settings = *model->precompute;
        // build_space writes a space of one level; a probe's or a second point's levels are
        // built by the command.
        if (settings.probe.enabled() || settings.pair.enabled())
          throw InputError(SourceLocation{model->source, {}, {}, {}},
                           fmt::format("the [precompute] table has {}: build_space builds point spaces; build this "
                                       "one with `tactus precompute`",
                                       settings.probe.enabled() ? "a probe" : "a second point"));
        std::size_t index = 0;
        while (model->bodies[index].name != settings.body) ++index;
        py::dict out;
        py::gil_scoped_release release;
        const physics::Body body = compile::make_physics_body(*model, index);
        precompute::Space space = precompute::make_space(body, settings, model->text);
        precompute::BuildOptions options;
        options.threads = threads > 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
        // As `tactus precompute`: the solvers run side by side, each one's element loops on
        // its own thread; the pool's size is put back afterwards.
        const unsigned pool = thread_count();
        set_thread_limit(1);
        precompute::BuildStats stats;
        try {
          const precompute::SolverFactory solver = [&] {
            return std::make_unique<precompute::ConfigurationSolver>(body, settings);
          };
          stats = precompute::build_local(space, solver, options);
          if (settings.refine_points > 0) {
            precompute::RefineOptions refine;
            refine.points = static_cast<std::size_t>(settings.refine_points);
            refine.threads = options.threads;
            precompute::refine_local(space, solver, refine);
          }
        } catch (...) {
          set_thread_limit(pool);
          throw;
        }
        set_thread_limit(pool);
        precompute::write_space(output, space);
        std::size_t solved = 0;
        for (std::size_t p = 0; p < space.point_count(); ++p) solved += space.solved(p);
        py::gil_scoped_acquire gil;
        out["points"] = space.point_count();
        out["solved"] = solved;
        out["unreachable"] = stats.unreachable;
        out["solves"] = stats.computed;
        out["wall_seconds"] = stats.wall_seconds;
        out["threads"] = stats.workers;
        return out;
      },
      py::arg("model"), py::arg("output"), py::arg("threads") = 0,
      "Builds the scene's configuration space ([precompute] table) on this machine's threads, as\n"
      "`tactus precompute SCENE -o OUTPUT` without MPI (refined as its refine_points asks), and writes it\n"
      "(HDF5). threads: solver threads (0: every core). Returns {points, solved, unreachable, solves,\n"
      "wall_seconds, threads}; open the file with ConfigurationSpace. The GIL is released while it builds;\n"
      "it is not interruptible.\n"
      "Raises tactus.InputError for a scene without [precompute] or a file that cannot be written.");
}

}  // namespace tactus::python
