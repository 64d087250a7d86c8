// glint — the Python module's image: a film with what made it, and its planes as numpy arrays.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <string>

#include "image/io.h"
#include "renderer/film.h"
#include "renderer/render.h"
#include "renderer/settings.h"

namespace glint::python {

// A rendered (or read) image: the film, how its render ended, and the settings it was made with
// (tone mapping and EXR options for writing it).
struct RenderedImage {
  std::shared_ptr<Film> film;
  ProgressiveResult result;
  RenderStats stats;
  ImageMetadata meta;
  RenderSettings settings;
  bool running = false;  // a progressive render's image after a pass that is not the last
};

// The film's planes as numpy arrays that share its memory (no copy; the film lives as long as
// any of them): "beauty" and "variance" (height, width, 3) float32, "alpha" (height, width)
// float32, "samples" (height, width) uint32, and with AOVs "albedo", "normal" (height, width,
// 3) and "depth" (height, width).
pybind11::dict filmArrays(const std::shared_ptr<Film>& film);

// A film made from numpy arrays (copied): "beauty" (height, width, 3) is required; "variance",
// "alpha", "samples" and the AOVs are optional and must have its size. Throws InputError naming
// the array that does not fit.
std::shared_ptr<Film> filmFromArrays(const pybind11::dict& arrays);

// Registers the class _glint.Image.
void registerImage(pybind11::module_& m);

}  // namespace glint::python
