// glint — the Python binding `_glint`; the package glint/ (python/glint/__init__.py) is its
// public face: docs/python.md.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>

#include "python/compare.h"
#include "python/errors.h"
#include "python/info.h"
#include "python/interruptible.h"
#include "python/rendered_image.h"
#include "python/scene_handle.h"

namespace py = pybind11;
using namespace glint;
using namespace glint::python;

namespace {

// Renders off the GIL; returns (image or None, the exception a signal raised or None): an
// interrupted render hands back the passes it did (None before the first), and the package
// raises glint.RenderInterrupted with them.
py::tuple renderScene(SceneHandle& scene, const std::string& options) {
  std::shared_ptr<RenderedImage> image;
  std::atomic<bool> cancel{false};
  const auto interrupt = runInterruptibly(cancel, [&] { image = scene.render(options, &cancel); });
  const py::object kept = image && image->result.spp > 0 ? py::cast(image) : py::none();
  return py::make_tuple(kept, interrupt ? interrupt->value() : py::none());
}

// The next pass of a progressive render, as renderScene returns a render.
py::tuple nextPass(ProgressiveSession& session) {
  std::shared_ptr<RenderedImage> image;
  const auto interrupt = runInterruptibly(session.cancel(), [&] { image = session.next(); });
  return py::make_tuple(image ? py::cast(image) : py::none(),
                        interrupt ? interrupt->value() : py::none());
}

}  // namespace

PYBIND11_MODULE(_glint, m) {
  m.doc() = "glint's C++ binding; use the package `glint` (docs/python.md).";
  registerErrors();
  registerImage(m);
  registerCompare(m);
  py::class_<SceneHandle>(m, "Scene")
      .def(py::init<const std::string&, const std::optional<std::string>&, std::optional<double>>(),
           py::arg("path"), py::arg("sidecar"), py::arg("time"),
           py::call_guard<py::gil_scoped_release>())
      .def(py::init([](const std::string& text, const std::string& file,
                       const std::optional<std::string>& scene, std::optional<double> time) {
             return std::make_unique<SceneHandle>(SceneLoader::JsonText{text, file}, scene, time);
           }),
           py::arg("json"), py::arg("name"), py::arg("scene"), py::arg("time"),
           py::call_guard<py::gil_scoped_release>())
      .def_property_readonly("file", &SceneHandle::file)
      .def_property_readonly("builds", &SceneHandle::builds)
      .def_property_readonly("refreshes", &SceneHandle::refreshes)
      .def_property_readonly("timings",
                             [](const SceneHandle& s) {
                               py::dict d;
                               d["load_seconds"] = s.loadSeconds();
                               d["build_seconds"] = s.lastBuild().totalSeconds;
                               d["accelerator_seconds"] = s.lastBuild().acceleratorSeconds;
                               return d;
                             })
      .def("update", &SceneHandle::update, py::arg("patch"))
      .def(
          "set_light",
          [](SceneHandle& s, const std::string& name, std::optional<float> intensity,
             std::optional<std::array<float, 3>> color) {
            std::optional<Rgb> rgb;
            if (color) rgb = Rgb{(*color)[0], (*color)[1], (*color)[2]};
            s.setLight(name, intensity, rgb);
          },
          py::arg("name"), py::arg("intensity"), py::arg("color"))
      .def_property_readonly("cameras",
                             [](const SceneHandle& s) {
                               std::vector<std::string> names;
                               for (const CameraDesc& c : s.description().cameras)
                                 names.push_back(c.name);
                               return names;
                             })
      .def_property_readonly("warnings",
                             [](const SceneHandle& s) { return s.description().warnings; })
      .def("info",
           [](SceneHandle& s) {
             SceneInfo info;
             {
               py::gil_scoped_release release;  // it may build the render scene
               info = s.info();
             }
             return infoDict(info);
           })
      .def("render", &renderScene, py::arg("options"))
      .def("progressive", &SceneHandle::progressive, py::arg("options"),
           py::call_guard<py::gil_scoped_release>());
  py::class_<ProgressiveSession>(m, "Progressive").def("next", &nextPass);
}
