// glint — eyelight, Lambert, Phong and Blinn-Phong: what they read.
#include "materials/basic_materials.h"

namespace glint {

SimpleMaterial::SimpleMaterial(ColorParam diffuse, ColorParam emission)
    : diffuse_(diffuse), emission_(emission) {
  uses(diffuse_);
  uses(emission_);
  traits_.emits = !emission_.isBlack();
}

}  // namespace glint
