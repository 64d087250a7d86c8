// glint — the course's first shaders: eyelight, Lambert, (energy-normalized) Phong and
// Blinn-Phong. Their lobes are in bxdfs.h.
#pragma once

#include "materials/material.h"

namespace glint {

// Shared parts of the simple materials: diffuse colour and emission.
class SimpleMaterial : public Material {
 public:
  SimpleMaterial(ColorParam diffuse, ColorParam emission);
  Rgb emitted(const SurfaceInteraction& si, TextureLookups& lookups) const override {
    return emission_.evaluate(si, lookups);
  }
  using Material::emitted;
  Rgb albedo(const SurfaceInteraction& si, TextureLookups& lookups) const override {
    return diffuse_.evaluate(si, lookups);
  }

 protected:
  ColorParam diffuse_, emission_;
};

// Colour x |cos(normal, view)|, independent of lights: the ray tracing course's first shader.
// With an alpha (setAlpha) it is the course's transparent eyelight: the rest of the light
// passes through. It does not scatter: its BSDF is empty.
class EyelightMaterial final : public SimpleMaterial {
 public:
  explicit EyelightMaterial(ColorParam color) : SimpleMaterial(color, ColorParam{{0, 0, 0}}) {}
  uint32_t flags() const override { return kBsdfUnlit; }

 protected:
  void setLobes(const SurfaceInteraction&, TextureLookups&, Bsdf*) const override {}
};

// glTF's KHR_materials_unlit: the colour is the radiance the surface sends along every ray
// that meets it, camera or bounce, whatever the lights (no cosine, unlike eyelight). It
// reflects nothing; it is not sampled as a light, but a path that meets it takes its colour,
// as Blender's importer does with an emission shader.
class UnlitMaterial final : public SimpleMaterial {
 public:
  explicit UnlitMaterial(ColorParam color) : SimpleMaterial(color, ColorParam{{0, 0, 0}}) {}
  uint32_t flags() const override { return kBsdfUnlit; }
  Rgb unlitRadiance(const SurfaceInteraction& si, TextureLookups& lookups) const override {
    return albedo(si, lookups);
  }

 protected:
  void setLobes(const SurfaceInteraction&, TextureLookups&, Bsdf*) const override {}
};

// Ideal diffuse reflection: f = albedo / pi.
class LambertMaterial final : public SimpleMaterial {
 public:
  using SimpleMaterial::SimpleMaterial;
  uint32_t flags() const override { return kBsdfDiffuse | kBsdfReflection; }

 protected:
  void setLobes(const SurfaceInteraction& si, TextureLookups& lookups, Bsdf* bsdf) const override {
    bsdf->emplace<DiffuseBxdf>(diffuse_.evaluate(si, lookups));
  }
};

// A diffuse lobe plus a cos^n specular lobe (PhongBxdf: Phong or Blinn-Phong), energy-
// normalized so that kd + ks <= 1 per channel (the scene builder checks it).
class PhongMaterial final : public SimpleMaterial {
 public:
  PhongMaterial(ColorParam diffuse, Rgb specular, float shininess, ColorParam emission,
                bool blinn = false)
      : SimpleMaterial(diffuse, emission),
        specular_(specular),
        shininess_(shininess),
        blinn_(blinn) {}
  uint32_t flags() const override { return kBsdfDiffuse | kBsdfGlossy | kBsdfReflection; }

 protected:
  void setLobes(const SurfaceInteraction& si, TextureLookups& lookups, Bsdf* bsdf) const override {
    bsdf->emplace<PhongBxdf>(diffuse_.evaluate(si, lookups), specular_, shininess_, blinn_);
  }

 private:
  Rgb specular_;
  float shininess_;
  bool blinn_;
};

}  // namespace glint
