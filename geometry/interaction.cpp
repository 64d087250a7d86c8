// glint — surface details of a triangle hit.
#include "geometry/interaction.h"

namespace glint {

namespace {

SurfaceInteraction shapeInteraction(const GeometryScene& scene, const Ray& ray, const Hit& hit) {
  const Instance& inst = scene.instances[hit.instance];
  PlacedShape placed = scene.placedShape(hit.instance);
  ShapeSurface s = placed.surface(ray, ShapeHit{hit.t, hit.prim});
  SurfaceInteraction si;
  si.p = s.p;
  si.pError = s.pError;
  si.wo = normalize(-ray.d);
  // Shade two-sided, like meshes: the normal faces the side the ray came from.
  Vec3f n = s.n;
  if (dot(n, si.wo) < 0) n = -n;
  si.ng = si.ns = n;
  si.uv = s.uv;
  si.dpdu = s.dpdu;
  si.dpdv = s.dpdv;
  si.t = hit.t;
  si.instance = hit.instance;
  si.prim = hit.prim;
  si.materialSlot = scene.shapes[inst.shape]->materialSlot(hit.prim);
  return si;
}

}  // namespace

SurfaceInteraction computeSurfaceInteraction(const GeometryScene& scene, const Ray& ray,
                                             const Hit& hit, SurfaceNeeds needs) {
  SurfaceInteraction si;
  const Instance& inst = scene.instances[hit.instance];
  if (inst.isShape()) return shapeInteraction(scene, ray, hit);
  const TriangleMesh& mesh = scene.meshes[inst.mesh];
  const uint32_t i0 = mesh.indices[3 * hit.prim], i1 = mesh.indices[3 * hit.prim + 1],
                 i2 = mesh.indices[3 * hit.prim + 2];
  const Vec3f p0 = mesh.positions[i0], p1 = mesh.positions[i1], p2 = mesh.positions[i2];
  const float b1 = hit.u, b2 = hit.v, b0 = 1 - b1 - b2;

  const Transform& xf = inst.worldFromObject;
  const bool identity = xf.isIdentity();
  if (needs.position) {
    // Object-space point from barycentrics; error bound as in pbrt-v4
    // (Triangle::InteractionFromIntersection).
    Vec3f pObj = b0 * p0 + b1 * p1 + b2 * p2;
    Vec3f errObj = gamma(7) * (abs(b0 * p0) + abs(b1 * p1) + abs(b2 * p2));
    if (identity) {
      si.p = pObj;
      si.pError = errObj;
    } else {
      si.p = xf.point(pObj, errObj, &si.pError);
    }
  }

  Vec3f nObj = cross(p1 - p0, p2 - p0);
  Vec3f ng = identity ? nObj : xf.normal(nObj);
  float len = length(ng);
  // Degenerate triangles are never hit by Embree, but guard anyway: fall back to -d.
  ng = len > 0 ? ng / len : normalize(-ray.d);

  Vec3f ns = ng;
  if (!mesh.normals.empty()) {
    Vec3f n = b0 * mesh.normals[i0] + b1 * mesh.normals[i1] + b2 * mesh.normals[i2];
    if (!identity) n = xf.normal(n);
    float l = length(n);
    if (l > 0) ns = n / l;
  }

  si.wo = normalize(-ray.d);
  // Shade two-sided: put ng on the side the ray came from and ns in ng's hemisphere.
  if (dot(ng, si.wo) < 0) ng = -ng;
  if (dot(ns, ng) < 0) ns = -ns;
  si.ng = ng;
  si.ns = ns;

  if (needs.uvs) {
    if (!mesh.uvs.empty())
      si.uv = b0 * mesh.uvs[i0] + b1 * mesh.uvs[i1] + b2 * mesh.uvs[i2];
    else
      si.uv = {b1, b2};
  }
  if (needs.colors && !mesh.colors.empty()) {
    const Vec4f c0 = mesh.colors[i0], c1 = mesh.colors[i1], c2 = mesh.colors[i2];
    si.color = {b0 * c0.x + b1 * c1.x + b2 * c2.x, b0 * c0.y + b1 * c1.y + b2 * c2.y,
                b0 * c0.z + b1 * c1.z + b2 * c2.z, b0 * c0.w + b1 * c1.w + b2 * c2.w};
  }
  si.t = hit.t;
  si.instance = hit.instance;
  si.mesh = inst.mesh;
  si.prim = hit.prim;
  return si;
}

}  // namespace glint
