// tactus.ConfigurationSpace: a configuration space built by `tactus precompute`
// (precompute/space_file.hpp), read once and queried for the force (and the body's shape)
// at any tool position with the same interpolators the haptic loop uses.
#include <fmt/format.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <thread>

#include "bindings.hpp"
#include "compile/bodies.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "precompute/builder.hpp"
#include "precompute/configuration_solver.hpp"
#include "precompute/interpolator.hpp"
#include "precompute/probe.hpp"
#include "precompute/refinement.hpp"
#include "precompute/space_file.hpp"

namespace tactus::python {
namespace {

/// A point space (one level, `point`) or a probe space (a level per lean, `probe`).
struct ConfigurationSpace {
  std::vector<std::shared_ptr<const precompute::Space>> levels;
  std::optional<precompute::Interpolator> point;
  std::optional<precompute::ProbeInterpolator> probe;

  [[nodiscard]] const precompute::Space& space() const { return *levels.front(); }
  [[nodiscard]] precompute::Interpolation method() const {
    return point ? point->method() : probe->level(0).method();
  }
  /// The per-point arrays of a point space; a probe space has them per lean.
  [[nodiscard]] const precompute::Space& one_level(const char* what) const {
    if (probe)
      throw py::value_error(fmt::format("{}: a probe space holds it per lean; read it from space.level(k)", what));
    return space();
  }
};

/// One direction (3,), or one per point (n, 3), as n unit-free directions; each must be finite
/// and not zero.
std::vector<Vec3> directions_of(const py::array_t<double>& d, Eigen::Index n) {
  std::vector<Vec3> out;
  if (d.ndim() == 1 && d.shape(0) == 3) {
    out.assign(static_cast<std::size_t>(n), Vec3(d.at(0), d.at(1), d.at(2)));
  } else if (d.ndim() == 2 && d.shape(0) == n && d.shape(1) == 3) {
    const auto r = d.unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i) out.emplace_back(r(i, 0), r(i, 1), r(i, 2));
  } else {
    throw py::value_error(fmt::format("directions must have shape (3,) or ({}, 3), one per point", n));
  }
  for (const Vec3& v : out)
    if (!v.allFinite() || v.norm() == 0.0) throw py::value_error("a probe direction must be finite and not zero");
  return out;
}

/// The probe's directions of a probe space's query: required there, refused for a point space.
std::vector<Vec3> query_directions(const ConfigurationSpace& c, const std::optional<py::array_t<double>>& d,
                                   Eigen::Index n) {
  if (!c.probe) {
    if (d) throw py::value_error("a point space takes no probe direction");
    return {};
  }
  if (!d) throw py::value_error("a probe space needs the probe's direction (3,) or (n, 3)");
  return directions_of(*d, n);
}

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

/// (values (n, 3), valid (n,)): the interpolated force, or with `torque` the torque, at each
/// point, with the probe's direction on a probe space.
py::tuple query_points(const ConfigurationSpace& c, const py::array_t<double>& p,
                       const std::optional<py::array_t<double>>& d, bool torque) {
  const auto points = points_of(p);
  const std::vector<Vec3> directions = query_directions(c, d, points.rows());
  py::array_t<double> values({points.rows(), Eigen::Index{3}});
  py::array_t<bool> valid(points.rows());
  auto v = values.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    const Vec3 at = points.row(i).transpose();
    const Vec3* direction = c.probe ? &directions[static_cast<std::size_t>(i)] : nullptr;
    const precompute::Query q = torque ? (direction ? c.probe->force_and_torque(at, *direction)
                                                    : c.point->force_and_torque(at))
                                       : (direction ? c.probe->force(at, *direction) : c.point->force(at));
    const Vec3& value = torque ? q.torque : q.force;
    for (py::ssize_t k = 0; k < 3; ++k) v(i, k) = value[k];
    valid.mutable_at(i) = q.valid;
  }
  return py::make_tuple(values, valid);
}

}  // namespace

void bind_cspace(py::module_& m) {
  py::class_<ConfigurationSpace, std::shared_ptr<ConfigurationSpace>>(
      m, "ConfigurationSpace",
      "A precomputed configuration space (`tactus precompute`), queried at tool positions with the haptic\n"
      "loop's interpolators. Forces are what the body exerts on the tool [N]; positions in metres.")
      .def(py::init([](const std::filesystem::path& path, const std::string& method) {
             std::vector<std::shared_ptr<const precompute::Space>> levels;
             for (auto& level : precompute::read_space_levels(path))
               levels.push_back(std::make_shared<const precompute::Space>(std::move(level)));
             const precompute::SpaceSettings& settings = levels.front()->settings;
             if (settings.pair.enabled())
               throw InputError(SourceLocation{path.string(), {}, {}, {}},
                                "a two-point space (levels of a second point): ConfigurationSpace reads point and "
                                "probe spaces; a scene's cspace body renders two-point spaces");
             const precompute::Interpolation how = precompute::parse_interpolation(method);
             auto c = std::make_shared<ConfigurationSpace>();
             c->levels = levels;
             if (!settings.probe.enabled()) {
               c->point.emplace(levels.front(), how);
               return c;
             }
             try {
               c->probe.emplace(std::move(levels), how);
             } catch (const InputError& e) {
               throw InputError(SourceLocation{path.string(), {}, {}, {}}, e.reason());
             }
             return c;
           }),
           py::arg("path"), py::arg("method") = "trilinear",
           "Reads the space file, a point space or a probe space (InputError naming the file and the reason\n"
           "when it cannot). `method`: trilinear, rbf_cubic, rbf_thin_plate, polynomial, tricubic_hermite or\n"
           "rbf_hermite (these two need a space with derivatives: one built by this version).")
      .def_property_readonly("method",
                             [](const ConfigurationSpace& c) { return std::string(precompute::to_string(c.method())); })
      .def_property_readonly("body", [](const ConfigurationSpace& c) { return c.space().settings.body; })
      .def_property_readonly("spacing", [](const ConfigurationSpace& c) { return c.space().grid.spacing; },
                             "The grid's spacing [m].")
      .def_property_readonly("counts", [](const ConfigurationSpace& c) { return c.space().grid.counts; },
                             "Grid points along x, y and z.")
      .def_property_readonly(
          "probe",
          [](const ConfigurationSpace& c) -> py::object {
            if (!c.probe) return py::none();
            const precompute::ProbeSettings& probe = c.space().settings.probe;
            std::vector<Vec3> directions;
            for (std::size_t k = 0; k < c.levels.size(); ++k)
              directions.push_back(c.probe->frame().direction(precompute::level_tilt(probe, k)));
            py::dict out;
            out["axis"] = vec3_copy({probe.axis});
            out["max_tilt"] = probe.max_tilt;
            out["tilt_levels"] = probe.tilt_levels;
            out["directions"] = vec3_copy(directions);
            return out;
          },
          "None for a point space. For a probe space: {axis (1, 3), max_tilt [rad], tilt_levels (leans per\n"
          "tangent axis), directions (levels, 3): each level's probe direction, level k at lean\n"
          "(k mod tilt_levels, k div tilt_levels) of the lattice from -max_tilt to max_tilt}.")
      .def_property_readonly("level_count", [](const ConfigurationSpace& c) { return c.levels.size(); },
                             "Levels in the file: 1 for a point space, one per lean for a probe space.")
      .def(
          "level",
          [](const ConfigurationSpace& c, std::size_t k) {
            if (k >= c.levels.size())
              throw py::index_error(fmt::format("level {} of a space of {} levels", k, c.levels.size()));
            auto one = std::make_shared<ConfigurationSpace>();
            one->levels = {c.levels[k]};
            one->point.emplace(c.levels[k], c.method());
            return one;
          },
          py::arg("k"),
          "Level k as a point space of its own (a probe space's lean k held fixed), with this space's method.")
      .def_property_readonly(
          "points",
          [](const ConfigurationSpace& c) {
            const precompute::Space& space = c.one_level("points");
            std::vector<Vec3> p(space.point_count());
            for (std::size_t i = 0; i < p.size(); ++i) p[i] = space.position(i);
            return vec3_copy(p);
          },
          "The points (n, 3) [m]: the grid's, x fastest, then those refinement added (refine_points).\n"
          "A probe space refines each lean on its own: read them per lean, from level(k).")
      .def_property_readonly(
          "solved",
          [](const ConfigurationSpace& c) {
            const precompute::Space& space = c.one_level("solved");
            py::array_t<bool> s(space.status.size());
            for (std::size_t i = 0; i < space.status.size(); ++i) s.mutable_at(i) = space.solved(i);
            return s;
          },
          "Whether each point was solved (n,).")
      .def_property_readonly(
          "point_forces", [](const ConfigurationSpace& c) { return vec3_copy(c.one_level("point_forces").force); },
          "The force stored at each point (n, 3) [N]; zero where not solved.")
      .def_property_readonly(
          "point_stiffness",
          [](const ConfigurationSpace& c) {
            const precompute::Space& space = c.one_level("point_stiffness");
            const auto n = static_cast<py::ssize_t>(space.point_count());
            py::array_t<double> k({n, py::ssize_t{3}, py::ssize_t{3}});
            auto w = k.mutable_unchecked<3>();
            for (py::ssize_t p = 0; p < n; ++p)
              for (py::ssize_t i = 0; i < 3; ++i)
                for (py::ssize_t j = 0; j < 3; ++j)
                  w(p, i, j) = space.force_gradient[static_cast<std::size_t>(p)](i, j);
            return k;
          },
          "∂force/∂x at each point (n, 3, 3) [N/m]: [p, i, k] = ∂F_i/∂x_k, the stiffness the tool feels\n"
          "there; zero where not solved or the file (version 1) has no derivatives.")
      .def_property_readonly(
          "point_torques", [](const ConfigurationSpace& c) { return vec3_copy(c.one_level("point_torques").torque); },
          "The torque stored at each point (n, 3) [N·m] about the interaction point; zero where not solved\n"
          "or the file (before version 3) has no torques.")
      .def(
          "force",
          [](const ConfigurationSpace& c, const py::array_t<double>& p, const std::optional<py::array_t<double>>& d) {
            return query_points(c, p, d, false);
          },
          py::arg("points"), py::arg("directions") = py::none(),
          "The interpolated force at each point, (forces (n, 3) [N], valid (n,)): valid is False where no\n"
          "solved grid point is near. Points outside the grid are clamped onto its box. A probe space needs\n"
          "the probe's direction, pointing into the body: one (3,) for every point or one per point (n, 3);\n"
          "a lean beyond max_tilt is clamped onto it. A point space takes none.")
      .def(
          "torque",
          [](const ConfigurationSpace& c, const py::array_t<double>& p, const std::optional<py::array_t<double>>& d) {
            if (!c.space().has_torques)
              throw py::value_error("the space's file (before version 3) stores no torques: build it again");
            return query_points(c, p, d, true);
          },
          py::arg("points"), py::arg("directions") = py::none(),
          "The interpolated torque the body exerts on the tool about the interaction point (a probe's end),\n"
          "(torques (n, 3) [N·m], valid (n,)), taken as force() is: the moment of the contact patch's\n"
          "reactions (zero for a patch of one node). ValueError for a file without torques (before version 3).")
      .def(
          "shape",
          [](const ConfigurationSpace& c, const py::array_t<double>& p, const std::optional<py::array_t<double>>& d) {
            const auto points = points_of(p);
            if (points.rows() != 1) throw py::value_error("shape() takes one point of shape (3,)");
            const std::vector<Vec3> directions = query_directions(c, d, 1);
            VecX displacement;
            const Vec3 at = points.row(0).transpose();
            const precompute::Query q =
                c.probe ? c.probe->shape(at, directions.front(), displacement) : c.point->shape(at, displacement);
            const auto nodes = static_cast<py::ssize_t>(displacement.size() / 3);
            py::array_t<double> u({nodes, py::ssize_t{3}});
            auto w = u.mutable_unchecked<2>();
            for (py::ssize_t n = 0; n < nodes; ++n)
              for (py::ssize_t k = 0; k < 3; ++k) w(n, k) = displacement[3 * n + k];
            return py::make_tuple(vec3_copy({q.force}), u, q.valid);
          },
          py::arg("point"), py::arg("direction") = py::none(),
          "The interpolated force (1, 3) [N], the body's nodal displacements (nodes, 3) [m] and whether the\n"
          "point had solved neighbours. A probe space needs the probe's direction (3,).");
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
