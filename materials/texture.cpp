// glint — texture mapping, checkerboards and the bilinear image texture.
#include "materials/texture.h"

#include <cmath>

namespace glint {

// ---------------------------------------------------------------------------------------------
// Mapping
// ---------------------------------------------------------------------------------------------

namespace {

Vec2f project(Vec3f v, TextureMapping::Plane plane) {
  switch (plane) {
    case TextureMapping::Plane::Xz:
      return {v.x, v.z};
    case TextureMapping::Plane::Yz:
      return {v.y, v.z};
    case TextureMapping::Plane::Xy:
    default:
      return {v.x, v.y};
  }
}

Vec2f scale2(Vec2f v, Vec3f s) { return {v.x * s.x, v.y * s.y}; }

}  // namespace

TexCoord2 TextureMapping::map2D(const TexturePoint& tp) const {
  TexCoord2 c;
  switch (space) {
    case Space::Uv:
      c.st = scale2(tp.uv, scale) + Vec2f{offset.x, offset.y};
      c.dstdx = scale2(tp.duvdx, scale);
      c.dstdy = scale2(tp.duvdy, scale);
      break;
    case Space::Object:
    case Space::World: {
      Vec3f dx = map3DVector(tp, tp.dpdx), dy = map3DVector(tp, tp.dpdy);
      c.st = project(map3D(tp), plane);
      c.dstdx = project(dx, plane);
      c.dstdy = project(dy, plane);
      break;
    }
  }
  return c;
}

Vec3f TextureMapping::map3D(const TexturePoint& tp) const {
  switch (space) {
    case Space::Uv:
      return Vec3f{tp.uv.x, tp.uv.y, 0} * scale + offset;
    case Space::Object:
      return tp.pObject() * scale + offset;
    case Space::World:
    default:
      return tp.p * scale + offset;
  }
}

Vec3f TextureMapping::map3DVector(const TexturePoint& tp, Vec3f d) const {
  switch (space) {
    case Space::Uv:
      return {};  // uv-space 3D lookups have no world-space gradient
    case Space::Object:
      return (tp.objectFromWorld ? tp.objectFromWorld->vector(d) : d) * scale;
    case Space::World:
    default:
      return d * scale;
  }
}

// ---------------------------------------------------------------------------------------------
// Checkerboard
// ---------------------------------------------------------------------------------------------

Vec4f CheckerTexture::evaluate(const TexturePoint& tp) const {
  int parity;
  if (solid_) {
    Vec3f q = mapping_.map3D(tp);
    parity = int(std::floor(q.x)) + int(std::floor(q.y)) + int(std::floor(q.z));
  } else {
    Vec2f st = mapping_.map2D(tp).st;
    parity = int(std::floor(st.x)) + int(std::floor(st.y));
  }
  Rgb c = (parity & 1) ? b_ : a_;
  return {c.x, c.y, c.z, 1};
}

// ---------------------------------------------------------------------------------------------
// Bilinear image texture
// ---------------------------------------------------------------------------------------------

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

BilinearImageTexture::BilinearImageTexture(std::shared_ptr<const ImageData> image,
                                           TextureWrap wrapU, TextureWrap wrapV, bool nearest)
    : image_(std::move(image)), wrapU_(wrapU), wrapV_(wrapV), nearest_(nearest) {}

namespace {
int wrapCoord(int i, int n, TextureWrap mode) {
  switch (mode) {
    case TextureWrap::Clamp:
      return std::clamp(i, 0, n - 1);
    case TextureWrap::Mirror: {
      int period = 2 * n;
      int m = ((i % period) + period) % period;
      return m < n ? m : period - 1 - m;
    }
    case TextureWrap::Black:  // the caller returns black outside; clamp keeps the index valid
      return std::clamp(i, 0, n - 1);
    case TextureWrap::Repeat:
    default:
      return ((i % n) + n) % n;
  }
}
}  // namespace

Vec4f BilinearImageTexture::texel(int x, int y) const {
  x = wrapCoord(x, image_->width, wrapU_);
  y = wrapCoord(y, image_->height, wrapV_);
  return image_->texels[size_t(y) * size_t(image_->width) + size_t(x)];
}

Vec4f BilinearImageTexture::lookup(Vec2f uv) const {
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
