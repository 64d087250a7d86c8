// glint — feature detection over a built scene, and the features' names.
#include "renderer/features.h"

#include "geometry/csg.h"
#include "renderer/integrator.h"
#include "renderer/projective_light.h"
#include "renderer/scene.h"

namespace glint {

namespace {

void addMaterialFeatures(const Material& mat, SceneFeatures* f, bool* anyLit) {
  const MaterialTraits& t = mat.traits();
  if (t.imageTextures) f->set(Feature::Textures);
  if (t.procedural) f->set(Feature::Procedural);
  if (t.vertexColors) f->set(Feature::VertexColors);
  if (t.emits) f->set(Feature::Emission);
  if (t.bump) f->set(Feature::Bump);
  if (t.transparency) f->set(Feature::Transparency);
  if (t.refraction) f->set(Feature::Refraction);
  if (!(mat.flags() & kBsdfUnlit)) *anyLit = true;
}

}  // namespace

SceneFeatures detectFeatures(const RenderScene& scene, const IntegratorSettings& integrator,
                             const BuildNotes& notes) {
  SceneFeatures f;
  f.set(Feature::DefaultLight, notes.defaultLight);
  f.set(Feature::Terrain, notes.terrain);
  f.set(Feature::Lens, scene.camera().hasLens());
  // Moving placements and deforming meshes alike.
  f.set(Feature::MotionBlur, scene.camera().isMoving() || scene.geometry().hasMotion());
  f.set(Feature::Volumes, scene.media() != nullptr);
  std::vector<uint32_t> uses(scene.geometry().meshes.size(), 0);
  bool anyLit = false;
  for (const Instance& inst : scene.geometry().instances) {
    if (!inst.isShape()) {
      ++uses[inst.mesh];
      continue;
    }
    f.set(Feature::Analytic);
    if (dynamic_cast<const CsgShape*>(scene.geometry().shapes[inst.shape].get()))
      f.set(Feature::Csg);
    for (uint32_t m : scene.shapeMaterials(inst.shape))
      addMaterialFeatures(*scene.materials()[m], &f, &anyLit);
  }
  for (size_t m = 0; m < scene.geometry().meshes.size(); ++m) {
    if (uses[m] == 0) continue;
    if (uses[m] > 1) f.set(Feature::Instancing);
    addMaterialFeatures(scene.materialOf(uint32_t(m)), &f, &anyLit);
  }
  for (const auto& light : scene.lights()) {
    if (light->castsShadows() && anyLit) f.set(Feature::Shadows);
    if (light->kind() == LightKind::Area) f.set(Feature::AreaLights);
    if (light->kind() == LightKind::Infinite) f.set(Feature::Environment);
    if (dynamic_cast<const ProjectiveLight*>(light.get())) f.set(Feature::Projective);
  }
  const IntegratorKind kind = resolveIntegrator(scene, integrator);
  f.set(Feature::Indirect, kind != IntegratorKind::Whitted);
  f.set(Feature::Vpls, kind == IntegratorKind::InstantRadiosity);
  return f;
}

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
