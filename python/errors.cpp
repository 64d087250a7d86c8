// glint — glint's errors as Python exceptions (see errors.h).
#include "python/errors.h"

#include <exception>
#include <string>

#include "scenes/errors.h"

namespace py = pybind11;

namespace glint::python {

namespace {

// Sets the Python error to glint._errors.CLASS(message, file, pointer, detail).
void raise(const char* cls, const std::string& message, py::object file, py::object pointer,
           const std::string& detail) {
  const py::object type = py::module_::import("glint._errors").attr(cls);
  const py::object error = type(message, file, pointer, detail);
  PyErr_SetObject(type.ptr(), error.ptr());
}

}  // namespace

void registerErrors() {
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const SceneError& e) {
      raise("InputError", e.what(), py::str(e.where().file),
            e.where().pointer.empty() ? py::object(py::none())
                                      : py::object(py::str(e.where().pointer)),
            e.message());
    } catch (const InputError& e) {
      raise("InputError", e.what(), py::none(), py::none(), e.what());
    } catch (const FailureError& e) {
      raise("RenderError", e.what(), py::none(), py::none(), e.what());
    }
  });
}

}  // namespace glint::python
