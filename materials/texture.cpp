// glint — image textures.
#include "materials/texture.h"

#include <cmath>

namespace glint {

float srgbToLinear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

ImageData makeImageData(int width, int height, int channels, const std::vector<float>& pixels,
                        bool srgb) {
  ImageData img;
  img.width = width;
  img.height = height;
  img.texels.resize(size_t(width) * size_t(height));
  auto decode = [&](float v) { return srgb ? srgbToLinear(v) : v; };
  for (size_t i = 0; i < img.texels.size(); ++i) {
    const float* p = &pixels[i * size_t(channels)];
    Vec4f t{1, 1, 1, 1};
    if (channels <= 2) {  // grey (+ alpha)
      float g = decode(p[0]);
      t = {g, g, g, channels == 2 ? p[1] : 1.0f};
    } else {
      t = {decode(p[0]), decode(p[1]), decode(p[2]), channels == 4 ? p[3] : 1.0f};
    }
    img.texels[i] = t;
  }
  return img;
}

ImageTexture::ImageTexture(std::shared_ptr<const ImageData> image, TextureWrap wrapU,
                           TextureWrap wrapV, bool nearest)
    : image_(std::move(image)), wrapU_(wrapU), wrapV_(wrapV), nearest_(nearest) {}

namespace {
int wrapCoord(int i, int n, TextureWrap mode) {
  switch (mode) {
    case TextureWrap::Clamp: return std::clamp(i, 0, n - 1);
    case TextureWrap::Mirror: {
      int period = 2 * n;
      int m = ((i % period) + period) % period;
      return m < n ? m : period - 1 - m;
    }
    case TextureWrap::Repeat:
    default: return ((i % n) + n) % n;
  }
}
}  // namespace

Vec4f ImageTexture::texel(int x, int y) const {
  x = wrapCoord(x, image_->width, wrapU_);
  y = wrapCoord(y, image_->height, wrapV_);
  return image_->texels[size_t(y) * size_t(image_->width) + size_t(x)];
}

Vec4f ImageTexture::lookup(Vec2f uv) const {
  if (image_->width == 0 || image_->height == 0 || !std::isfinite(uv.x) || !std::isfinite(uv.y))
    return {0, 0, 0, 1};
  float x = uv.x * float(image_->width), y = uv.y * float(image_->height);
  if (nearest_) return texel(int(std::floor(x)), int(std::floor(y)));
  // Bilinear between the four texel centres around (x, y).
  x -= 0.5f, y -= 0.5f;
  float fx = std::floor(x), fy = std::floor(y);
  int x0 = int(fx), y0 = int(fy);
  float tx = x - fx, ty = y - fy;
  Vec4f a = texel(x0, y0), b = texel(x0 + 1, y0), c = texel(x0, y0 + 1), d = texel(x0 + 1, y0 + 1);
  auto mix = [](Vec4f p, Vec4f q, float t) {
    return Vec4f{p.x + (q.x - p.x) * t, p.y + (q.y - p.y) * t, p.z + (q.z - p.z) * t,
                 p.w + (q.w - p.w) * t};
  };
  return mix(mix(a, b, tx), mix(c, d, tx), ty);
}

}  // namespace glint
