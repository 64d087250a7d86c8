// glint — `glint diff` from Python.
#pragma once

#include <pybind11/pybind11.h>

namespace glint::python {

// Registers _glint.compare(options): compares two image files as `glint diff` does and returns
// the JSON text `glint diff --json` prints.
void registerCompare(pybind11::module_& m);

}  // namespace glint::python
