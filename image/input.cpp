// glint — a Film from disk (image/input.h).
#include "image/input.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

namespace glint {

namespace {

// The R, G, B (and A, else 1) channels of `image`, read from `path`, as a film without AOVs.
Film filmOf(const Image& image, const std::string& path) {
  int r = image.channel("R"), g = image.channel("G"), b = image.channel("B");
  int a = image.channel("A");
  if (r < 0 || g < 0 || b < 0)
    throw ImageReadError(fmt::format("{}: has no R, G, B channels", path));
  if (image.width <= 0 || image.height <= 0 || image.depth > 1)
    throw ImageReadError(fmt::format("{}: not a 2D image", path));

  const int nch = image.channels;
  Film film(image.width, image.height, false);
  for (size_t i = 0; i < film.color.size(); ++i) {
    const float* p = &image.pixels[i * size_t(nch)];
    film.color[i] = Rgb{p[r], p[g], p[b]};
    film.alpha[i] = a >= 0 ? p[a] : 1.0f;
  }
  return film;
}

}  // namespace

Film readExr(const std::string& path, ImageMetadata* meta) {
  Image image = readImage(path);
  if (image.format != "openexr")
    throw ImageReadError(fmt::format("{}: is not an OpenEXR image ({})", path, image.format));
  if (meta) *meta = image.meta;
  return filmOf(image, path);
}

Film readRenderState(const std::string& path, ImageMetadata* meta, std::string* whyNot) {
  Image image = readImage(path);
  const auto no = [&](std::string why) {
    if (whyNot) *whyNot = std::move(why);
    return Film{};
  };
  if (image.format != "openexr") return no("not an OpenEXR image");
  if (!image.hasMeta) return no("no glint metadata");
  if (image.type == PixelType::Half) return no("stored as half floats (continuing needs float)");
  if (meta) *meta = image.meta;
  Film film = filmOf(image, path);
  film.originX = image.x, film.originY = image.y;
  film.fullWidth = image.fullWidth, film.fullHeight = image.fullHeight;
  const int nch = image.channels;
  const auto channel = [&](const char* name) { return image.channel(name); };
  const int vr = channel("variance.R"), vg = channel("variance.G"), vb = channel("variance.B");
  if (vr < 0 || vg < 0 || vb < 0) return no("no variance channels (written by an older glint)");
  const int k = channel("samples");
  const int ar = channel("albedo.R"), ag = channel("albedo.G"), ab = channel("albedo.B");
  const int nx = channel("N.X"), ny = channel("N.Y"), nz = channel("N.Z"), z = channel("Z");
  film.hasAovs = ar >= 0 && ag >= 0 && ab >= 0 && nx >= 0 && ny >= 0 && nz >= 0 && z >= 0;
  const size_t n = film.color.size();
  if (film.hasAovs) {
    film.albedo.resize(n);
    film.normal.resize(n);
    film.depth.resize(n);
  }
  const uint32_t spp = uint32_t(std::max(0, image.meta.spp));
  for (size_t i = 0; i < n; ++i) {
    const float* p = &image.pixels[i * size_t(nch)];
    film.variance[i] = Rgb{p[vr], p[vg], p[vb]};
    if (k >= 0) {
      if (!(p[k] >= 0 && p[k] <= float(spp) && p[k] == std::floor(p[k])))
        return no(
            fmt::format("pixel {} has {} samples, not a count up to the {} spp", i, p[k], spp));
      film.samples[i] = uint32_t(p[k]);
    } else {
      film.samples[i] = spp;
    }
    if (film.hasAovs) {
      film.albedo[i] = Rgb{p[ar], p[ag], p[ab]};
      film.normal[i] = Vec3f{p[nx], p[ny], p[nz]};
      film.depth[i] = p[z];
    }
  }
  return film;
}

Film readSceneLinear(const std::string& path) {
  Image image = readImage(path);
  if (image.format != "openexr" && image.format != "hdr")
    throw ImageReadError(fmt::format(
        "{}: is not a scene-linear image (OpenEXR or Radiance .hdr) but {}", path, image.format));
  return filmOf(image, path);
}

}  // namespace glint
