// glint — surface details of a triangle hit.
#include "geometry/interaction.h"

#include <algorithm>
#include <cmath>

namespace glint {

namespace {

SurfaceInteraction shapeInteraction(const GeometryScene& scene, const Ray& ray, const Hit& hit,
                                    SurfaceNeeds needs, const PlacedShape& placed) {
  const Instance& inst = scene.instances[hit.instance];
  ShapeSurface s = placed.surface(ray, ShapeHit{hit.t, hit.prim},
                                  SurfaceDetails{.uv = needs.uvs, .tangents = needs.tangents});
  SurfaceInteraction si;
  si.p = s.p;
  si.pError = s.pError;
  si.wo = normalize(-ray.d);
  // Shade two-sided, like meshes: the normal faces the side the ray came from.
  Vec3f n = s.n;
  si.frontFace = dot(n, si.wo) >= 0;
  if (!si.frontFace) n = -n;
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

// dp/du and dp/dv of a triangle from its UVs (pbrt-v4's Triangle::InteractionFromIntersection),
// in world space. Without UVs (or with degenerate ones) the barycentric parameterisation is
// used, and a triangle with no area in uv gets any frame around its normal.
void triangleTangents(const TriangleMesh& mesh, const Transform& xf, bool identity, uint32_t i0,
                      uint32_t i1, uint32_t i2, Vec3f p0, Vec3f p1, Vec3f p2,
                      SurfaceInteraction* si) {
  Vec2f uv0{0, 0}, uv1{1, 0}, uv2{0, 1};
  if (!mesh.uvs.empty()) uv0 = mesh.uvs[i0], uv1 = mesh.uvs[i1], uv2 = mesh.uvs[i2];
  const Vec2f duv02 = uv0 - uv2, duv12 = uv1 - uv2;
  const Vec3f dp02 = p0 - p2, dp12 = p1 - p2;
  const float det = duv02.x * duv12.y - duv02.y * duv12.x;
  Vec3f dpdu, dpdv;
  bool ok = std::abs(det) > 1e-12f;
  if (ok) {
    const float inv = 1 / det;
    dpdu = (duv12.y * dp02 - duv02.y * dp12) * inv;
    dpdv = (duv02.x * dp12 - duv12.x * dp02) * inv;
    ok = isFinite(dpdu) && isFinite(dpdv) && lengthSquared(cross(dpdu, dpdv)) > 0;
  }
  if (!ok) {
    const Frame f = Frame::fromZ(si->ng);  // already in world space
    si->dpdu = f.s, si->dpdv = f.t;
  } else {
    si->dpdu = identity ? dpdu : xf.vector(dpdu);
    si->dpdv = identity ? dpdv : xf.vector(dpdv);
  }
}

// TEXCOORD_1 at the hit, and the Jacobian d uv1 / d uv of the triangle (affine in both), so
// that a pixel footprint in uv carries over to uv1.
void secondUvSet(const TriangleMesh& mesh, uint32_t i0, uint32_t i1, uint32_t i2, float b0,
                 float b1, float b2, SurfaceInteraction* si) {
  const Vec2f a0 = mesh.uvs1[i0], a1 = mesh.uvs1[i1], a2 = mesh.uvs1[i2];
  si->uv1 = b0 * a0 + b1 * a1 + b2 * a2;
  Vec2f u0{0, 0}, u1{1, 0}, u2{0, 1};
  if (!mesh.uvs.empty()) u0 = mesh.uvs[i0], u1 = mesh.uvs[i1], u2 = mesh.uvs[i2];
  // [d uv1] = J [d uv] for the edges (1 - 0) and (2 - 0): J = A U^-1.
  const Vec2f du1 = u1 - u0, du2 = u2 - u0, da1 = a1 - a0, da2 = a2 - a0;
  const float det = du1.x * du2.y - du2.x * du1.y;
  if (!(std::abs(det) > 1e-20f)) return;
  const float inv = 1 / det;
  // U^-1 = [du2.y, -du2.x; -du1.y, du1.x] / det; the columns of J are d uv1 / du and / dv.
  const Vec2f dAdu = (da1 * du2.y - da2 * du1.y) * inv;
  const Vec2f dAdv = (da2 * du1.x - da1 * du2.x) * inv;
  if (std::isfinite(dAdu.x) && std::isfinite(dAdu.y) && std::isfinite(dAdv.x) &&
      std::isfinite(dAdv.y))
    si->duv1du = dAdu, si->duv1dv = dAdv;
}

// Embree intersects an instanced mesh by moving the ray into object space itself, in float
// and without error bounds: the origin o of a ray spawned from p becomes W o (W = M^-1, which
// Embree inverts in float too), off by about gamma(k) (|W| |o| + |W_t|) on each object axis;
// M maps that back to world space. Where the cancellation in W o is large (a small triangle
// far from the origin) this dwarfs p's own error, and without it a spawned ray can start
// behind the surface Embree sees. k = 3 for the product plus a margin for the inverse.
//
// A placement that only translates (a glTF node's translation, a scene moved as a whole) is
// exact in Embree's hands: its inverse is the negated translation, the products are by 1 and 0,
// and o - t rounds once, at the magnitude of the small object-space result. The general bound
// there is gamma(8) (|o| + |t|): a unit refraction offset for a glass sphere at 1e6, which
// carried the refracted ray out through the far side.
Vec3f instanceRayTransformError(const Transform& xf, Vec3f p) {
  constexpr int kTransformRoundings = 8;
  const auto& w = xf.inverseMatrix().m;
  const auto& m = xf.matrix().m;
  const bool translates = m[0][0] == 1 && m[1][1] == 1 && m[2][2] == 1 && m[0][1] == 0 &&
                          m[0][2] == 0 && m[1][0] == 0 && m[1][2] == 0 && m[2][0] == 0 &&
                          m[2][1] == 0;
  if (translates) {
    Vec3f e;
    for (int r = 0; r < 3; ++r) e[r] = gamma(2) * std::abs(p[r] - m[r][3]);
    return e;
  }
  float obj[3];
  for (int r = 0; r < 3; ++r)
    obj[r] = gamma(kTransformRoundings) * (std::abs(w[r][0] * p.x) + std::abs(w[r][1] * p.y) +
                                           std::abs(w[r][2] * p.z) + std::abs(w[r][3]));
  Vec3f world;
  for (int r = 0; r < 3; ++r)
    world[r] = std::abs(m[r][0]) * obj[0] + std::abs(m[r][1]) * obj[1] + std::abs(m[r][2]) * obj[2];
  return world * (1 + gamma(4));
}

// A triangle hit on an instance placed by `xf` (its transform at the ray's time when it moves).
// Inlined twice, for static and for moving or deforming meshes, so the static path carries no
// motion code.
[[gnu::always_inline]] inline SurfaceInteraction triangleInteraction(
    const GeometryScene& scene, const Ray& ray, const Hit& hit, SurfaceNeeds needs,
    const Instance& inst, const Transform& xf, bool moves, bool deforms) {
  SurfaceInteraction si;
  const TriangleMesh& mesh = scene.meshes[inst.mesh];
  const uint32_t i0 = mesh.indices[3 * hit.prim], i1 = mesh.indices[3 * hit.prim + 1],
                 i2 = mesh.indices[3 * hit.prim + 2];
  // A deforming mesh's triangle where it was at the ray's time: the blend of two time steps
  // Embree intersected.
  TriangleMesh::StepBlend step{0, 0};
  if (deforms) step = mesh.stepAt(ray.time);
  const Vec3f p0 = deforms ? mesh.positionAt(i0, step) : mesh.positions[i0];
  const Vec3f p1 = deforms ? mesh.positionAt(i1, step) : mesh.positions[i1];
  const Vec3f p2 = deforms ? mesh.positionAt(i2, step) : mesh.positions[i2];
  const float b1 = hit.u, b2 = hit.v, b0 = 1 - b1 - b2;

  const bool identity = xf.isIdentity();
  if (needs.position) {
    // Object-space point from barycentrics; error bound as in pbrt-v4
    // (Triangle::InteractionFromIntersection).
    Vec3f pObj = b0 * p0 + b1 * p1 + b2 * p2;
    Vec3f errObj = gamma(7) * (abs(b0 * p0) + abs(b1 * p1) + abs(b2 * p2));
    if (deforms) {
      // The blend of the steps is rounded (by Embree too, perhaps fused): a few roundings of
      // the two steps' magnitudes per vertex.
      auto blendError = [&](uint32_t v) {
        return gamma(3) *
               (abs(mesh.positionSteps[step.k][v]) + abs(mesh.positionSteps[step.k + 1][v]));
      };
      errObj += std::abs(b0) * blendError(i0) + std::abs(b1) * blendError(i1) +
                std::abs(b2) * blendError(i2);
    }
    if (identity) {
      si.p = pObj;
      si.pError = errObj;
    } else {
      si.p = xf.point(pObj, errObj, &si.pError);
      si.pError += instanceRayTransformError(xf, si.p);
    }
    if (moves) {
      // Embree evaluated the transform at this time itself; its float slerp and matrix build
      // agree with ours only to a few 1e-6 of the matrix's scale (more between nearly
      // parallel rotations), far above one rounding: without this margin a ray spawned from
      // the point could start behind the surface Embree intersects.
      const float mismatch = inst.motion.interpolationMismatch(ray.time);
      const auto& m = xf.matrix().m;
      float entry = 0;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) entry = std::max(entry, std::abs(m[r][c]));
      const float reach = entry * (std::abs(pObj.x) + std::abs(pObj.y) + std::abs(pObj.z) + 1);
      for (int r = 0; r < 3; ++r) si.pError[r] += mismatch * (reach + std::abs(m[r][3]));
    }
  }

  Vec3f nObj = cross(p1 - p0, p2 - p0);
  Vec3f ng = identity ? nObj : xf.normal(nObj);
  float len = length(ng);
  // Degenerate triangles are never hit by Embree, but guard anyway: fall back to -d.
  ng = len > 0 ? ng / len : normalize(-ray.d);

  Vec3f ns = ng;
  if (!mesh.normals.empty()) {
    Vec3f n = deforms && !mesh.normalSteps.empty()
                  ? b0 * mesh.normalAt(i0, step) + b1 * mesh.normalAt(i1, step) +
                        b2 * mesh.normalAt(i2, step)
                  : b0 * mesh.normals[i0] + b1 * mesh.normals[i1] + b2 * mesh.normals[i2];
    if (!identity) n = xf.normal(n);
    float l = length(n);
    if (l > 0) ns = n / l;
  }

  si.wo = normalize(-ray.d);
  // Shade two-sided: put ng on the side the ray came from and ns in ng's hemisphere.
  si.frontFace = dot(ng, si.wo) >= 0;
  if (!si.frontFace) ng = -ng;
  if (dot(ns, ng) < 0) ns = -ns;
  si.ng = ng;
  si.ns = ns;

  if (needs.uvs) {
    if (!mesh.uvs.empty())
      si.uv = b0 * mesh.uvs[i0] + b1 * mesh.uvs[i1] + b2 * mesh.uvs[i2];
    else
      si.uv = {b1, b2};
    si.uv1 = si.uv;
    if (!mesh.uvs1.empty()) secondUvSet(mesh, i0, i1, i2, b0, b1, b2, &si);
  }
  if (needs.tangents) {
    triangleTangents(mesh, xf, identity, i0, i1, i2, p0, p1, p2, &si);
    if (!mesh.tangents.empty()) {
      const Vec4f t0 = mesh.tangents[i0], t1 = mesh.tangents[i1], t2 = mesh.tangents[i2];
      Vec3f t = b0 * Vec3f{t0.x, t0.y, t0.z} + b1 * Vec3f{t1.x, t1.y, t1.z} +
                b2 * Vec3f{t2.x, t2.y, t2.z};
      if (!identity) t = xf.vector(t);
      const float tLen = length(t);
      if (tLen > 0) {
        si.tangent = t / tLen;
        // A mirroring placement turns cross(n, t) against the bitangent: the sign flips.
        si.bitangentSign = (t0.w < 0) != (!identity && xf.swapsHandedness()) ? -1.0f : 1.0f;
      }
    }
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

// A moving mesh is mapped by its transform at the ray's time, interpolated as Embree
// interpolated it, and a deforming one's vertices are blended at that time, so the point and
// normal are those of the surface it intersected.
[[gnu::noinline]] SurfaceInteraction movingTriangleInteraction(const GeometryScene& scene,
                                                               const Ray& ray, const Hit& hit,
                                                               SurfaceNeeds needs,
                                                               const Instance& inst) {
  return triangleInteraction(scene, ray, hit, needs, inst, inst.worldFromObjectAt(ray.time),
                             inst.moves(), scene.meshes[inst.mesh].deforms());
}

}  // namespace

SurfaceInteraction computeSurfaceInteraction(const GeometryScene& scene, const Ray& ray,
                                             const Hit& hit, SurfaceNeeds needs,
                                             const PlacedShape* placed) {
  const Instance& inst = scene.instances[hit.instance];
  if (inst.isShape()) {
    if (placed) return shapeInteraction(scene, ray, hit, needs, *placed);
    // A moving shape where it was at the ray's time: the placement traversal intersected.
    return shapeInteraction(scene, ray, hit, needs, scene.placedShape(hit.instance, ray.time));
  }
  if (inst.moves() || scene.meshes[inst.mesh].deforms())
    return movingTriangleInteraction(scene, ray, hit, needs, inst);
  return triangleInteraction(scene, ray, hit, needs, inst, inst.worldFromObject, false, false);
}

}  // namespace glint
