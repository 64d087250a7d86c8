// glint — emitting surfaces as lights: one area light per instance whose material emits.
//
// RenderScene derives them from its parts (renderer/scene.h), after the scene's own lights, and
// derives them again whenever a material changes: an area light reads its material's emission
// through a pointer, so no light may outlive the material it was made from.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "renderer/light.h"

namespace glint {

struct SceneParts;

// An emitting surface next-event estimation cannot sample (no light: it glows only where rays
// hit it), with the reason, for `glint info`.
struct UnsampledEmitter {
  uint32_t instance;
  std::string shape;  // the shape's typeName
  std::string reason;
};

struct SurfaceLights {
  std::vector<std::unique_ptr<Light>> lights;
  // Per instance, the index of its light among the scene's lights (firstIndex + its place in
  // `lights`), or -1; empty when no surface emits.
  std::vector<int32_t> ofInstance;
  // Emitting shapes that cannot be sampled (planes, CSG trees): they still emit where rays
  // hit them but are not lights.
  std::vector<UnsampledEmitter> unsampled;
};

// The area lights of the instances of `parts.geometry` whose material (any of a CSG tree's)
// emits: the instance's mesh or placed shape (at the middle of the shutter) with the material's
// emission, numbered from `firstIndex` on.
SurfaceLights makeSurfaceLights(const SceneParts& parts, uint32_t firstIndex);

}  // namespace glint
