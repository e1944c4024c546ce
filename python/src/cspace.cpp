// tactus.ConfigurationSpace: a configuration space built by `tactus precompute`
// (precompute/space_file.hpp), read once and queried for the force (and the body's shape)
// at any tool position with the same interpolators the haptic loop uses.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>

#include "bindings.hpp"
#include "precompute/interpolator.hpp"
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
             const precompute::Interpolation how = precompute::parse_interpolation(method);
             return std::make_shared<ConfigurationSpace>(ConfigurationSpace{space, precompute::Interpolator(space, how)});
           }),
           py::arg("path"), py::arg("method") = "trilinear",
           "Reads the space file (InputError naming the file and the reason when it cannot). `method`: trilinear,\n"
           "rbf_cubic, rbf_thin_plate or polynomial.")
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
            std::vector<Vec3> p(c.space->grid.size());
            for (std::size_t i = 0; i < p.size(); ++i) p[i] = c.space->grid.point(i);
            return vec3_copy(p);
          },
          "The grid points (n, 3) [m], x fastest.")
      .def_property_readonly(
          "solved",
          [](const ConfigurationSpace& c) {
            py::array_t<bool> s(c.space->status.size());
            for (std::size_t i = 0; i < c.space->status.size(); ++i) s.mutable_at(i) = c.space->solved(i);
            return s;
          },
          "Whether each grid point was solved (n,).")
      .def_property_readonly(
          "point_forces", [](const ConfigurationSpace& c) { return vec3_copy(c.space->force); },
          "The force stored at each grid point (n, 3) [N]; zero where not solved.")
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
}

}  // namespace tactus::python
