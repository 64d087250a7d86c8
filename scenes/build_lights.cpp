// glint — emitting surfaces as lights.
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

namespace {

// Why an emitting shape cannot be sampled (its area() is 0), for `glint info`.
std::string unsampledReason(const Shape& shape) {
  if (isUnbounded(shape.bounds()))
    return "unbounded: no finite area to draw points from; it glows where rays hit it";
  if (std::string(shape.typeName()) == "csg")
    return "a CSG surface is the parts of its leaves that survive the set operations, with no "
           "direct way to draw points on it; it glows where rays hit it";
  return std::string("the ") + shape.typeName() + " shape has no sampling routine";
}

std::unique_ptr<Light> meshLight(const TriangleMesh& mesh, const Transform& world,
                                 const AreaEmission& emission) {
  EmissiveMesh m{mesh.positions, mesh.indices, mesh.normals, mesh.uvs, mesh.uvs1};
  if (!world.isIdentity()) {
    placeVertices(world, &m.positions, &m.indices);  // the winding faces the front
    for (Vec3f& n : m.normals) n = normalize(world.normal(n));
  }
  return std::make_unique<AreaLight>(std::move(m), emission);
}

}  // namespace

bool addEmissiveSurfaceLights(RenderScene* scene) {
  const GeometryScene& g = scene->geometry;
  bool anyEmits = false;
  for (uint32_t i = 0; i < g.instances.size(); ++i) {
    const Instance& inst = g.instances[i];
    // A shape emits when any of its materials does (CSG trees have one per leaf).
    const uint32_t m =
        inst.isShape() ? scene->shapeMaterials[inst.shape].front() : scene->meshMaterial[inst.mesh];
    bool emits = scene->materials[m]->traits().emits;
    if (inst.isShape())
      for (uint32_t sm : scene->shapeMaterials[inst.shape])
        emits = emits || scene->materials[sm]->traits().emits;
    if (!emits) continue;
    anyEmits = true;
    if (scene->instanceLight.empty()) scene->instanceLight.assign(g.instances.size(), -1);
    if (inst.isShape() && !(g.shapes[inst.shape]->area() > 0)) {
      const Shape& shape = *g.shapes[inst.shape];
      scene->unsampledEmitters.push_back({i, shape.typeName(), unsampledReason(shape)});
      continue;
    }
    // Moving emitters are placed at the middle of the shutter, like every light.
    const Transform world = inst.worldFromObjectAt(0.5f);
    AreaEmission emission;
    emission.material = scene->materials[m].get();
    emission.objectFromWorld = inst.moves() ? world.inverse() : scene->objectFromWorld[i];
    emission.instance = i;
    // Material::emitted does not depend on the side; a single-sided mesh is seen, and so
    // emits, from the front only.
    emission.twoSided = inst.isShape() || !g.meshes[inst.mesh].singleSided;
    scene->instanceLight[i] = int32_t(scene->lights.size());
    if (inst.isShape())
      scene->lights.push_back(
          std::make_unique<AreaLight>(PlacedShape(g.shapes[inst.shape].get(), world), emission));
    else
      scene->lights.push_back(meshLight(g.meshes[inst.mesh], world, emission));
  }
  return anyEmits;
}

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
