// glint — the material (shader) interface shared by every integrator.
//
// One interface serves the Whitted integrator, the path tracer and instant radiosity alike:
// evaluate f(wo, wi), sample wi with its pdf, and the pdf alone (for MIS). Directions are
// world-space unit vectors; wo is si.wo. f excludes the cosine factor.
//
// The public calls are non-virtual (they add what every material shares: the shadow-terminator
// term of perturbed normals); each material implements the protected `evalBsdf`, `sampleBsdf`
// and `pdfBsdf`. Per hit, an integrator calls `perturbNormal` once (bump, normal map, snow)
// before anything else.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "geometry/interaction.h"
#include "materials/texture.h"

namespace glint {

enum BsdfFlags : uint32_t {
  kBsdfNone = 0,
  kBsdfUnlit = 1u << 0,  // not lit by lights: colour x |cos| towards the eye (eyelight)
  kBsdfDiffuse = 1u << 1,
  kBsdfGlossy = 1u << 2,
  kBsdfSpecular = 1u << 3,  // delta lobes (mirror, glass): eval and pdf are zero
  kBsdfReflection = 1u << 4,
  kBsdfTransmission = 1u << 5,
};
// Both hemispheres: the default lobe selection of Material::sample.
inline constexpr uint32_t kBsdfAllLobes = kBsdfReflection | kBsdfTransmission;

struct BsdfSample {
  Rgb f;  // f(wo, wi), without the cosine
  Vec3f wi;
  float pdf = 0;  // solid-angle density (for delta lobes: the discrete probability)
  uint32_t flags = kBsdfNone;
  float eta = 1;  // relative index of refraction crossed (transmission), else 1

  // The path throughput factor f |cos| / pdf along ns.
  Rgb weight(Vec3f ns) const { return f * (std::abs(dot(wi, ns)) / pdf); }
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
      Vec4f t = texture->evaluate(TexturePoint(si));
      c *= Rgb{t.x, t.y, t.z};
    }
    if (useVertexColor) c *= Rgb{si.color.x, si.color.y, si.color.z};
    return c;
  }
  // The alpha that goes with the colour (glTF base colour alpha x texture alpha x COLOR_0.a).
  float alpha(const SurfaceInteraction& si, float factorAlpha) const {
    float a = factorAlpha;
    if (texture) a *= texture->evaluate(TexturePoint(si)).w;
    if (useVertexColor) a *= si.color.w;
    return a;
  }
  bool isBlack() const { return !texture && maxComponent(factor) <= 0; }
};

// A scalar parameter: factor x optional texture channel (0-3: r, g, b, a; -1: luminance).
struct FloatParam {
  float factor = 1;
  const Texture* texture = nullptr;
  int channel = -1;

  float evaluate(const SurfaceInteraction& si) const {
    if (!texture) return factor;
    TexturePoint tp(si);
    if (channel < 0) return factor * texture->scalar(tp);
    return factor * texture->evaluate(tp)[channel];
  }
};

// Changes the shading normal of a hit before it is shaded: bump mapping, normal maps, snow
// (materials/bump.h).
class NormalModifier {
 public:
  virtual ~NormalModifier() = default;
  // Replaces si.ns (and may tilt si.dpdu / dpdv with it); keeps ns in ng's hemisphere.
  virtual void apply(SurfaceInteraction& si) const = 0;
  // Textures it reads (for SceneFeatures and the attributes a scene interpolates).
  virtual std::vector<const Texture*> textures() const { return {}; }
  // Surface attributes it reads besides its textures' (e.g. object space for snow).
  virtual TextureNeeds needs() const { return {}; }
};

// What a material reads and does, decided once when it is built; scenes lacking a trait skip
// the work it would need (SceneFeatures).
struct MaterialTraits {
  bool imageTextures = false;  // reads an image (file or glTF)
  bool procedural = false;     // reads a procedural (noise) texture
  bool vertexColors = false;
  bool emits = false;
  bool bump = false;          // perturbs the shading normal
  bool transparency = false;  // lets light pass straight through (alpha, transparent eyelight)
  bool refraction = false;    // transmits with refraction (glass, glTF transmission)
  TextureNeeds needs;         // surface attributes its textures read
};

// How alpha becomes opacity (glTF alphaMode): ignored, a cut-out at `cutoff`, or a blend.
enum class AlphaMode { Opaque, Mask, Blend };

class Material {
 public:
  virtual ~Material() = default;

  // Perturbs si.ns (bump, normal map, snow): once per hit, before the calls below.
  void perturbNormal(SurfaceInteraction& si) const {
    if (normalModifier_) normalModifier_->apply(si);
  }
  // f(wo, wi) at si (no cosine). Zero for delta lobes and for unlit materials.
  Rgb eval(const SurfaceInteraction& si, Vec3f wi) const;
  // Samples wi given two uniform numbers for the direction and one for the lobe choice,
  // restricted to the hemispheres in `lobes` (kBsdfReflection, kBsdfTransmission or both):
  // pdf and f are then those of the restricted choice, so an integrator may follow the
  // reflected and the transmitted lobe separately (Whitted) or pick one (path tracing).
  // kBsdfSpecular in `lobes` further restricts the choice to delta lobes.
  std::optional<BsdfSample> sample(const SurfaceInteraction& si, Vec2f u, float uLobe,
                                   uint32_t lobes = kBsdfAllLobes) const;
  // Solid-angle density with which sample() (all lobes) returns wi.
  float pdf(const SurfaceInteraction& si, Vec3f wi) const { return pdfBsdf(si, wi); }

  // Radiance emitted towards si.wo. Integrators call it only when traits().emits is set.
  virtual Rgb emitted(const SurfaceInteraction&) const { return {}; }
  // The surface's colour at si: the eyelight colour, and the albedo AOV.
  virtual Rgb albedo(const SurfaceInteraction& si) const = 0;
  // The fraction of light the surface stops; the rest passes straight through it (glTF alpha,
  // transparent eyelight). 1 for opaque materials.
  float opacity(const SurfaceInteraction& si) const;
  virtual uint32_t flags() const = 0;
  const MaterialTraits& traits() const { return traits_; }

  // Sets the normal modifier (the builder calls this once).
  void setNormalModifier(std::unique_ptr<NormalModifier> m);
  // Makes the surface partly transparent: `mode` says how the alpha of `source` (its texture
  // and vertex alpha times `factor`) becomes opacity.
  void setAlpha(AlphaMode mode, float factor, float cutoff, const ColorParam& source);

 protected:
  virtual Rgb evalBsdf(const SurfaceInteraction& si, Vec3f wi) const = 0;
  virtual std::optional<BsdfSample> sampleBsdf(const SurfaceInteraction& si, Vec2f u, float uLobe,
                                               uint32_t lobes) const = 0;
  virtual float pdfBsdf(const SurfaceInteraction& si, Vec3f wi) const = 0;

  // Derived constructors record what they read.
  void uses(const ColorParam& c);
  void uses(const FloatParam& f);
  void uses(const Texture* t);
  MaterialTraits traits_;

 private:
  std::unique_ptr<NormalModifier> normalModifier_;
  AlphaMode alphaMode_ = AlphaMode::Opaque;
  float alphaFactor_ = 1, alphaCutoff_ = 0.5f;
  ColorParam alphaSource_;
};

// Chiang, Li and Burley (2019), "Taming the Shadow Terminator": a shadowing term for shading
// normals that differ from the geometric one, smooth and 1 wherever ns = ng. Multiplying the
// reflected light by it removes the hard terminator that bump maps otherwise show on lit
// spheres, at the price of slightly darkening strongly bumped grazing regions.
float terminatorShadowing(Vec3f ng, Vec3f ns, Vec3f wi);

}  // namespace glint
