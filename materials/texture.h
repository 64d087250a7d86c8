// glint — textures: a colour (or a scalar) as a function of a surface point, and the mapping
// layer that turns a surface point into texture coordinates.
//
// A texture sees a TexturePoint, not the whole SurfaceInteraction: bump mapping evaluates the
// height texture at points shifted along the surface, which means copies with a moved p and
// uv. Image textures live in image_texture.h (OpenImageIO's TextureSystem), the Perlin-noise
// patterns in procedural.h.
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <type_traits>

#include "geometry/interaction.h"

namespace glint {

// Everything a texture may look up at one shading point.
struct TexturePoint {
  Vec3f p;                    // world-space position
  Vec2f uv;                   // the primitive's UVs
  Vec2f duvdx, duvdy;         // change of uv across one pixel (zero: point sample)
  Vec2f uv1, duv1dx, duv1dy;  // the second UV set (glTF TEXCOORD_1) and its footprint
  Vec3f dpdx, dpdy;           // change of p across one pixel (zero: point sample)
  // The object's own frame, for object-space mapping (null: the world frame).
  const Transform* objectFromWorld = nullptr;
  uint32_t instance = 0, prim = 0;  // which object and primitive (random colours)

  TexturePoint() = default;
  explicit TexturePoint(const SurfaceInteraction& si)
      : p(si.p),
        uv(si.uv),
        duvdx(si.duvdx),
        duvdy(si.duvdy),
        uv1(si.uv1),
        duv1dx(si.duv1dx),
        duv1dy(si.duv1dy),
        dpdx(si.dpdx),
        dpdy(si.dpdy),
        objectFromWorld(si.objectFromWorld),
        instance(si.instance),
        prim(si.prim) {}
  Vec3f pObject() const { return objectFromWorld ? objectFromWorld->point(p) : p; }
};

// A 2D texture coordinate with its footprint across one pixel.
struct TexCoord2 {
  Vec2f st, dstdx, dstdy;
};

// Which coordinates a texture reads, and how: primitive UVs or a 3D space, scaled, then offset.
//   2D lookups (images, checkers): uv space gives (u, v) * scale.xy + offset.xy; object and
//   world space project the 3D point onto one of the planes xy, xz or yz.
//   3D lookups (noise patterns): p * scale + offset in object or world space; uv space gives
//   (u, v, 0) * scale + offset.
struct TextureMapping {
  enum class Space { Uv, Object, World };
  enum class Plane { Xy, Xz, Yz };
  Space space = Space::Uv;
  Plane plane = Plane::Xy;
  Vec3f scale{1, 1, 1}, offset{0, 0, 0};
  // UV space only: uv' = offset + R (scale * uv), R a rotation by `uvRotation` radians as
  // glTF's KHR_texture_transform defines it: R (x, y) = (x cos - y sin, x sin + y cos).
  float uvCos = 1, uvSin = 0;
  int uvSet = 0;  // UV space: 0 reads TexturePoint::uv, 1 uv1 (glTF texCoord)

  void setUvRotation(float radians) { uvCos = std::cos(radians), uvSin = std::sin(radians); }
  Vec2f rotateUv(Vec2f v) const { return {v.x * uvCos - v.y * uvSin, v.x * uvSin + v.y * uvCos}; }
  TexCoord2 map2D(const TexturePoint& tp) const;
  Vec3f map3D(const TexturePoint& tp) const;
  // The change of map3D for a small world-space step `d` from tp (footprints, gradients).
  Vec3f map3DVector(const TexturePoint& tp, Vec3f d) const;
  bool usesUvs() const { return space == Space::Uv; }
  bool usesObjectSpace() const { return space == Space::Object; }
};

// What a texture needs from the surface point, so scenes without it skip computing it.
// `tangents`: dp/du and dp/dv (bump and normal maps, footprints in uv).
struct TextureNeeds {
  bool uvs = false, objectSpace = false, footprint = false, tangents = false;
  TextureNeeds& operator|=(const TextureNeeds& o) {
    uvs |= o.uvs, objectSpace |= o.objectSpace, footprint |= o.footprint;
    tangents |= o.tangents;
    return *this;
  }
};

class Texture {
 public:
  virtual ~Texture() = default;
  // Colour (linear RGB) and alpha at the point.
  virtual Vec4f evaluate(const TexturePoint& tp) const = 0;
  // A scalar from the colour: luminance (height maps, weights).
  float scalar(const TexturePoint& tp) const {
    Vec4f c = evaluate(tp);
    return luminance({c.x, c.y, c.z});
  }
  // The world-space gradient of scalar() at tp, when the texture knows it exactly (3D
  // procedural patterns); false otherwise, and bump mapping then takes finite differences.
  virtual bool scalarGradient(const TexturePoint&, Vec3f*) const { return false; }
  virtual TextureNeeds needs() const = 0;
  // A bound on every colour the texture returns (energy checks of the materials using it).
  virtual Rgb upperBound() const { return {1, 1, 1}; }
  // An image read from a file or the glTF (the "textures" effect); procedural ones are not.
  virtual bool isImage() const { return false; }
  // The texture coordinate set a uv-mapped texture reads (TextureMapping::uvSet), else 0.
  virtual int uvSet() const { return 0; }
};

// The textures read at one shading point, each looked up once however many of a material's
// parameters use it (glTF's base colour and its alpha, metallic and roughness from one image,
// the albedo AOV and the BSDF's colour). One lives on the integrator's stack per hit; the
// point is fixed when it is made (a perturbed shading normal does not move it).
class TextureLookups {
 public:
  // `si` must outlive this; its texture point (p, uv, footprint, frame) is read at the first
  // lookup, so a material that reads no texture pays nothing.
  explicit TextureLookups(const SurfaceInteraction& si) : si_(si) {
    static_assert(std::is_trivially_destructible_v<TexturePoint> &&
                  std::is_trivially_destructible_v<Vec4f>);
  }
  // The texture's value at the point, looked up on first use.
  Vec4f operator()(const Texture* texture);

 private:
  static constexpr int kSlots = 6;  // more distinct textures than this are looked up each time
  const SurfaceInteraction& si_;
  // The texture point and the cached values are constructed when first written: every hit
  // makes a TextureLookups, and most materials read no texture (zero-filling these was ~160
  // bytes per hit for nothing).
  union {
    TexturePoint point_;
  };
  union {
    Vec4f values_[kSlots];
  };
  const Texture* keys_[kSlots];
  int used_ = 0;
  bool pointSet_ = false;
};

// A checkerboard of two colours over the 2D mapping (unit squares), or over the 3D mapping
// (unit cubes) when `solid`.
class CheckerTexture final : public Texture {
 public:
  CheckerTexture(TextureMapping mapping, Rgb a, Rgb b, bool solid)
      : mapping_(mapping), a_(a), b_(b), solid_(solid) {}
  Vec4f evaluate(const TexturePoint& tp) const override;
  TextureNeeds needs() const override {
    return {.uvs = mapping_.usesUvs(), .objectSpace = mapping_.usesObjectSpace()};
  }
  Rgb upperBound() const override { return max(a_, b_); }

 private:
  TextureMapping mapping_;
  Rgb a_, b_;
  bool solid_;
};

// How a 2D lookup treats coordinates outside [0, 1].
enum class TextureWrap { Repeat, Clamp, Mirror, Black };

// sRGB transfer function (IEC 61966-2-1), encoded value -> linear.
inline float srgbToLinear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}
// And its inverse, linear -> encoded.
inline float linearToSrgb(float v) {
  return v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

}  // namespace glint
