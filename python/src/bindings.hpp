#pragma once
// The parts of the tactus._tactus extension, one file each, and the helpers they share.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "core/math.hpp"
#include "runtime/session.hpp"
#include "scene/model.hpp"

namespace tactus::python {

namespace py = pybind11;

void bind_errors(py::module_& m);      // errors.cpp: InputError and its translation
void bind_model(py::module_& m);       // model.cpp: Model and its parts, load_scene, parse_scene
void bind_run(py::module_& m);         // run.cpp: run() in lockstep and its RunResult
void bind_simulation(py::module_& m);  // simulation.cpp: Simulation, stepped frame by frame
void bind_solve(py::module_& m);       // solve.cpp: solve() and its results
void bind_recording(py::module_& m);   // recording.cpp: read_recording()
void bind_cspace(py::module_& m);      // cspace.cpp: ConfigurationSpace, read and queried
void bind_mesh(py::module_& m);        // mesh.cpp: read_mesh(), write_mesh()

/// What tactus.Model holds: the scene and the text it was read from (a recording stores the
/// text, so that it replays by itself).
struct LoadedModel : scene::Model {
  std::string text;
};
using ModelHandle = std::shared_ptr<LoadedModel>;

/// What tactus.RunResult holds: a run's report, its frames sorted device by device.
struct RunResult;
/// The RunResult of a finished run (run.cpp).
py::object make_run_result(runtime::SessionReport&& report, const scene::Model& model);

/// A read-only NumPy view of one field of `rows` records stored `stride` bytes apart:
/// (rows,) for a scalar (cols = 0), (rows, cols) for `cols` contiguous values; `first` is
/// the field of the first record (any valid address when rows = 0). Kept valid by `owner`.
template <class T>
py::array field_view(const T* first, std::size_t rows, std::size_t stride, std::size_t cols, py::handle owner) {
  std::vector<std::size_t> shape{rows}, strides{stride};
  if (cols > 0) {
    shape.push_back(cols);
    strides.push_back(sizeof(T));
  }
  py::array a(py::dtype::of<T>(), shape, strides, rows ? first : nullptr, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

/// An (n, K) read-only view of index records (triangles, tets), kept alive by `owner`.
template <class Index, std::size_t K>
py::array index_view(const std::vector<std::array<Index, K>>& v, py::handle owner) {
  return field_view<Index>(v.empty() ? nullptr : v.front().data(), v.size(), sizeof(std::array<Index, K>), K, owner);
}
/// An (n,) read-only view of a vector of numbers, kept alive by `owner`.
template <class T>
py::array vector_view(const std::vector<T>& v, py::handle owner) {
  return field_view<T>(v.data(), v.size(), sizeof(T), 0, owner);
}

/// A NumPy view of `rows` 3-vectors stored `stride` bytes apart from `first`, kept valid by
/// `owner` (the array holds a reference to it: the memory lives as long as the array).
/// Read-only unless `writeable`.
inline py::array vec3_view(const Vec3* first, std::size_t rows, std::size_t stride, py::handle owner,
                           bool writeable = false) {
  py::array a(py::dtype::of<double>(), {rows, std::size_t{3}},
              {stride, sizeof(double)}, first ? first->data() : nullptr, owner);
  if (!writeable) py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}
/// The same over a contiguous std::vector<Vec3>.
inline py::array vec3_view(const std::vector<Vec3>& v, py::handle owner, bool writeable = false) {
  return vec3_view(v.data(), v.size(), sizeof(Vec3), owner, writeable);
}
/// A copy of 3-vectors as an (n, 3) array (for values the engine does not keep in place).
inline py::array_t<double> vec3_copy(const std::vector<Vec3>& v) {
  py::array_t<double> a({v.size(), std::size_t{3}});
  auto w = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < v.size(); ++i)
    for (py::ssize_t k = 0; k < 3; ++k) w(static_cast<py::ssize_t>(i), k) = v[i][k];
  return a;
}

}  // namespace tactus::python
