// glint — RenderScene: the render-time objects built from a scene description.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "geometry/accel/accelerator.h"
#include "materials/image_texture.h"
#include "materials/material.h"
#include "renderer/camera.h"
#include "renderer/features.h"
#include "renderer/light.h"
#include "renderer/light_sampler.h"
#include "renderer/settings.h"
#include "renderer/volume.h"

namespace glint {

struct RenderScene {
  GeometryScene geometry;
  std::vector<uint32_t> meshMaterial;  // material index per mesh
  // Per analytic shape (GeometryScene::shapes), the material index of each material slot.
  std::vector<std::vector<uint32_t>> shapeMaterials;
  std::vector<std::unique_ptr<Material>> materials;
  // The images the textures read (before them: it must outlive them); shared with the next
  // frames of a sequence (BuildOptions::images).
  std::shared_ptr<TextureImages> images;
  std::vector<std::unique_ptr<Texture>> textures;
  // Per instance: the frame its object was authored in, for object-space textures (meshes
  // baked into world space keep their original placement here).
  std::vector<Transform> objectFromWorld;
  std::vector<std::unique_ptr<Light>> lights;  // every light, emitting surfaces included
  // Per instance, the index in `lights` of the area light it is (an emissive mesh or shape),
  // or -1; empty when no surface emits.
  std::vector<int32_t> instanceLight;
  // Emitting surfaces next-event estimation cannot sample (no lights: they glow only where
  // rays hit them), with the reason, for `glint info`.
  struct UnsampledEmitter {
    uint32_t instance;
    std::string shape;  // the shape's typeName
    std::string reason;
  };
  std::vector<UnsampledEmitter> unsampledEmitters;
  std::vector<const Light*> infiniteLights;    // the environment lights among `lights`
  std::unique_ptr<LightSampler> lightSampler;  // over `lights`, for next-event estimation
  Camera camera;
  std::string cameraName;
  Rgb background{0, 0, 0};  // what escaping rays see when there is no environment light
  SceneFeatures features;
  // Participating media (renderer/volume.h); null when the scene has none (Feature::Volumes).
  std::unique_ptr<MediaScene> media;
  std::unique_ptr<Accelerator> accel;  // built last, over `geometry` (buildAccelerator)
  // The static analytic shapes placed in the world once, for shading: the placement's inverse
  // and flags are not worked out again at every hit. placedShapeOf[instance] indexes
  // placedShapes (kNoPlacement for meshes and moving shapes, placed at each ray's time); both
  // stay empty in a scene without static shapes, and unless buildAccelerator made them.
  static constexpr uint32_t kNoPlacement = ~0u;
  std::vector<PlacedShape> placedShapes;
  std::vector<uint32_t> placedShapeOf;

  // Builds `accel` over `geometry` and fills `placedShapes`: once the geometry is final.
  void buildAccelerator(const std::string& name);
  // The static placement of shape instance `i`, or null (a mesh, a moving shape, or none built).
  const PlacedShape* placedShape(uint32_t i) const {
    return i < placedShapeOf.size() && placedShapeOf[i] != kNoPlacement
               ? &placedShapes[placedShapeOf[i]]
               : nullptr;
  }

  // Radiance along an escaping ray of unit direction d: the environment lights', or the
  // background (which lights nothing) when there are none.
  Rgb escaped(Vec3f d) const {
    if (infiniteLights.empty()) return background;
    Rgb L;
    for (const Light* l : infiniteLights) L += l->Le(d);
    return L;
  }
  // The same for a direction of any length, normalised only when an environment reads it:
  // most camera rays of a scene without one miss everything, and the square root and division
  // were a third of their shading time.
  Rgb escapedAlong(Vec3f d) const {
    return infiniteLights.empty() ? background : escaped(normalize(d));
  }
  // The area light a hit found, or null.
  const Light* areaLight(const Hit& hit, uint32_t* index = nullptr) const {
    if (instanceLight.empty() || instanceLight[hit.instance] < 0) return nullptr;
    if (index) *index = uint32_t(instanceLight[hit.instance]);
    return lights[size_t(instanceLight[hit.instance])].get();
  }
  const Material& materialOf(uint32_t mesh) const { return *materials[meshMaterial[mesh]]; }
  // The material index of a hit, on a mesh or an analytic shape.
  uint32_t materialIndex(const Hit& hit) const {
    const Instance& inst = geometry.instances[hit.instance];
    if (!inst.isShape()) return meshMaterial[inst.mesh];
    return shapeMaterials[inst.shape][geometry.shapes[inst.shape]->materialSlot(hit.prim)];
  }
};

}  // namespace glint
