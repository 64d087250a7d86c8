// glint — the scene as the renderer sees it: its parts checked, and what follows from them.
#include "renderer/scene.h"

#include <chrono>
#include <stdexcept>

namespace glint {

namespace {

// The builder broke a rule of SceneParts: a bug, not the user's input.
[[noreturn]] void broken(const std::string& what) {
  throw std::logic_error("RenderScene: " + what);
}

}  // namespace

RenderScene::RenderScene(SceneParts parts, const SceneAssembly& assembly,
                         double* acceleratorSeconds)
    : parts_(std::move(parts)), assembly_(assembly) {
  checkParts();
  lights_ = std::move(parts_.lights);
  ownLights_ = lights_.size();
  deriveLights();
  const auto start = std::chrono::steady_clock::now();
  accel_ = makeAccelerator(assembly_.accelerator, parts_.geometry);
  if (acceleratorSeconds)
    *acceleratorSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const GeometryScene& g = parts_.geometry;
  for (uint32_t i = 0; i < g.instances.size(); ++i) {
    const Instance& inst = g.instances[i];
    if (!inst.isShape() || inst.moves()) continue;
    // Only now that there is one: a scene of meshes alone keeps no per-instance table.
    if (placedShapeOf_.empty()) placedShapeOf_.assign(g.instances.size(), kNoPlacement);
    placedShapeOf_[i] = uint32_t(placedShapes_.size());
    placedShapes_.push_back(g.placedShape(i));
  }
}

void RenderScene::checkParts() const {
  const SceneParts& p = parts_;
  const GeometryScene& g = p.geometry;
  const size_t materials = p.materials.size();
  if (p.meshMaterial.size() != g.meshes.size())
    broken(std::to_string(p.meshMaterial.size()) + " mesh materials for " +
           std::to_string(g.meshes.size()) + " meshes");
  for (uint32_t m : p.meshMaterial)
    if (m >= materials) broken("a mesh's material " + std::to_string(m) + " is not one");
  if (p.shapeMaterials.size() != g.shapes.size())
    broken(std::to_string(p.shapeMaterials.size()) + " shape material lists for " +
           std::to_string(g.shapes.size()) + " shapes");
  for (size_t s = 0; s < g.shapes.size(); ++s) {
    if (p.shapeMaterials[s].size() != g.shapes[s]->materialSlotCount())
      broken("shape " + std::to_string(s) + " has " + std::to_string(p.shapeMaterials[s].size()) +
             " materials for " + std::to_string(g.shapes[s]->materialSlotCount()) + " slots");
    for (uint32_t m : p.shapeMaterials[s])
      if (m >= materials) broken("a shape's material " + std::to_string(m) + " is not one");
  }
  for (const auto& m : p.materials)
    if (!m) broken("a null material");
  if (p.objectFromWorld.size() != g.instances.size())
    broken(std::to_string(p.objectFromWorld.size()) + " object frames for " +
           std::to_string(g.instances.size()) + " instances");
  checkLights(p.lights);
}

void RenderScene::checkLights(const std::vector<std::unique_ptr<Light>>& lights) {
  for (const auto& l : lights)
    if (!l) broken("a null light");
}

void RenderScene::deriveLights() {
  // The surfaces' lights read their materials: made again, never kept past a change.
  lights_.resize(ownLights_);
  surfaces_ = makeSurfaceLights(parts_, uint32_t(ownLights_));
  for (auto& light : surfaces_.lights) lights_.push_back(std::move(light));
  surfaces_.lights.clear();
  // Lights at infinity learn the scene's extent; then the sampler that picks among them.
  const Bounds3f extent = parts_.geometry.bounds();
  infiniteLights_.clear();
  for (auto& light : lights_) {
    light->preprocess(extent);
    if (light->kind() == LightKind::Infinite) infiniteLights_.push_back(light.get());
  }
  lightSampler_ = makeLightSampler(assembly_.integrator.lightSampler, lights_);
  detect();
}

void RenderScene::setCamera(Camera camera, std::string name) {
  parts_.camera = std::move(camera);
  parts_.cameraName = std::move(name);
  detect();
}

void RenderScene::replaceMaterial(uint32_t index, std::unique_ptr<Material> material) {
  if (index >= parts_.materials.size() || !material)
    broken("replaceMaterial(" + std::to_string(index) + ") of " +
           std::to_string(parts_.materials.size()) + " materials");
  parts_.materials[index] = std::move(material);
  deriveLights();
}

void RenderScene::setLights(std::vector<std::unique_ptr<Light>> lights) {
  checkLights(lights);
  lights_ = std::move(lights);
  ownLights_ = lights_.size();
  assembly_.notes.defaultLight = false;
  deriveLights();
}

void RenderScene::addLight(std::unique_ptr<Light> light) {
  if (!light) broken("a null light");
  lights_.insert(lights_.begin() + std::ptrdiff_t(ownLights_), std::move(light));
  ++ownLights_;
  deriveLights();
}

void RenderScene::setLightSampler(const std::string& name) {
  assembly_.integrator.lightSampler = name;
  lightSampler_ = makeLightSampler(name, lights_);
}

}  // namespace glint
