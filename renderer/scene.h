// glint — RenderScene: the render-time objects built from a scene description.
//
// A RenderScene is made from SceneParts (plain data, assembled by scenes/build.cpp) by its
// constructor, which checks that the parts agree (a material for every mesh and every slot of
// every shape, indices in range, one object frame per instance) and derives everything that
// follows from them: the emitting surfaces' lights, the lights' preprocessing and sampler, the
// environment lights, the scene's features and its accelerator. After that, its data can only
// be read, or changed through the few methods below, each of which re-derives what the change
// moves; so no caller can leave a table pointing past the lights, a light reading a material
// that is gone, or the sampler over lights that are gone.
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
#include "renderer/surface_lights.h"
#include "renderer/volume.h"

namespace glint {

// What a RenderScene is made of, before its constructor checks and completes it.
struct SceneParts {
  GeometryScene geometry;
  std::vector<std::unique_ptr<Material>> materials;
  std::vector<uint32_t> meshMaterial;  // per mesh of `geometry`, an index into `materials`
  // Per analytic shape of `geometry`, the material index of each of its material slots.
  std::vector<std::vector<uint32_t>> shapeMaterials;
  // The images the textures read (before them: it must outlive them); shared with the next
  // frames of a sequence (BuildOptions::images).
  std::shared_ptr<TextureImages> images;
  std::vector<std::unique_ptr<Texture>> textures;
  // Per instance: the frame its object was authored in, for object-space textures (meshes
  // baked into world space keep their original placement here).
  std::vector<Transform> objectFromWorld;
  // The scene's own lights: those it names and the studio environment. Emitting surfaces are
  // not among them: RenderScene makes their lights from the materials.
  std::vector<std::unique_ptr<Light>> lights;
  Camera camera;
  std::string cameraName;
  Rgb background{0, 0, 0};  // what escaping rays see when there is no environment light
  // Participating media (renderer/volume.h); null when the scene has none (Feature::Volumes).
  std::unique_ptr<MediaScene> media;
};

// How the constructor completes the parts.
struct SceneAssembly {
  std::string accelerator = "embree";  // makeAccelerator's name
  IntegratorSettings integrator;       // its light sampler, and what features follow from it
  BuildNotes notes;                    // what the builder added (the studio light, a terrain)
};

class RenderScene {
 public:
  // An empty scene with nothing to render, to be assigned a built one.
  RenderScene() = default;
  // Checks `parts` (a disagreement is a bug in the builder, thrown as std::logic_error), adds
  // the emitting surfaces' lights after the parts' own, preprocesses the lights with the
  // scene's extent, builds the light sampler, detects the features and builds the accelerator
  // over the geometry (its seconds in `acceleratorSeconds`).
  RenderScene(SceneParts parts, const SceneAssembly& assembly,
              double* acceleratorSeconds = nullptr);
  RenderScene(RenderScene&&) noexcept = default;
  RenderScene& operator=(RenderScene&&) noexcept = default;

  // ---- Reading
  const GeometryScene& geometry() const { return parts_.geometry; }
  const Accelerator& accel() const { return *accel_; }
  const std::vector<std::unique_ptr<Material>>& materials() const { return parts_.materials; }
  const std::shared_ptr<TextureImages>& images() const { return parts_.images; }
  const std::vector<std::unique_ptr<Texture>>& textures() const { return parts_.textures; }
  // Every light: the scene's own, then one per emitting surface that can be sampled.
  const std::vector<std::unique_ptr<Light>>& lights() const { return lights_; }
  // Per instance, the index in lights() of the area light it is, or -1; empty when no surface
  // emits.
  const std::vector<int32_t>& instanceLight() const { return surfaces_.ofInstance; }
  const std::vector<UnsampledEmitter>& unsampledEmitters() const { return surfaces_.unsampled; }
  const std::vector<const Light*>& infiniteLights() const { return infiniteLights_; }
  // Over lights(), for next-event estimation; null in a scene without lights.
  const LightSampler* lightSampler() const { return lightSampler_.get(); }
  const Camera& camera() const { return parts_.camera; }
  const std::string& cameraName() const { return parts_.cameraName; }
  Rgb background() const { return parts_.background; }
  const SceneFeatures& features() const { return features_; }
  const MediaScene* media() const { return parts_.media.get(); }
  // The frame instance `i`'s object was authored in (object-space textures).
  const Transform& objectFromWorld(uint32_t i) const { return parts_.objectFromWorld[i]; }

  // The static placement of shape instance `i`, or null (a mesh or a moving shape).
  const PlacedShape* placedShape(uint32_t i) const {
    return i < placedShapeOf_.size() && placedShapeOf_[i] != kNoPlacement
               ? &placedShapes_[placedShapeOf_[i]]
               : nullptr;
  }
  // Radiance along an escaping ray of unit direction d: the environment lights', or the
  // background (which lights nothing) when there are none.
  Rgb escaped(Vec3f d) const {
    if (infiniteLights_.empty()) return parts_.background;
    Rgb L;
    for (const Light* l : infiniteLights_) L += l->Le(d);
    return L;
  }
  // The same for a direction of any length, normalised only when an environment reads it:
  // most camera rays of a scene without one miss everything, and the square root and division
  // were a third of their shading time.
  Rgb escapedAlong(Vec3f d) const {
    return infiniteLights_.empty() ? parts_.background : escaped(normalize(d));
  }
  // The area light a hit found, or null.
  const Light* areaLight(const Hit& hit, uint32_t* index = nullptr) const {
    const std::vector<int32_t>& of = surfaces_.ofInstance;
    if (of.empty() || of[hit.instance] < 0) return nullptr;
    if (index) *index = uint32_t(of[hit.instance]);
    return lights_[size_t(of[hit.instance])].get();
  }
  uint32_t meshMaterialIndex(uint32_t mesh) const { return parts_.meshMaterial[mesh]; }
  const Material& materialOf(uint32_t mesh) const {
    return *parts_.materials[parts_.meshMaterial[mesh]];
  }
  // The material indices of analytic shape `shape`'s slots.
  const std::vector<uint32_t>& shapeMaterials(uint32_t shape) const {
    return parts_.shapeMaterials[shape];
  }
  // The material index of a hit, on a mesh or an analytic shape.
  uint32_t materialIndex(const Hit& hit) const {
    const Instance& inst = parts_.geometry.instances[hit.instance];
    if (!inst.isShape()) return parts_.meshMaterial[inst.mesh];
    return parts_
        .shapeMaterials[inst.shape][parts_.geometry.shapes[inst.shape]->materialSlot(hit.prim)];
  }

  // ---- Changing (each re-derives what it moves; integrators made before must be made again)
  // Another camera (a preview's view, a test's lens): re-detects the features (lens, motion).
  void setCamera(Camera camera, std::string name);
  // Material `index` replaced (its slot in every mesh and shape that uses it): the emitting
  // surfaces' lights are made again, and the features re-detected.
  void replaceMaterial(uint32_t index, std::unique_ptr<Material> material);
  // Replaces the scene's own lights (the emitting surfaces stay lights). The lights are
  // preprocessed, sampled by the assembly's light sampler, and the features re-detected (the
  // studio light, if it was one, is gone with the others).
  void setLights(std::vector<std::unique_ptr<Light>> lights);
  // Adds a light to the scene's own (and re-derives as setLights does).
  void addLight(std::unique_ptr<Light> light);
  // Samples the lights by `name` (makeLightSampler's names).
  void setLightSampler(const std::string& name);
  // Turns one feature on or off against what detection found, to render with or without an
  // effect (tests, benchmarks); the next change above detects them all again.
  void setFeature(Feature feature, bool on = true) { features_.set(feature, on); }

 private:
  void checkParts() const;
  static void checkLights(const std::vector<std::unique_ptr<Light>>& lights);
  // The emitting surfaces' lights after the parts' own; then every light preprocessed, the
  // infinite lights, the sampler and the features.
  void deriveLights();
  void detect() { features_ = detectFeatures(*this, assembly_.integrator, assembly_.notes); }

  SceneParts parts_;
  SceneAssembly assembly_;
  // The scene's own lights (parts_.lights, moved here) and after them, from ownLights_ on,
  // the emitting surfaces' (surfaces_.lights, moved here; surfaces_ keeps their tables).
  std::vector<std::unique_ptr<Light>> lights_;
  size_t ownLights_ = 0;
  SurfaceLights surfaces_;
  std::vector<const Light*> infiniteLights_;  // the environment lights among the lights
  std::unique_ptr<LightSampler> lightSampler_;
  SceneFeatures features_;
  std::unique_ptr<Accelerator> accel_;  // built last, over the geometry
  // The static analytic shapes placed in the world once, for shading: the placement's inverse
  // and flags are not worked out again at every hit. placedShapeOf_[instance] indexes
  // placedShapes_ (kNoPlacement for meshes and moving shapes, placed at each ray's time); both
  // stay empty in a scene without static shapes.
  static constexpr uint32_t kNoPlacement = ~0u;
  std::vector<PlacedShape> placedShapes_;
  std::vector<uint32_t> placedShapeOf_;
};

}  // namespace glint
