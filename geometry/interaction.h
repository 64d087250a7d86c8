// glint — SurfaceInteraction: everything about a ray's final hit that shading needs.
#pragma once

#include "geometry/accel/accelerator.h"
#include "geometry/mesh.h"
#include "geometry/ray.h"

namespace glint {

// Which optional attributes to interpolate; a scene without textures or vertex colours does
// not pay for them (see SceneFeatures).
struct SurfaceNeeds {
  bool uvs = true;
  bool colors = true;
  // p and pError, for spawning rays. Unlit (eyelight) shading reads only normals and wo, so
  // it skips the hit point and its error bound.
  bool position = true;
  // dp/du and dp/dv (triangles: from their UVs; analytic shapes: from their own uv), for bump
  // and normal maps and texture footprints.
  bool tangents = false;
};

struct SurfaceInteraction {
  Vec3f p;              // world-space hit point,
  Vec3f pError;         // with a conservative bound on its absolute rounding error (both zero
                        // unless SurfaceNeeds::position)
  Vec3f ng;             // unit geometric normal (world), on the side the ray came from
  Vec3f ns;             // unit shading normal (world), in ng's hemisphere
  Vec3f nsUnperturbed;  // ns before a bump or normal map changed it (set only then)
  Vec3f wo;             // unit direction back along the ray
  Vec2f uv;             // TEXCOORD_0 (or barycentrics when the mesh has none); a shape's own
                        // uv (only with SurfaceNeeds::uvs; zero otherwise)
  Vec2f uv1;            // TEXCOORD_1 (uv when the mesh has no second set)
  // How uv1 changes with uv across the triangle (columns d uv1 / du, d uv1 / dv): carries uv's
  // pixel footprint over to uv1 (identity without a second set).
  Vec2f duv1du{1, 0}, duv1dv{0, 1};
  Vec3f dpdu, dpdv;         // world-space partial derivatives of p by uv (only with
                            // SurfaceNeeds::tangents; zero otherwise)
  Vec4f color{1, 1, 1, 1};  // COLOR_0, white when absent
  // The mesh's TANGENT (world, unit) and the bitangent's handedness, when it has one (only
  // with SurfaceNeeds::tangents; zero otherwise): normal maps prefer it to dp/du.
  Vec3f tangent;
  float bitangentSign = 1;
  // True when the ray arrived on the side the surface's outward normal points to (a mesh's
  // counter-clockwise front, a solid's outside): refraction enters the object there.
  bool frontFace = true;
  // Footprint of one pixel at the hit, for texture filtering: how p and uv change from one
  // pixel to the next (zero unless the renderer computes them: RayCone, setPixelFootprint).
  Vec3f dpdx, dpdy;
  Vec2f duvdx, duvdy;
  Vec2f duv1dx, duv1dy;  // the same for uv1
  // The object's own frame, for object-space textures (null: the world frame). Set by the
  // renderer, which knows the placement each object was authored in; for a moving instance it
  // is the inverse of worldFromObjectAt(ray time), held by the caller, so the texture moves
  // with the object.
  const Transform* objectFromWorld = nullptr;
  float t = 0;
  uint32_t instance = 0, prim = 0;
  uint32_t mesh = Instance::kNone;  // the instance's mesh, or kNone for an analytic shape
  uint32_t materialSlot = 0;        // which of the instance's materials (CSG: the leaf)

  // A ray leaving this point in direction d (origin offset past the point's error bound).
  Ray spawnRay(Vec3f d, float time) const { return glint::spawnRay(p, pError, ng, d, time); }
  // A shadow ray towards a point: t in [0, 1) covers the segment.
  Ray spawnRayTo(Vec3f target, float time) const {
    return glint::spawnRayTo(p, pError, ng, target, time);
  }
};

// Computes the surface details of `hit` (found for `ray` in `scene`). Triangles: the hit point
// is re-evaluated from the vertices and barycentrics, which is far more accurate than o + t d,
// with its error bound propagated through the instance transform. Analytic shapes: their own
// surface() (re-projected point, error bound, normal, uv, dp/du, dp/dv) in world space. A moving
// instance is placed by its transform at ray.time (Instance::worldFromObjectAt). `placed`, when
// given, is the hit shape instance's static placement made beforehand (RenderScene::placedShape),
// which saves making it again for this hit.
SurfaceInteraction computeSurfaceInteraction(const GeometryScene& scene, const Ray& ray,
                                             const Hit& hit, SurfaceNeeds needs = {},
                                             const PlacedShape* placed = nullptr);

}  // namespace glint
