// tactus._tactus: the compiled half of the Python package `tactus` (docs/python.md).
#include "bindings.hpp"
#include "core/version.hpp"

PYBIND11_MODULE(_tactus, m) {
  namespace tp = tactus::python;
  m.doc() = "Tactus engine bindings: scenes, lockstep runs, frame-by-frame simulation, static solves, recordings, configuration spaces, meshes.";
  m.attr("__version__") = tactus::kVersion;
  tp::bind_errors(m);
  tp::bind_model(m);
  tp::bind_run(m);
  tp::bind_simulation(m);
  tp::bind_solve(m);
  tp::bind_recording(m);
  tp::bind_cspace(m);
  tp::bind_mesh(m);
}
