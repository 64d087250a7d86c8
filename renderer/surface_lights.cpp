// glint — emitting surfaces as lights.
#include "renderer/surface_lights.h"

#include "renderer/area_lights.h"
#include "renderer/scene.h"

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

SurfaceLights makeSurfaceLights(const SceneParts& parts, uint32_t firstIndex) {
  const GeometryScene& g = parts.geometry;
  SurfaceLights out;
  for (uint32_t i = 0; i < g.instances.size(); ++i) {
    const Instance& inst = g.instances[i];
    // A shape emits when any of its materials does (CSG trees have one per leaf).
    const uint32_t m =
        inst.isShape() ? parts.shapeMaterials[inst.shape].front() : parts.meshMaterial[inst.mesh];
    bool emits = parts.materials[m]->traits().emits;
    if (inst.isShape())
      for (uint32_t sm : parts.shapeMaterials[inst.shape])
        emits = emits || parts.materials[sm]->traits().emits;
    if (!emits) continue;
    if (out.ofInstance.empty()) out.ofInstance.assign(g.instances.size(), -1);
    if (inst.isShape() && !(g.shapes[inst.shape]->area() > 0)) {
      const Shape& shape = *g.shapes[inst.shape];
      out.unsampled.push_back({i, shape.typeName(), unsampledReason(shape)});
      continue;
    }
    // Moving emitters are placed at the middle of the shutter, like every light.
    const Transform world = inst.worldFromObjectAt(0.5f);
    AreaEmission emission;
    emission.material = parts.materials[m].get();
    emission.objectFromWorld = inst.moves() ? world.inverse() : parts.objectFromWorld[i];
    emission.instance = i;
    // Material::emitted does not depend on the side; a single-sided mesh is seen, and so
    // emits, from the front only.
    emission.twoSided = inst.isShape() || !g.meshes[inst.mesh].singleSided;
    out.ofInstance[i] = int32_t(firstIndex + out.lights.size());
    if (inst.isShape())
      out.lights.push_back(
          std::make_unique<AreaLight>(PlacedShape(g.shapes[inst.shape].get(), world), emission));
    else
      out.lights.push_back(meshLight(g.meshes[inst.mesh], world, emission));
  }
  return out;
}

}  // namespace glint
