// glint — RenderScene: the render-time objects built from a scene description.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "geometry/accel/accelerator.h"
#include "materials/material.h"
#include "renderer/camera.h"
#include "renderer/features.h"
#include "renderer/light.h"

namespace glint {

struct RenderScene {
  GeometryScene geometry;
  std::vector<uint32_t> meshMaterial;  // material index per mesh
  std::vector<std::unique_ptr<Material>> materials;
  std::vector<std::unique_ptr<Texture>> textures;
  std::vector<std::unique_ptr<Light>> lights;
  Camera camera;
  std::string cameraName;
  Rgb background{0, 0, 0};
  SceneFeatures features;
  std::unique_ptr<Accelerator> accel;  // built last, over `geometry`

  const Material& materialOf(uint32_t mesh) const { return *materials[meshMaterial[mesh]]; }
};

// Derives the features from the built scene (materials, lights, instancing). The builder calls
// it once; flags it cannot see (e.g. Headlight) are set by the builder itself.
SceneFeatures detectFeatures(const RenderScene& scene);

}  // namespace glint
