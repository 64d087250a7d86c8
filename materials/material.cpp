// glint — what every material shares: traits, normal modifiers, alpha.
#include "materials/material.h"

namespace glint {

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

float Material::opacity(const SurfaceInteraction& si, TextureLookups& lookups) const {
  if (alphaMode_ == AlphaMode::Opaque) return 1;
  const float a = alphaSource_.alpha(si, alphaFactor_, lookups);
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
