// glint — Film storage.
#include "renderer/film.h"

namespace glint {

Film::Film(int w, int h, bool aovs)
    : width(w), height(h), fullWidth(w), fullHeight(h), hasAovs(aovs) {
  size_t n = size_t(w) * size_t(h);
  color.assign(n, Rgb{});
  variance.assign(n, Rgb{});
  alpha.assign(n, 0.0f);
  samples.assign(n, 0);
  if (aovs) {
    albedo.assign(n, Rgb{});
    normal.assign(n, Vec3f{});
    depth.assign(n, 0.0f);
  }
}

}  // namespace glint
