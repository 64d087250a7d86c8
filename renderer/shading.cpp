// glint — a hit made ready to shade (renderer/shading.h).
#include "renderer/shading.h"

#include <algorithm>

#include "materials/bump.h"

namespace glint {

void setPixelFootprint(SurfaceInteraction& si, Vec3f d, float width) {
  const float cosD = dot(d, si.ng);
  // Grazing hits stretch the footprint without bound; cap the stretch at 1/0.05 (20x).
  const float safeCos = std::copysign(std::max(std::abs(cosD), 0.05f), cosD == 0 ? 1 : cosD);
  const Frame cone = Frame::fromZ(normalize(d));
  auto onPlane = [&](Vec3f v) { return v - d * (dot(v, si.ng) / safeCos); };
  si.dpdx = onPlane(cone.s * (0.5f * width));
  si.dpdy = onPlane(cone.t * (0.5f * width));
  const float a00 = dot(si.dpdu, si.dpdu), a01 = dot(si.dpdu, si.dpdv), a11 = dot(si.dpdv, si.dpdv);
  const float det = a00 * a11 - a01 * a01;
  if (!(det > 0) || !std::isfinite(det)) {
    si.duvdx = si.duvdy = si.duv1dx = si.duv1dy = {};
    return;
  }
  auto solve = [&](Vec3f dp) {
    const float b0 = dot(si.dpdu, dp), b1 = dot(si.dpdv, dp);
    Vec2f r{(a11 * b0 - a01 * b1) / det, (a00 * b1 - a01 * b0) / det};
    // Clamp absurd values (degenerate parameterisations) rather than let them through.
    r.x = std::isfinite(r.x) ? std::clamp(r.x, -1e8f, 1e8f) : 0;
    r.y = std::isfinite(r.y) ? std::clamp(r.y, -1e8f, 1e8f) : 0;
    return r;
  };
  si.duvdx = solve(si.dpdx);
  si.duvdy = solve(si.dpdy);
  si.duv1dx = si.duv1du * si.duvdx.x + si.duv1dv * si.duvdx.y;
  si.duv1dy = si.duv1du * si.duvdy.x + si.duv1dv * si.duvdy.y;
}

std::vector<MaterialShading> materialShadings(const RenderScene& scene) {
  const SceneFeatures& f = scene.features();
  std::vector<MaterialShading> shadings(scene.materials().size());
  for (size_t m = 0; m < shadings.size(); ++m) {
    const Material& mat = *scene.materials()[m];
    const MaterialTraits& t = mat.traits();
    MaterialShading& s = shadings[m];
    s.flags = mat.flags();
    s.unlit = (s.flags & kBsdfUnlit) != 0;
    s.transparent = t.transparency;
    s.emits = t.emits;
    s.absorbs = maxComponent(mat.absorption()) > 0;
    s.objectSpace = t.needs.objectSpace;
    s.footprint = t.needs.footprint || t.bump;
    s.needs.uvs = t.needs.uvs;
    s.needs.colors = t.vertexColors && f.has(Feature::VertexColors);
    s.needs.tangents = t.needs.tangents || s.footprint;
    // Unlit (eyelight) shading reads only normals and wo, unless the ray goes on through it.
    s.needs.position =
        !s.unlit || s.transparent || s.objectSpace || s.footprint || (s.flags & kBsdfSpecular);
  }
  return shadings;
}

ShadedHit::ShadedHit(const RenderScene& scene, const std::vector<MaterialShading>& shadings,
                     uint32_t materialIndex, const Ray& ray, const Hit& hit, RayCone cone)
    : material(*scene.materials()[materialIndex]),
      shading(shadings[materialIndex]),
      si(computeSurfaceInteraction(scene.geometry(), ray, hit, shading.needs,
                                   scene.placedShape(hit.instance))),
      lookups(si),
      distance(hit.t * length(ray.d)) {
  if (shading.objectSpace) {
    // A moving object's texture moves with it: its frame at the ray's time.
    const Instance& inst = scene.geometry().instances[hit.instance];
    if (inst.moves())
      si.objectFromWorld = frame_.set(inst.worldFromObjectAt(ray.time).inverse());
    else
      si.objectFromWorld = &scene.objectFromWorld(hit.instance);
  }
  if (shading.footprint) setPixelFootprint(si, ray.d / length(ray.d), cone.widthAt(distance));
  material.perturbNormal(si);
  // Every shading normal, interpolated or perturbed, reflects wo above the surface (bump.h).
  si.ns = reflectionSafeNormal(si.ns, si.ng, si.wo);
}

}  // namespace glint
