// glint — texture mapping, checkerboards and the bilinear image texture.
#include "materials/texture.h"

#include <cmath>
#include <new>

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
    case Space::Uv: {
      const bool second = uvSet == 1;
      c.st = rotateUv(scale2(second ? tp.uv1 : tp.uv, scale)) + Vec2f{offset.x, offset.y};
      c.dstdx = rotateUv(scale2(second ? tp.duv1dx : tp.duvdx, scale));
      c.dstdy = rotateUv(scale2(second ? tp.duv1dy : tp.duvdy, scale));
      break;
    }
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
    case Space::Uv: {
      const Vec2f st = rotateUv(scale2(tp.uv, scale));
      return Vec3f{st.x, st.y, 0} + offset;
    }
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

Vec4f TextureLookups::operator()(const Texture* texture) {
  for (int i = 0; i < used_; ++i)
    if (keys_[i] == texture) return values_[i];
  if (!pointSet_) {
    new (&point_) TexturePoint(si_);
    pointSet_ = true;
  }
  const Vec4f v = texture->evaluate(point_);
  if (used_ < kSlots) {
    keys_[used_] = texture;
    new (&values_[used_++]) Vec4f(v);
  }
  return v;
}

}  // namespace glint
