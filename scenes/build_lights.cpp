// glint — emitting surfaces as lights.
#include "scenes/build_lights.h"

#include <cmath>

#include "geometry/shapes/box.h"
#include "geometry/shapes/cone.h"
#include "geometry/shapes/cylinder.h"
#include "geometry/shapes/disk.h"
#include "geometry/shapes/quad.h"
#include "geometry/shapes/sphere.h"
#include "renderer/area_lights.h"
#include "renderer/environment_light.h"
#include "image/output.h"
#include "renderer/projective_light.h"
#include "scenes/errors.h"

namespace glint {

namespace {

// The uniform scale of a similarity transform's linear part, or 0 when it is not one (a
// sphere stays a sphere only under a similarity).
float uniformScale(const Transform& t) {
  const Vec3f x = t.vector({1, 0, 0}), y = t.vector({0, 1, 0}), z = t.vector({0, 0, 1});
  const float s = length(x);
  constexpr float kTolerance = 1e-4f;  // relative: what float placements round to
  if (!(s > 0) || std::abs(length(y) - s) > kTolerance * s || std::abs(length(z) - s) > kTolerance * s)
    return 0;
  if (std::abs(dot(x, y)) > kTolerance * s * s || std::abs(dot(y, z)) > kTolerance * s * s ||
      std::abs(dot(x, z)) > kTolerance * s * s)
    return 0;
  return s;
}

// The surface of a box, cylinder, cone or sphere as ShapeSurfaceLight parts (object space,
// uv as the shape's surface() gives them); empty for other shapes.
std::vector<SurfacePart> surfaceParts(const Shape& shape) {
  using Kind = SurfacePart::Kind;
  std::vector<SurfacePart> parts;
  auto disk = [](Vec3f centre, float radius, Vec3f normal) {
    SurfacePart p;
    p.kind = Kind::Disk;
    p.origin = centre;
    p.radius = radius;
    p.normal = normal;
    return p;
  };
  if (auto* b = dynamic_cast<const Box*>(&shape)) {
    const Vec3f lo = b->lower(), e = b->upper() - b->lower();
    auto face = [&](Vec3f origin, Vec3f eu, Vec3f ev, Vec3f normal) {
      SurfacePart p;
      p.origin = origin, p.edgeU = eu, p.edgeV = ev, p.normal = normal;
      parts.push_back(p);
    };
    // Box::surface's uv: X faces (z, y), Y faces (x, z), Z faces (x, y), from `lower`.
    const Vec3f ex{e.x, 0, 0}, ey{0, e.y, 0}, ez{0, 0, e.z};
    face(lo, ez, ey, {-1, 0, 0});
    face(lo + ex, ez, ey, {1, 0, 0});
    face(lo, ex, ez, {0, -1, 0});
    face(lo + ey, ex, ez, {0, 1, 0});
    face(lo, ex, ey, {0, 0, -1});
    face(lo + ez, ex, ey, {0, 0, 1});
  } else if (auto* c = dynamic_cast<const Cylinder*>(&shape)) {
    SurfacePart side;
    side.kind = Kind::CylinderSide;
    side.radius = c->radius(), side.height = c->height();
    parts.push_back(side);
    if (c->capped()) {
      parts.push_back(disk({0, 0, 0}, c->radius(), {0, -1, 0}));
      parts.push_back(disk({0, c->height(), 0}, c->radius(), {0, 1, 0}));
    }
  } else if (auto* k = dynamic_cast<const Cone*>(&shape)) {
    SurfacePart side;
    side.kind = Kind::ConeSide;
    side.radius = k->radius(), side.height = k->height();
    parts.push_back(side);
    if (k->capped()) parts.push_back(disk({0, 0, 0}, k->radius(), {0, -1, 0}));
  } else if (auto* s = dynamic_cast<const Sphere*>(&shape)) {
    SurfacePart whole;
    whole.kind = Kind::Sphere;
    whole.origin = s->center(), whole.radius = s->radius();
    parts.push_back(whole);
  }
  return parts;
}

// The area light of an emitting analytic shape, or null when the shape cannot be sampled
// (planes are infinite; CSG trees' surfaces are the parts of their leaves that survive the
// set operations, with no direct way to draw them uniformly).
std::unique_ptr<Light> shapeLight(const Shape& shape, const Transform& world,
                                  const AreaEmission& emission) {
  if (auto* q = dynamic_cast<const Quad*>(&shape))
    return std::make_unique<QuadLight>(world.point(q->corner()), world.vector(q->edgeU()),
                                       world.vector(q->edgeV()), emission);
  if (auto* d = dynamic_cast<const Disk*>(&shape)) {
    const float r = d->radius();
    return std::make_unique<DiskLight>(world.point({0, 0, 0}), world.vector({r, 0, 0}),
                                       world.vector({0, 0, r}), emission);
  }
  if (auto* s = dynamic_cast<const Sphere*>(&shape)) {
    // A sphere under a similarity is sampled by the cone it subtends; an ellipsoid by area.
    const float scale = uniformScale(world);
    if (scale > 0)
      return std::make_unique<SphereLight>(world.point(s->center()), s->radius() * scale,
                                           emission);
  }
  std::vector<SurfacePart> parts = surfaceParts(shape);
  if (!parts.empty()) return std::make_unique<ShapeSurfaceLight>(std::move(parts), world, emission);
  return nullptr;
}

std::unique_ptr<Light> meshLight(const TriangleMesh& mesh, const Transform& world,
                                 const AreaEmission& emission) {
  std::vector<Vec3f> positions = mesh.positions, normals = mesh.normals;
  if (!world.isIdentity()) {
    for (Vec3f& p : positions) p = world.point(p);
    for (Vec3f& n : normals) n = normalize(world.normal(n));
  }
  return std::make_unique<TriangleMeshLight>(std::move(positions), mesh.indices,
                                             std::move(normals), mesh.uvs, emission);
}

}  // namespace

bool addEmissiveSurfaceLights(RenderScene* scene) {
  const GeometryScene& g = scene->geometry;
  bool anyEmits = false;
  for (uint32_t i = 0; i < g.instances.size(); ++i) {
    const Instance& inst = g.instances[i];
    // A shape emits when its (first) material does; CSG trees never become lights anyway.
    const uint32_t m = inst.isShape() ? scene->shapeMaterials[inst.shape].front()
                                      : scene->meshMaterial[inst.mesh];
    bool emits = scene->materials[m]->traits().emits;
    if (inst.isShape())
      for (uint32_t sm : scene->shapeMaterials[inst.shape])
        emits = emits || scene->materials[sm]->traits().emits;
    if (!emits) continue;
    anyEmits = true;
    if (scene->instanceLight.empty()) scene->instanceLight.assign(g.instances.size(), -1);
    // Moving emitters are placed at the middle of the shutter, like every light.
    const Transform world = inst.worldFromObjectAt(0.5f);
    AreaEmission emission;
    emission.material = scene->materials[m].get();
    emission.objectFromWorld = inst.moves() ? world.inverse() : scene->objectFromWorld[i];
    emission.instance = i;
    emission.twoSided = true;  // Material::emitted does not depend on the side
    std::unique_ptr<Light> light =
        inst.isShape() ? (scene->shapeMaterials[inst.shape].size() == 1
                              ? shapeLight(*g.shapes[inst.shape], world, emission)
                              : nullptr)
                       : meshLight(g.meshes[inst.mesh], world, emission);
    if (!light) continue;
    scene->instanceLight[i] = int32_t(scene->lights.size());
    scene->lights.push_back(std::move(light));
  }
  return anyEmits;
}

std::unique_ptr<Light> makeSidecarLight(const LightDesc& l, const Transform& world,
                                        const Texture* slide) {
  AreaEmission emission;
  emission.radiance = l.color * l.intensity;
  emission.twoSided = l.twoSided;
  std::unique_ptr<AreaLight> area;
  switch (l.type) {
    case LightType::Quad:
      area = std::make_unique<QuadLight>(world.point(l.corner), world.vector(l.edgeU),
                                         world.vector(l.edgeV), emission);
      break;
    case LightType::Disk:
      // In the frame's XY plane facing -Z: cross(axisZ, axisX) must be -Z, so the "Z" axis
      // of DiskLight is the frame's +Y.
      area = std::make_unique<DiskLight>(world.point({0, 0, 0}), world.vector({l.radius, 0, 0}),
                                         world.vector({0, l.radius, 0}), emission);
      break;
    case LightType::Sphere: {
      // Under a similarity a sphere light; otherwise (non-uniform scale or shear, from its
      // transform or its node's animation) the ellipsoid it becomes, sampled by area.
      const float scale = uniformScale(world);
      if (scale > 0) {
        area = std::make_unique<SphereLight>(world.point({0, 0, 0}), l.radius * scale, emission);
      } else {
        SurfacePart sphere;
        sphere.kind = SurfacePart::Kind::Sphere;
        sphere.radius = l.radius;
        area = std::make_unique<ShapeSurfaceLight>(std::vector<SurfacePart>{sphere}, world,
                                                   emission);
      }
      break;
    }
    case LightType::Projective:
      return std::make_unique<ProjectiveLight>(world, l.color * l.intensity, l.fov, slide,
                                               l.attenuation, l.castsShadows);
    default:
      return nullptr;
  }
  area->setCastsShadows(l.castsShadows);
  return area;
}

std::unique_ptr<Light> makeEnvironmentLight(const EnvironmentDesc& env) {
  if (env.image.empty()) return std::make_unique<UniformEnvironmentLight>(env.color * env.intensity);
  Film film;
  try {
    film = readExr(env.image);
  } catch (const std::exception& e) {
    throw SceneError(env.where.child("image"), e.what());
  }
  return std::make_unique<ImageEnvironmentLight>(film.width, film.height, std::move(film.color),
                                                 env.intensity, env.rotation);
}

}  // namespace glint
