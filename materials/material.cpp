// glint — what every material shares: the terminator term, traits, normal modifiers.
#include "materials/material.h"

namespace glint {

float terminatorShadowing(Vec3f ng, Vec3f ns, Vec3f wi) {
  const float cosNs = dot(ns, wi), cosNg = dot(ng, wi), cosNsNg = dot(ns, ng);
  if (cosNs <= 0 || cosNg <= 0 || cosNsNg <= 0) return cosNg > 0 ? 1.0f : 0.0f;
  const float g = std::min(1.0f, cosNg / (cosNs * cosNsNg));
  return -g * g * g + g * g + g;  // the smooth form of the paper's eq. 4
}

Rgb Material::eval(const SurfaceInteraction& si, Vec3f wi) const {
  Rgb f = evalBsdf(si, wi);
  if (normalModifier_ && dot(wi, si.ng) > 0) f *= terminatorShadowing(si.ng, si.ns, wi);
  return f;
}

std::optional<BsdfSample> Material::sample(const SurfaceInteraction& si, Vec2f u, float uLobe,
                                           uint32_t lobes) const {
  std::optional<BsdfSample> s = sampleBsdf(si, u, uLobe, lobes);
  if (s && normalModifier_ && !(s->flags & kBsdfSpecular) && dot(s->wi, si.ng) > 0)
    s->f *= terminatorShadowing(si.ng, si.ns, s->wi);
  return s;
}

void Material::setNormalModifier(std::unique_ptr<NormalModifier> m) {
  normalModifier_ = std::move(m);
  if (!normalModifier_) return;
  traits_.bump = true;
  traits_.needs.tangents = true;
  traits_.needs |= normalModifier_->needs();
  for (const Texture* t : normalModifier_->textures()) uses(t);
}

void Material::setAlpha(AlphaMode mode, float factor, float cutoff, const ColorParam& source) {
  alphaMode_ = mode;
  alphaFactor_ = factor;
  alphaCutoff_ = cutoff;
  alphaSource_ = source;
  if (mode == AlphaMode::Opaque) return;
  traits_.transparency = true;
  uses(source);
}

float Material::opacity(const SurfaceInteraction& si) const {
  if (alphaMode_ == AlphaMode::Opaque) return 1;
  const float a = alphaSource_.alpha(si, alphaFactor_);
  if (alphaMode_ == AlphaMode::Mask) return a >= alphaCutoff_ ? 1.0f : 0.0f;
  return std::clamp(a, 0.0f, 1.0f);
}

void Material::uses(const Texture* t) {
  if (!t) return;
  if (t->isImage())
    traits_.imageTextures = true;
  else
    traits_.procedural = true;
  traits_.needs |= t->needs();
}

void Material::uses(const ColorParam& c) {
  uses(c.texture);
  if (c.useVertexColor) traits_.vertexColors = true;
}

void Material::uses(const FloatParam& f) { uses(f.texture); }

}  // namespace glint
