// glint — `glint info` as a Python dict.
#pragma once

#include <pybind11/pybind11.h>

#include "scenes/scene_info.h"

namespace glint::python {

// The dict Scene.info() returns: every figure `glint info` prints, under the names of its lines
// (docs/python.md lists the keys).
pybind11::dict infoDict(const SceneInfo& info);

}  // namespace glint::python
