// glint — feature names.
#include "renderer/features.h"

namespace glint {

const char* featureName(Feature f) {
  switch (f) {
    case Feature::Shadows:
      return "shadows";
    case Feature::Textures:
      return "textures";
    case Feature::VertexColors:
      return "vertex colors";
    case Feature::Emission:
      return "emission";
    case Feature::Instancing:
      return "instancing";
    case Feature::DefaultLight:
      return "default light";
    case Feature::Analytic:
      return "analytic";
    case Feature::Csg:
      return "csg";
    case Feature::Terrain:
      return "terrain";
    case Feature::Transparency:
      return "transparency";
    case Feature::Refraction:
      return "refraction";
    case Feature::Bump:
      return "bump";
    case Feature::Procedural:
      return "procedural";
    case Feature::Lens:
      return "depth of field";
    case Feature::MotionBlur:
      return "motion blur";
    case Feature::Volumes:
      return "volumes";
    case Feature::AreaLights:
      return "area lights";
    case Feature::Environment:
      return "environment light";
    case Feature::Projective:
      return "projective light";
    case Feature::Indirect:
      return "indirect light";
    case Feature::Vpls:
      return "virtual point lights";
    case Feature::Count:
      break;
  }
  return "?";
}

std::vector<std::string> SceneFeatures::names() const {
  std::vector<std::string> out;
  for (uint32_t i = 0; i < uint32_t(Feature::Count); ++i)
    if (has(Feature(i))) out.push_back(featureName(Feature(i)));
  return out;
}

}  // namespace glint
