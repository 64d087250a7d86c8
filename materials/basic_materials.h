// glint — the course's first shaders: eyelight, Lambert and (energy-normalized) Phong.
#pragma once

#include "materials/material.h"

namespace glint {

// Shared parts of the simple materials: diffuse colour and emission.
class SimpleMaterial : public Material {
 public:
  SimpleMaterial(ColorParam diffuse, ColorParam emission)
      : diffuse_(diffuse), emission_(emission) {}
  Rgb emitted(const SurfaceInteraction& si) const override { return emission_.evaluate(si); }
  Rgb albedo(const SurfaceInteraction& si) const override { return diffuse_.evaluate(si); }
  bool usesTextures() const override { return diffuse_.texture || emission_.texture; }
  bool usesVertexColors() const override {
    return diffuse_.useVertexColor || emission_.useVertexColor;
  }
  bool emits() const override {
    return emission_.texture || maxComponent(emission_.factor) > 0;
  }

 protected:
  ColorParam diffuse_, emission_;
};

// Colour x |cos(normal, view)|, independent of lights: the ray tracing course's first shader.
class EyelightMaterial final : public SimpleMaterial {
 public:
  explicit EyelightMaterial(ColorParam color) : SimpleMaterial(color, ColorParam{{0, 0, 0}}) {}
  Rgb eval(const SurfaceInteraction&, Vec3f) const override { return {}; }
  std::optional<BsdfSample> sample(const SurfaceInteraction&, Vec2f, float) const override {
    return std::nullopt;
  }
  float pdf(const SurfaceInteraction&, Vec3f) const override { return 0; }
  uint32_t flags() const override { return kBsdfUnlit; }
};

// Ideal diffuse reflection: f = albedo / pi.
class LambertMaterial final : public SimpleMaterial {
 public:
  using SimpleMaterial::SimpleMaterial;
  Rgb eval(const SurfaceInteraction& si, Vec3f wi) const override;
  std::optional<BsdfSample> sample(const SurfaceInteraction& si, Vec2f u,
                                   float uLobe) const override;
  float pdf(const SurfaceInteraction& si, Vec3f wi) const override;
  uint32_t flags() const override { return kBsdfDiffuse | kBsdfReflection; }
};

// Energy-normalized Phong (Lafortune & Willems 1994): f = kd/pi + ks (n+2)/(2 pi) cos^n(alpha),
// alpha between wi and the mirror direction of wo. Reflects no more than it receives as long
// as kd + ks <= 1 per channel (the scene builder checks this).
class PhongMaterial final : public SimpleMaterial {
 public:
  PhongMaterial(ColorParam diffuse, Rgb specular, float shininess, ColorParam emission);
  Rgb eval(const SurfaceInteraction& si, Vec3f wi) const override;
  std::optional<BsdfSample> sample(const SurfaceInteraction& si, Vec2f u,
                                   float uLobe) const override;
  float pdf(const SurfaceInteraction& si, Vec3f wi) const override;
  uint32_t flags() const override { return kBsdfDiffuse | kBsdfGlossy | kBsdfReflection; }

 private:
  // Probability of sampling the specular lobe, from the lobes' relative weights.
  float specularProbability(const SurfaceInteraction& si) const;
  Rgb specular_;
  float shininess_;
};

}  // namespace glint
