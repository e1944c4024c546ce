// tactus.InputError: the C++ tactus::InputError (a bad scene, key, file) as a ValueError
// subclass that keeps where the problem is as attributes.
#include "bindings.hpp"
#include "core/error.hpp"

namespace tactus::python {
namespace {

// A new reference held for the interpreter's life: the type outlives every module object.
PyObject* input_error_type = nullptr;

py::object optional_int(const std::optional<std::uint64_t>& v) {
  return v ? py::object(py::int_(*v)) : py::object(py::none());
}

}  // namespace

void bind_errors(py::module_& m) {
  input_error_type = PyErr_NewExceptionWithDoc(
      "tactus.InputError",
      "A problem in the user's input (a scene file, a key, a recording), as tactus::InputError.\n\n"
      "Attributes: file (str), line, column, byte_offset (int or None), reason (the message\n"
      "without the location). str(error) is 'file:line:column: reason'.",
      PyExc_ValueError, nullptr);
  if (!input_error_type) throw py::error_already_set();
  m.add_object("InputError", py::handle(input_error_type).inc_ref());

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      py::object error = py::reinterpret_borrow<py::object>(input_error_type)(e.what());
      error.attr("file") = e.where().file;
      error.attr("line") = optional_int(e.where().line);
      error.attr("column") = optional_int(e.where().column);
      error.attr("byte_offset") = optional_int(e.where().byte_offset);
      error.attr("reason") = e.reason();
      PyErr_SetObject(input_error_type, error.ptr());
    }
  });
}

}  // namespace tactus::python
