// glint — the material interface shared by every integrator.
//
// A material is a recipe: its parameters (colours, roughness, transmission, alpha, emission),
// each a constant or a texture. Once per hit an integrator asks it for what it needs, in this
// order, through one TextureLookups of that hit, so each texture is read once however many
// parameters share it (pbrt-v4's Material::GetBSDF; yocto-gl's material_point):
//   perturbNormal(si)          bump, normal map or snow: the shading normal (Integrator does
//                              this in shadingPoint);
//   opacity(si, lookups)       only for materials with traits().transparency: a path passing
//                              straight through needs nothing more;
//   bsdf(si, lookups)          the scattering function at the hit, a small value whose f,
//                              sample and pdf never read a texture (materials/bsdf.h);
//   emitted / albedo(si, ...)  the emission (traits().emits), the albedo AOV and eyelight colour.
// Opacity, BSDF and emission are separate calls rather than one record so that a path passing
// through an alpha cut-out, or a hit on a surface that does not emit, pays for none of the rest;
// the shared TextureLookups keeps that from costing repeated lookups.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/interaction.h"
#include "materials/bsdf.h"
#include "materials/texture.h"

namespace glint {

// A colour parameter: constant factor x optional texture x optional vertex colour (glTF
// multiplies all three).
struct ColorParam {
  Rgb factor{1, 1, 1};
  const Texture* texture = nullptr;  // owned by the render scene
  bool useVertexColor = false;

  Rgb evaluate(const SurfaceInteraction& si, TextureLookups& lookups) const {
    Rgb c = factor;
    if (texture) {
      const Vec4f t = lookups(texture);
      c *= Rgb{t.x, t.y, t.z};
    }
    if (useVertexColor) c *= Rgb{si.color.x, si.color.y, si.color.z};
    return c;
  }
  // The alpha that goes with the colour (glTF base colour alpha x texture alpha x COLOR_0.a).
  float alpha(const SurfaceInteraction& si, float factorAlpha, TextureLookups& lookups) const {
    float a = factorAlpha;
    if (texture) a *= lookups(texture).w;
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

  float evaluate(TextureLookups& lookups) const {
    if (!texture) return factor;
    const Vec4f c = lookups(texture);
    return factor * (channel < 0 ? luminance({c.x, c.y, c.z}) : c[channel]);
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
  // A rough metal: it reflects its surroundings through a glossy lobe, which Whitted (highlights
  // from point lights only) cannot render; `--integrator auto` then picks the path tracer.
  bool glossyMetal = false;
  TextureNeeds needs;  // surface attributes its textures read
};

// How alpha becomes opacity (glTF alphaMode): ignored, a cut-out at `cutoff`, or a blend.
enum class AlphaMode { Opaque, Mask, Blend };

class Material {
 public:
  virtual ~Material() = default;

  // Perturbs si.ns (bump, normal map, snow): once per hit, before the calls below.
  void perturbNormal(SurfaceInteraction& si) const {
    if (!normalModifier_) return;
    si.nsUnperturbed = si.ns;
    normalModifier_->apply(si);
  }
  // The BSDF at si, in the frame of si.ns (already perturbed), every parameter read once.
  // Bumped surfaces get the shadow-terminator term (terminatorShadowing) in f and sample.
  Bsdf bsdf(const SurfaceInteraction& si, TextureLookups& lookups) const {
    return Bsdf(si, perturbsNormal(), [&](Bsdf* b) { setLobes(si, lookups, b); });
  }
  // The same with lookups of its own (tests, and points that are not otherwise shaded).
  Bsdf bsdf(const SurfaceInteraction& si) const {
    TextureLookups lookups(si);
    return bsdf(si, lookups);
  }
  // Radiance emitted towards si.wo. Integrators call it only when traits().emits is set.
  virtual Rgb emitted(const SurfaceInteraction& si, TextureLookups& lookups) const {
    (void)si, (void)lookups;
    return {};
  }
  // The same at a point that is not otherwise shaded (a point sampled on an emitting surface).
  Rgb emitted(const SurfaceInteraction& si) const {
    TextureLookups lookups(si);
    return emitted(si, lookups);
  }
  // The surface's colour at si: the eyelight colour, and the albedo AOV.
  virtual Rgb albedo(const SurfaceInteraction& si, TextureLookups& lookups) const = 0;
  // Unlit materials (flags() has kBsdfUnlit) only: the radiance towards si.wo. Eyelight's
  // colour x |cos|; glTF unlit overrides it with the colour alone.
  virtual Rgb unlitRadiance(const SurfaceInteraction& si, TextureLookups& lookups) const {
    return albedo(si, lookups) * std::abs(dot(si.ns, si.wo));
  }
  // The fraction of light the surface stops; the rest passes straight through it (glTF alpha,
  // transparent eyelight). 1 for opaque materials.
  float opacity(const SurfaceInteraction& si, TextureLookups& lookups) const;
  // The kinds of lobes the material can have anywhere (a BSDF's flags() are its hit's).
  virtual uint32_t flags() const = 0;
  // The absorption coefficient (per unit length, world units) of the material's inside, for
  // materials that refract into a volume (KHR_materials_volume): integrators attenuate a path
  // by exp(-absorption * distance) between entering the surface and leaving it. Zero: clear.
  virtual Rgb absorption() const { return {}; }
  const MaterialTraits& traits() const { return traits_; }

  // Sets the normal modifier (the builder calls this once).
  void setNormalModifier(std::unique_ptr<NormalModifier> m);
  // Makes the surface partly transparent: `mode` says how the alpha of `source` (its texture
  // and vertex alpha times `factor`) becomes opacity.
  void setAlpha(AlphaMode mode, float factor, float cutoff, const ColorParam& source);

 protected:
  // Puts the material's lobes at si into `bsdf` (Bsdf::emplace); its frame is set afterwards,
  // from si (a material that needs the local frame first builds it: buildLocalFrame).
  // Materials that do not scatter leave it empty.
  virtual void setLobes(const SurfaceInteraction& si, TextureLookups& lookups,
                        Bsdf* bsdf) const = 0;

  // Whether perturbNormal changes the shading normal (si.nsUnperturbed is then set).
  bool perturbsNormal() const { return normalModifier_ != nullptr; }
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

}  // namespace glint
