// glint — the course's first shaders: eyelight, Lambert, (energy-normalized) Phong and
// Blinn-Phong.
#pragma once

#include "materials/material.h"

namespace glint {

// Shared parts of the simple materials: diffuse colour and emission.
class SimpleMaterial : public Material {
 public:
  SimpleMaterial(ColorParam diffuse, ColorParam emission);
  Rgb emitted(const SurfaceInteraction& si) const override { return emission_.evaluate(si); }
  Rgb albedo(const SurfaceInteraction& si) const override { return diffuse_.evaluate(si); }

 protected:
  ColorParam diffuse_, emission_;
};

// Colour x |cos(normal, view)|, independent of lights: the ray tracing course's first shader.
// With an alpha (setAlpha) it is the course's transparent eyelight: the rest of the light
// passes through.
class EyelightMaterial final : public SimpleMaterial {
 public:
  explicit EyelightMaterial(ColorParam color) : SimpleMaterial(color, ColorParam{{0, 0, 0}}) {}
  uint32_t flags() const override { return kBsdfUnlit; }

 protected:
  Rgb evalBsdf(const SurfaceInteraction&, Vec3f) const override { return {}; }
  std::optional<BsdfSample> sampleBsdf(const SurfaceInteraction&, Vec2f, float,
                                       uint32_t) const override {
    return std::nullopt;
  }
  float pdfBsdf(const SurfaceInteraction&, Vec3f) const override { return 0; }
};

// Ideal diffuse reflection: f = albedo / pi.
class LambertMaterial final : public SimpleMaterial {
 public:
  using SimpleMaterial::SimpleMaterial;
  uint32_t flags() const override { return kBsdfDiffuse | kBsdfReflection; }

 protected:
  Rgb evalBsdf(const SurfaceInteraction& si, Vec3f wi) const override;
  std::optional<BsdfSample> sampleBsdf(const SurfaceInteraction& si, Vec2f u, float uLobe,
                                       uint32_t lobes) const override;
  float pdfBsdf(const SurfaceInteraction& si, Vec3f wi) const override;
};

// A diffuse lobe plus a cos^n specular lobe, energy-normalized so that kd + ks <= 1 per channel
// (the scene builder checks it) never reflects more than it receives:
//   Phong (Lafortune & Willems 1994): ks (n+2)/(2 pi) cos^n(alpha), alpha between wi and the
//     mirror direction of wo.
//   Blinn-Phong, in Ashikhmin & Shirley's (2000) normalization:
//     ks (n+1)/(8 pi) cos^n(theta_h) / ((h.wi) max(cos theta_i, cos theta_o)),
//     whose cosine-weighted integral is at most 1 for every wo (the classic (n+8)/(8 pi)
//     factor exceeds 1 near normal incidence).
class PhongMaterial final : public SimpleMaterial {
 public:
  PhongMaterial(ColorParam diffuse, Rgb specular, float shininess, ColorParam emission,
                bool blinn = false);
  uint32_t flags() const override { return kBsdfDiffuse | kBsdfGlossy | kBsdfReflection; }

 protected:
  Rgb evalBsdf(const SurfaceInteraction& si, Vec3f wi) const override;
  std::optional<BsdfSample> sampleBsdf(const SurfaceInteraction& si, Vec2f u, float uLobe,
                                       uint32_t lobes) const override;
  float pdfBsdf(const SurfaceInteraction& si, Vec3f wi) const override;

 private:
  // Probability of sampling the specular lobe, from the lobes' relative weights.
  float specularProbability(const SurfaceInteraction& si) const;
  // The specular lobe's value (without ks) and its sampling density, for wi.
  float specularLobe(const SurfaceInteraction& si, Vec3f wi) const;
  float specularPdf(const SurfaceInteraction& si, Vec3f wi) const;
  Rgb specular_;
  float shininess_;
  bool blinn_;
};

}  // namespace glint
