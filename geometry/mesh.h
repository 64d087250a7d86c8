// glint — triangle meshes and their placements: the geometry every accelerator is built from.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/math.h"
#include "geometry/motion.h"
#include "geometry/shape.h"

namespace glint {

// An indexed triangle mesh in object space. Per-vertex attributes are empty or have one entry
// per position. Embree's convention for barycentrics: p = (1-u-v) p0 + u p1 + v p2.
struct TriangleMesh {
  std::vector<Vec3f> positions;
  std::vector<Vec3f> normals;
  std::vector<Vec4f> tangents;  // xyz: unit tangent, w: bitangent handedness (+-1)
  std::vector<Vec2f> uvs;
  std::vector<Vec2f> uvs1;  // a second texture coordinate set (glTF TEXCOORD_1)
  std::vector<Vec4f> colors;
  std::vector<uint32_t> indices;  // 3 per triangle
  // Back faces are invisible (glTF doubleSided false): a ray that reaches a triangle from
  // behind passes through it, for every kind of query (camera, bounce, shadow). The front is
  // the side of the object-space winding's normal (p1 - p0) x (p2 - p0), carried into the
  // world as a normal (inverse transpose): a mirroring placement keeps the outside outside,
  // as glTF says ("the determinant of the node's global transform defines the winding
  // order"). Every accelerator honours it identically.
  bool singleSided = false;

  // Deformation blur (a skinned or morphed mesh whose pose changes inside the shutter): the
  // positions, and the normals when there are any, at K >= 2 evenly spaced normalised shutter
  // times 0, 1/(K-1), ..., 1, as Embree's time steps are. Between two steps every vertex moves
  // on a straight line (Embree's interpolation, which every backend and the surface
  // interaction reproduce through at()). Empty for a mesh that keeps its shape, which is then
  // built and traced exactly as without motion. When set, K is odd and `positions`/`normals`
  // are the middle step: what ignores time (emission sampling, light bounds) sees the pose at
  // the shutter's middle. Tangents, uvs and colours do not change with time.
  std::vector<std::vector<Vec3f>> positionSteps;
  std::vector<std::vector<Vec3f>> normalSteps;  // empty, or one per position step

  size_t triangleCount() const { return indices.size() / 3; }
  bool deforms() const { return !positionSteps.empty(); }
  // Where normalised shutter time `time` falls between the steps (timeStepBlend).
  struct StepBlend {
    uint32_t k;
    float f;
  };
  StepBlend stepAt(float time) const;
  // Vertex v's position (normal) at the blend: (1 - f) a + f b of the two steps.
  Vec3f positionAt(uint32_t v, StepBlend s) const {
    const Vec3f a = positionSteps[s.k][v], b = positionSteps[s.k + 1][v];
    return (1 - s.f) * a + s.f * b;
  }
  Vec3f normalAt(uint32_t v, StepBlend s) const {
    const Vec3f a = normalSteps[s.k][v], b = normalSteps[s.k + 1][v];
    return (1 - s.f) * a + s.f * b;
  }
  // The bounds of every step (a linear blend of two steps stays inside their union).
  Bounds3f bounds() const;
};

// Where normalised shutter time `time` falls among `stepCount` >= 2 uniform time steps: step
// k and k + 1, with weight f on k + 1 (Embree's mapping: time (K - 1), floored and clamped to
// a segment, so time 1 is the end of the last segment).
TriangleMesh::StepBlend timeStepBlend(float time, size_t stepCount);

// Bakes a placement into a triangle list: positions go to the world, and when the placement
// mirrors, each triangle's winding is reversed (its last two indices swapped) so that the
// world-space winding keeps facing the front (see TriangleMesh::singleSided). Normals and
// tangents are the caller's.
void placeVertices(const Transform& world, std::vector<Vec3f>* positions,
                   std::vector<uint32_t>* indices);

// The handedness w of glTF's tangent space where a triangle's uv layout gives dp/du and dp/dv
// around the unit normal n: the bitangent cross(n, t) w points to decreasing v, the image's
// up, where a normal map's green channel points (glTF's uv origin is the image's top left).
// +1 for a layout as drawn, -1 for a mirrored one.
inline float uvHandedness(Vec3f n, Vec3f dpdu, Vec3f dpdv) {
  return dot(cross(n, dpdu), dpdv) > 0 ? -1.0f : 1.0f;
}

// Per-vertex tangents (xyz unit, w the handedness) of a mesh whose file gives none, from its
// positions, unit normals and the uv set its normal map reads, as glTF asks ("client
// implementations SHOULD calculate tangents using default MikkTSpace algorithms"): each
// triangle's dp/du, projected into the vertex's tangent plane, weighted by the triangle's
// angle at the vertex, summed per vertex and handedness; a vertex takes the handedness that
// carries more weight (files split their vertices at uv seams, mirror seams included, so the
// two rarely meet). The tangent frame then turns smoothly over a smooth mesh as MikkTSpace's
// does, where one frame per triangle would crease the shading at every edge. A vertex no
// triangle gives a direction (degenerate uvs) gets any tangent perpendicular to its normal.
std::vector<Vec4f> vertexTangents(const std::vector<Vec3f>& positions,
                                  const std::vector<Vec3f>& normals, const std::vector<Vec2f>& uvs,
                                  const std::vector<uint32_t>& indices);

// One placement of a mesh or of an analytic shape (exactly one of the two indices is set).
// Meshes placed several times are built once and instanced.
struct Instance {
  static constexpr uint32_t kNone = ~0u;
  uint32_t mesh = kNone;  // index into GeometryScene::meshes
  Transform worldFromObject;
  uint32_t shape = kNone;  // index into GeometryScene::shapes
  // The placement over the shutter when it moves (then worldFromObject == motion.key(0));
  // static (one key) otherwise, and then nothing is built with time steps.
  AnimatedTransform motion;

  bool isShape() const { return shape != kNone; }
  bool moves() const { return motion.isAnimated(); }
  // The placement at normalised shutter time `time`: the transform the accelerators intersected
  // at that time (the same interpolation as Embree's), worldFromObject when static.
  Transform worldFromObjectAt(float time) const {
    return motion.isAnimated() ? motion.at(time) : worldFromObject;
  }
};

// Everything an accelerator needs: meshes, analytic shapes (primitives and CSG trees, each in
// its own object space) and their placements. Materials live elsewhere and are looked up by
// (instance, material slot): geometry knows nothing of shading.
struct GeometryScene {
  std::vector<TriangleMesh> meshes;
  std::vector<std::unique_ptr<Shape>> shapes;
  std::vector<Instance> instances;

  // The analytic shape of instance `i` (which must be a shape instance), placed in the world
  // (at shutter open when it moves).
  PlacedShape placedShape(uint32_t i) const {
    return PlacedShape(shapes[instances[i].shape].get(), instances[i].worldFromObject);
  }
  // The same, placed where it is at normalised shutter time `time`.
  PlacedShape placedShape(uint32_t i, float time) const {
    return PlacedShape(shapes[instances[i].shape].get(), instances[i].worldFromObjectAt(time));
  }
  // World bounds of the bounded geometry, moving instances swept over the shutter (unbounded
  // shapes such as infinite planes are left out: they have no finite box).
  Bounds3f bounds() const;
  bool hasMotion() const;                 // any instance moves or any mesh deforms
  size_t uniqueTriangleCount() const;     // triangles stored
  size_t instancedTriangleCount() const;  // triangles in the world (instances counted)
  size_t shapeInstanceCount() const;      // analytic objects in the world
};

}  // namespace glint
