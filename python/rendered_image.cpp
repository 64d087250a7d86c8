// glint — films as numpy arrays, and the _glint.Image class (see rendered_image.h).
#include "python/rendered_image.h"

#include <pybind11/stl.h>

#include <algorithm>
#include <cstring>
#include <nlohmann/json.hpp>
#include <type_traits>

#include "image/color.h"
#include "image/input.h"
#include "image/output.h"
#include "image/tonemap.h"
#include "scenes/json_reader.h"
#include "scenes/json_util.h"
#include "scenes/sidecar.h"

namespace py = pybind11;

namespace glint::python {

namespace {

static_assert(sizeof(Vec3f) == 3 * sizeof(float), "numpy views Rgb planes as (h, w, 3) floats");

template <class T>
py::array view(const std::shared_ptr<Film>& film, const py::capsule& owner, T* data, int planes) {
  const auto h = py::ssize_t(film->height), w = py::ssize_t(film->width);
  const auto item = py::ssize_t(sizeof(T)) / (planes == 3 ? 3 : 1);
  using Item = std::conditional_t<std::is_same_v<T, Vec3f>, float, T>;
  if (planes == 3)
    return py::array_t<Item>({h, w, py::ssize_t(3)}, {w * 3 * item, 3 * item, item},
                             reinterpret_cast<Item*>(data), owner);
  return py::array_t<Item>({h, w}, {w * item, item}, reinterpret_cast<Item*>(data), owner);
}

// Copies array `name` of `arrays`, (height, width, channels) or (height, width) when channels
// is 1, into `out`; false when absent.
template <class T>
bool copyPlane(const py::dict& arrays, const char* name, int width, int height, int channels,
               T* out) {
  if (!arrays.contains(name) || arrays[name].is_none()) return false;
  using Item = std::conditional_t<std::is_same_v<T, uint32_t>, uint32_t, float>;
  auto a = py::array_t<Item, py::array::c_style | py::array::forcecast>::ensure(arrays[name]);
  const bool fits = a &&
                    (channels == 1 ? a.ndim() == 2 : a.ndim() == 3 && a.shape(2) == channels) &&
                    a.shape(0) == height && a.shape(1) == width;
  if (!fits)
    throw InputError("Image: '" + std::string(name) + "' must be a " + std::to_string(height) +
                     " x " + std::to_string(width) +
                     (channels == 1 ? "" : " x " + std::to_string(channels)) + " array of numbers");
  std::memcpy(static_cast<void*>(out), a.data(), size_t(a.size()) * sizeof(Item));
  return true;
}

// The tone mapping `options` ask for (a JSON object of the sidecar's render.tonemap keys:
// exposure, operator, ward, display, view) over `base`; errors name "tonemap()".
ToneMapSettings toneMapOptions(const std::string& options, const RenderSettings& base) {
  const std::string where = "tonemap()";
  const nlohmann::json doc = {{"tonemap", parseSceneJson(options, where)}};
  SceneDescription desc;
  desc.render = base;
  JsonReader r(doc, {where, ""});
  readRenderBlock(r, &desc);
  r.finish();
  try {
    resolveDisplayView(desc.render.tonemap.display, desc.render.tonemap.view);
  } catch (const ColorError& e) {
    throw SceneError({where, "/tonemap"}, e.what());
  }
  return desc.render.tonemap;
}

// The film as a display shows it (displayPixels, Ward's scale from the film itself), as a
// (height, width, 3) float32 array in [0, 1].
py::array displayArray(const Film& film, const ToneMapSettings& tonemap) {
  LogLuminanceStats stats;
  if (tonemap.op == "ward") stats.add(film.color, tonemap);
  auto* pixels = new std::vector<float>(displayPixels(film.color, tonemap, stats.logAverage()));
  for (float& v : *pixels) v = std::clamp(v, 0.0f, 1.0f);
  const py::capsule owner(pixels, [](void* p) { delete static_cast<std::vector<float>*>(p); });
  const auto h = py::ssize_t(film.height), w = py::ssize_t(film.width), f = py::ssize_t(4);
  return py::array_t<float>({h, w, py::ssize_t(3)}, {w * 3 * f, 3 * f, f}, pixels->data(), owner);
}

}  // namespace

py::dict filmArrays(const std::shared_ptr<Film>& film) {
  // The capsule holds a reference to the film for as long as an array lives.
  const py::capsule owner(new std::shared_ptr<Film>(film),
                          [](void* p) { delete static_cast<std::shared_ptr<Film>*>(p); });
  py::dict d;
  d["beauty"] = view(film, owner, film->color.data(), 3);
  d["variance"] = view(film, owner, film->variance.data(), 3);
  d["alpha"] = view(film, owner, film->alpha.data(), 1);
  d["samples"] = view(film, owner, film->samples.data(), 1);
  if (film->hasAovs) {
    d["albedo"] = view(film, owner, film->albedo.data(), 3);
    d["normal"] = view(film, owner, film->normal.data(), 3);
    d["depth"] = view(film, owner, film->depth.data(), 1);
  }
  return d;
}

std::shared_ptr<Film> filmFromArrays(const py::dict& arrays) {
  if (!arrays.contains("beauty")) throw InputError("Image: needs a 'beauty' array");
  auto beauty = py::array::ensure(arrays["beauty"]);
  if (!beauty || beauty.ndim() != 3 || beauty.shape(2) != 3)
    throw InputError("Image: 'beauty' must be a height x width x 3 array of numbers");
  const int h = int(beauty.shape(0)), w = int(beauty.shape(1));
  const bool aovs = arrays.contains("albedo") && !arrays["albedo"].is_none();
  auto film = std::make_shared<Film>(w, h, aovs);
  copyPlane(arrays, "beauty", w, h, 3, film->color.data());
  copyPlane(arrays, "variance", w, h, 3, film->variance.data());
  if (!copyPlane(arrays, "alpha", w, h, 1, film->alpha.data()))
    std::fill(film->alpha.begin(), film->alpha.end(), 1.0f);
  if (!copyPlane(arrays, "samples", w, h, 1, film->samples.data()))
    std::fill(film->samples.begin(), film->samples.end(), 1u);
  if (aovs) {
    copyPlane(arrays, "albedo", w, h, 3, film->albedo.data());
    copyPlane(arrays, "normal", w, h, 3, film->normal.data());
    copyPlane(arrays, "depth", w, h, 1, film->depth.data());
  }
  return film;
}

void registerImage(py::module_& m) {
  py::class_<RenderedImage, std::shared_ptr<RenderedImage>>(m, "Image")
      .def_property_readonly("arrays", [](const RenderedImage& i) { return filmArrays(i.film); })
      .def_property_readonly("spp", [](const RenderedImage& i) { return i.result.spp; })
      .def_property_readonly("error", [](const RenderedImage& i) { return i.result.error; })
      .def_property_readonly(
          "stop",
          [](const RenderedImage& i) {
            return i.running ? py::object(py::none())
                             : py::object(py::str(std::string(stopReasonName(i.result.reason))));
          })
      .def_property_readonly("passes", [](const RenderedImage& i) { return i.result.passes; })
      .def_property_readonly("stats",
                             [](const RenderedImage& i) {
                               py::dict d;
                               d["render_seconds"] = i.stats.renderSeconds;
                               d["threads"] = i.stats.threads;
                               d["rays"] = i.stats.rays.total();
                               d["nonfinite_samples"] = i.stats.nonfiniteSamples;
                               d["brightest_sample"] = i.stats.brightestSample;
                               d["mean_spp"] = i.stats.meanSpp;
                               return d;
                             })
      .def_property_readonly("metadata",
                             [](const RenderedImage& i) {
                               py::dict d;
                               forEachMetadataField(
                                   i.meta, [&](const char* name, const auto& v, bool whenStopped) {
                                     if (!whenStopped || !i.meta.stop.empty()) d[name] = v;
                                   });
                               return d;
                             })
      .def(
          "display",
          [](const RenderedImage& i, const std::string& options) {
            return displayArray(*i.film, toneMapOptions(options, i.settings));
          },
          py::arg("options"))
      .def(
          "save",
          [](const RenderedImage& i, const std::string& path) {
            std::string why;
            if (!isSupportedOutput(path, &why)) throw InputError(path + ": " + why);
            writeImage(path, *i.film, i.settings, i.meta);
          },
          py::arg("path"), "Writes the image (format by extension) with glint's metadata.");

  m.def(
      "read_image",
      [](const std::string& path) {
        auto image = std::make_shared<RenderedImage>();
        std::string whyNot;
        Film film = readRenderState(path, &image->meta, &whyNot);
        if (film.width == 0) film = readExr(path, &image->meta);
        image->result.spp = uint32_t(std::max(image->meta.spp, 0));
        image->result.error = image->meta.error;
        image->film = std::make_shared<Film>(std::move(film));
        return image;
      },
      py::arg("path"));
  m.def(
      "image_from_arrays",
      [](const py::dict& arrays) {
        auto image = std::make_shared<RenderedImage>();
        image->film = filmFromArrays(arrays);
        return image;
      },
      py::arg("arrays"));
}

}  // namespace glint::python
