#include "bindings.hpp"

namespace tactus::python {

void bind_simulation(py::module_&) {}

}  // namespace tactus::python
