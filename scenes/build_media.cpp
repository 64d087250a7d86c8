// glint — media descriptions to render-time media.
#include "scenes/build_media.h"

#include "materials/vdb_volume.h"

namespace glint {

namespace {

std::unique_ptr<DensityField> makeDensity(const MediumDesc& m, const Bounds3f& regionBounds) {
  switch (m.density) {
    case DensityType::Grid:
      return std::make_unique<GridDensity>(m.gridRes[0], m.gridRes[1], m.gridRes[2], m.gridValues,
                                           regionBounds);
    case DensityType::Noise:
      return std::make_unique<NoiseDensity>(m.noiseScale, m.noiseOctaves, m.noiseThreshold,
                                            m.noiseSeed, m.noiseOffset);
    case DensityType::Exponential:
      return std::make_unique<ExponentialDensity>(m.up, m.falloff, m.h0);
    case DensityType::Vdb:
      return std::make_unique<VdbDensity>(m.vdb, m.vdbScale);
    case DensityType::Constant:
    default:
      return std::make_unique<ConstantDensity>(m.value);
  }
}

// The box a whole-scene medium fills.
Bounds3f sceneBox(const SceneParts& scene) {
  Bounds3f box = scene.geometry.bounds();
  box.extend(scene.camera.position());
  for (const auto& light : scene.lights)
    if (std::optional<LightBounds> lb = light->bounds()) box.extend(lb->bounds);
  const Vec3f margin = Vec3f{1, 1, 1} * (0.01f * length(box.diagonal()));
  return {box.lower - margin, box.upper + margin};
}

// A VDB fire's own emission (blackbody, flame); null when it has none.
std::unique_ptr<EmissionField> makeEmission(const MediumDesc& m) {
  if (m.density != DensityType::Vdb) return nullptr;
  const VdbVolume& v = *m.vdb;
  const bool blackbody = v.temperature && m.blackbodyIntensity > 0;
  const bool flame = v.flame && m.flameStrength > 0 && maxComponent(m.flameColor) > 0;
  if (!blackbody && !flame) return nullptr;
  VdbEmissionParams p;
  p.blackbodyIntensity = blackbody ? m.blackbodyIntensity : 0;
  p.flameStrength = flame ? m.flameStrength : 0;
  p.flameColor = m.flameColor;
  return std::make_unique<VdbEmission>(m.vdb, p);
}

}  // namespace

void addMedia(const SceneDescription& desc, SceneParts* scene) {
  if (desc.media.empty()) return;
  auto media = std::make_unique<MediaScene>(desc.render.integrator);
  const Bounds3f box = sceneBox(*scene);
  for (const MediumDesc& m : desc.media) {
    auto medium = std::make_unique<Medium>();
    medium->name = m.name;
    medium->sigmaA = m.sigmaA;
    medium->sigmaS = m.sigmaS;
    medium->Le = m.emission;
    medium->g = m.g;
    medium->heroTracking = m.heroTracking;
    medium->emissionField = makeEmission(m);
    if (m.density == DensityType::Vdb && m.vdb->color) {
      medium->color = std::make_unique<VdbColor>(m.vdb, m.vdbScale);
      medium->colorTintsAlbedo = m.colorTintsAlbedo;
    }
    switch (m.region) {
      case MediumDesc::Region::Scene:
        medium->density = makeDensity(m, box);
        media->addSceneRegion(std::move(medium), box);
        break;
      case MediumDesc::Region::Shape:
      case MediumDesc::Region::Object: {
        const bool object = m.region == MediumDesc::Region::Object;
        // An object's region is where the object is at the frame's time.
        const ObjectDesc* obj = object ? &desc.objects[size_t(m.object)] : nullptr;
        std::unique_ptr<Shape> shape = (obj ? obj->shape : m.shape)->clone();
        medium->density = makeDensity(m, shape->bounds());
        media->addRegion(std::move(medium), std::move(shape),
                         obj ? obj->worldFromObject : m.worldFromRegion);
        break;
      }
    }
  }
  scene->media = std::move(media);
}

}  // namespace glint
