// glint — the Python module's errors: glint's error family raised as Python exceptions.
#pragma once

#include <pybind11/pybind11.h>

namespace glint::python {

// Registers the translation of glint's errors (geometry/error.h) into the exception classes of
// the package's glint/_errors.py: a SceneError becomes glint.InputError with its file, JSON
// pointer and message as attributes, any other InputError a glint.InputError naming no pointer,
// a FailureError glint.RenderError. What the command line exits with 2 and 1.
void registerErrors();

}  // namespace glint::python
