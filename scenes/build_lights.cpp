// glint — the lights a scene description names: sidecar lights and the environment.
#include "scenes/build_lights.h"

#include <cmath>

#include "geometry/shapes/disk.h"
#include "geometry/shapes/quad.h"
#include "geometry/shapes/sphere.h"
#include "image/input.h"
#include "renderer/area_lights.h"
#include "renderer/environment_light.h"
#include "renderer/projective_light.h"
#include "scenes/errors.h"

namespace glint {

std::unique_ptr<Light> makeSidecarLight(const LightDesc& l, const Transform& world,
                                        const Texture* slide) {
  AreaEmission emission;
  emission.radiance = l.color * l.intensity;
  emission.twoSided = l.twoSided;
  // Area lights are the matching shape in the light's frame; any placement (a sphere under a
  // non-uniform scale is an ellipsoid, sampled just as exactly).
  std::unique_ptr<Shape> shape;
  Transform placement = world;
  switch (l.type) {
    case LightType::Quad:
      shape = std::make_unique<Quad>(l.corner, l.edgeU, l.edgeV);
      break;
    case LightType::Disk:
      // In the frame's XY plane facing -Z: the disk shape's +Y normal turned to -Z, its (x, z)
      // onto the frame's (x, y).
      shape = std::make_unique<Disk>(l.radius);
      placement = world * Transform::rotate(-90, {1, 0, 0});
      break;
    case LightType::Sphere:
      shape = std::make_unique<Sphere>(Vec3f{0, 0, 0}, l.radius);
      break;
    case LightType::Projective:
      return std::make_unique<ProjectiveLight>(world, l.color * l.intensity, l.fov, slide,
                                               l.attenuation, l.castsShadows);
    default:
      return nullptr;
  }
  auto area = makeShapeLight(std::move(shape), placement, emission);
  area->setCastsShadows(l.castsShadows);
  return area;
}

std::unique_ptr<Light> makeEnvironmentLight(const EnvironmentDesc& env) {
  if (env.studio) {
    // 512 x 256: the softbox's 12-degree radius spans 34 pixels, enough for a smooth edge.
    constexpr int kWidth = 512, kHeight = 256;
    return std::make_unique<ImageEnvironmentLight>(
        kWidth, kHeight, studioEnvironment(kWidth, kHeight), env.intensity, env.rotation);
  }
  if (env.image.empty())
    return std::make_unique<UniformEnvironmentLight>(env.color * env.intensity);
  Film film;
  try {
    film = readSceneLinear(env.image);
  } catch (const FailureError&) {
    throw;  // not the scene's fault (the OpenImageIO plugin is missing): exit code 1
  } catch (const std::exception& e) {
    // The sidecar's "image" key, or the command line's --env itself.
    throw SceneError(env.where.file == "command line" ? env.where : env.where.child("image"),
                     e.what());
  }
  return std::make_unique<ImageEnvironmentLight>(film.width, film.height, std::move(film.color),
                                                 env.intensity, env.rotation);
}

}  // namespace glint
