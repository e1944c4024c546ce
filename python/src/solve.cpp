// tactus.solve: `tactus solve` (offline/solve.hpp) on a loaded model: static equilibrium by
// load stepping, or dynamics to a time. Results are copied into NumPy arrays (the C++
// result is a temporary).
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "offline/solve.hpp"

namespace tactus::python {
namespace {

/// (rows, groups, 3) from each row's per-group vectors.
py::array_t<double> stack_rows(const std::vector<offline::SolveRow>& rows,
                               std::vector<Vec3> offline::SolveRow::*field, std::size_t groups) {
  py::array_t<double> a({rows.size(), groups, std::size_t{3}});
  auto w = a.mutable_unchecked<3>();
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto& v = rows[r].*field;
    for (std::size_t g = 0; g < groups; ++g)
      for (py::ssize_t k = 0; k < 3; ++k)
        w(static_cast<py::ssize_t>(r), static_cast<py::ssize_t>(g), k) = g < v.size() ? v[g][k] : 0.0;
  }
  return a;
}

py::dict body_result(const offline::BodySolve& b) {
  py::dict out;
  out["body"] = b.body;
  out["probe_names"] = b.probe_names;
  out["region_names"] = b.region_names;
  py::array_t<double> time(b.rows.size());
  py::array_t<int> step(b.rows.size()), iterations(b.rows.size());
  py::array_t<bool> converged(b.rows.size());
  for (std::size_t r = 0; r < b.rows.size(); ++r) {
    time.mutable_at(r) = b.rows[r].time;
    step.mutable_at(r) = b.rows[r].step;
    iterations.mutable_at(r) = b.rows[r].linear_iterations;
    converged.mutable_at(r) = b.rows[r].converged;
  }
  out["time"] = time;
  out["step"] = step;
  out["linear_iterations"] = iterations;
  out["converged"] = converged;
  out["probe_displacements"] = stack_rows(b.rows, &offline::SolveRow::probe_displacements, b.probe_names.size());
  out["reactions"] = stack_rows(b.rows, &offline::SolveRow::reactions, b.region_names.size());
  out["final_positions"] = vec3_copy(b.final_positions);
  out["failure"] = b.failure;
  out["step_halvings"] = b.step_halvings;
  return out;
}

}  // namespace

void bind_solve(py::module_& m) {
  m.def(
      "solve",
      [](const ModelHandle& model, bool static_solve, double until, double every) {
        offline::SolveOptions o;
        o.static_solve = static_solve;
        o.until = until;
        o.report_every = every;
        offline::SolveResult result;
        {
          py::gil_scoped_release release;
          result = offline::solve(*model, o);
        }
        py::list out;
        for (const auto& b : result.bodies) out.append(body_result(b));
        return out;
      },
      py::arg("model"), py::kw_only(), py::arg("static") = true, py::arg("until") = 1.0, py::arg("every") = 0.0,
      "Solves the scene's deformable bodies without devices (`tactus solve`, docs/solve-output.md):\n"
      "static=True: equilibrium under the scene's loads and prescribed motions by load stepping;\n"
      "static=False: dynamics to `until` [s], a row every `every` seconds (0: every step).\n"
      "Returns one dict per deformable body: body, probe_names, region_names (fixed regions then\n"
      "prescribed motions), time (rows,) [s, or load fraction when static], step, converged,\n"
      "linear_iterations, probe_displacements (rows, probes, 3) [m], reactions (rows, regions, 3) [N],\n"
      "final_positions (nodes, 3) [m], failure (str, empty when every step converged), step_halvings.");
}

}  // namespace tactus::python
