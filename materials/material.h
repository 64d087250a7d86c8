// glint — the material (shader) interface shared by every integrator.
//
// One interface serves the Whitted integrator, the path tracer and instant radiosity alike:
// evaluate f(wo, wi), sample wi with its pdf, and the pdf alone (for MIS). Directions are
// world-space unit vectors; wo is si.wo. f excludes the cosine factor.
#pragma once

#include <cstdint>
#include <optional>

#include "geometry/interaction.h"
#include "materials/texture.h"

namespace glint {

enum BsdfFlags : uint32_t {
  kBsdfNone = 0,
  kBsdfUnlit = 1u << 0,         // not lit by lights: colour x |cos| towards the eye (eyelight)
  kBsdfDiffuse = 1u << 1,
  kBsdfGlossy = 1u << 2,
  kBsdfSpecular = 1u << 3,      // delta lobes (mirror, glass): eval and pdf are zero
  kBsdfReflection = 1u << 4,
  kBsdfTransmission = 1u << 5,
};

struct BsdfSample {
  Rgb f;          // f(wo, wi), without the cosine
  Vec3f wi;
  float pdf = 0;  // solid-angle density (for delta lobes: the discrete probability)
  uint32_t flags = kBsdfNone;
};

// A colour parameter: constant factor x optional texture x optional vertex colour (glTF
// multiplies all three).
struct ColorParam {
  Rgb factor{1, 1, 1};
  const Texture* texture = nullptr;  // owned by the render scene
  bool useVertexColor = false;

  Rgb evaluate(const SurfaceInteraction& si) const {
    Rgb c = factor;
    if (texture) {
      Vec4f t = texture->evaluate(si);
      c *= Rgb{t.x, t.y, t.z};
    }
    if (useVertexColor) c *= Rgb{si.color.x, si.color.y, si.color.z};
    return c;
  }
};

class Material {
 public:
  virtual ~Material() = default;
  // f(wo, wi) at si (no cosine). Zero for delta lobes and for unlit materials.
  virtual Rgb eval(const SurfaceInteraction& si, Vec3f wi) const = 0;
  // Samples wi given two uniform numbers for the direction and one for the lobe choice.
  virtual std::optional<BsdfSample> sample(const SurfaceInteraction& si, Vec2f u,
                                           float uLobe) const = 0;
  // Solid-angle density with which sample() returns wi.
  virtual float pdf(const SurfaceInteraction& si, Vec3f wi) const = 0;
  // Radiance emitted towards si.wo.
  virtual Rgb emitted(const SurfaceInteraction&) const { return {}; }
  // The surface's colour at si: the eyelight colour, and the albedo AOV.
  virtual Rgb albedo(const SurfaceInteraction& si) const = 0;
  virtual uint32_t flags() const = 0;
  // Optional inputs the material reads, so scenes that lack them skip interpolating them.
  virtual bool usesTextures() const { return false; }
  virtual bool usesVertexColors() const { return false; }
  virtual bool emits() const { return false; }
};

}  // namespace glint
