// glint — what every integrator shares, and the integrator factory.
#include "renderer/integrator.h"

#include "geometry/error.h"
#include "materials/bump.h"
#include "renderer/instant_radiosity.h"
#include "renderer/path.h"
#include "renderer/whitted.h"

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

Integrator::Integrator(const RenderScene& scene) : scene_(scene) {
  // One shading record per material: what its hits need, decided here and not per hit.
  const SceneFeatures& f = scene.features;
  shading_.resize(scene.materials.size());
  for (size_t m = 0; m < shading_.size(); ++m) {
    const Material& mat = *scene.materials[m];
    const MaterialTraits& t = mat.traits();
    MaterialShading& s = shading_[m];
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
}

SurfaceInteraction Integrator::shadingPoint(const Ray& ray, const Hit& hit, const RayCone& cone,
                                            uint32_t materialIndex,
                                            MovingFrame* movingFrame) const {
  const MaterialShading& s = shading_[materialIndex];
  SurfaceInteraction si = computeSurfaceInteraction(scene_.geometry, ray, hit, s.needs,
                                                    scene_.placedShape(hit.instance));
  if (s.objectSpace) {
    // A moving object's texture moves with it: its frame at the ray's time.
    const Instance& inst = scene_.geometry.instances[hit.instance];
    if (inst.moves())
      si.objectFromWorld = movingFrame->set(inst.worldFromObjectAt(ray.time).inverse());
    else
      si.objectFromWorld = &scene_.objectFromWorld[hit.instance];
  }
  if (s.footprint) {
    const float len = length(ray.d);
    setPixelFootprint(si, ray.d / len, cone.widthAt(hit.t * len));
  }
  scene_.materials[materialIndex]->perturbNormal(si);
  // Every shading normal, interpolated or perturbed, reflects wo above the surface (bump.h).
  si.ns = reflectionSafeNormal(si.ns, si.ng, si.wo);
  return si;
}

Rgb Integrator::Li(const Ray& ray, Sampler& sampler, RayCounters& counters, PathAovs& aovs) const {
  ++counters.camera;
  Hit hit;
  bool found = scene_.accel->closestHit(ray, &hit);
  return LiFromHit(ray, found ? &hit : nullptr, sampler, counters, aovs);
}

const std::vector<std::string>& integratorNames() {
  static const std::vector<std::string> names = {"whitted", "path", "instant-radiosity", "auto"};
  return names;
}

IntegratorKind resolveIntegrator(const RenderScene& scene, const IntegratorSettings& settings) {
  if (settings.type == "whitted") return IntegratorKind::Whitted;
  if (settings.type == "path") return IntegratorKind::Path;
  if (settings.type == "instant-radiosity") return IntegratorKind::InstantRadiosity;
  if (settings.type != "auto")
    throw InputError("unknown integrator '" + settings.type +
                     "' (whitted, path, instant-radiosity, auto)");
  // Media asking for multiple scattering need the path tracer (Whitted scatters once); other
  // media go by the light rule below (Whitted's marched single scattering is the low-noise
  // answer for point lights).
  if (scene.media && settings.volume == "multiple") return IntegratorKind::Path;
  // Light with an extent (area, emitting surfaces, the environment) is what Whitted's hard
  // shadows cannot render; point, spot and directional lights it renders exactly.
  bool extended = !scene.infiniteLights.empty();
  for (int32_t l : scene.instanceLight) extended = extended || l >= 0;
  for (const auto& light : scene.lights) extended = extended || !light->isDelta();
  // A rough metal reflects the rest of the scene through a glossy lobe, which Whitted renders
  // only as highlights of point lights: it looks black elsewhere.
  for (const auto& material : scene.materials)
    extended = extended || material->traits().glossyMetal;
  return extended ? IntegratorKind::Path : IntegratorKind::Whitted;
}

const char* integratorName(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::Whitted:
      return "whitted";
    case IntegratorKind::Path:
      return "path";
    case IntegratorKind::InstantRadiosity:
      return "instant-radiosity";
  }
  return "?";
}

std::unique_ptr<Integrator> makeIntegrator(const RenderScene& scene,
                                           const RenderSettings& settings) {
  const IntegratorSettings& s = settings.integrator;
  switch (resolveIntegrator(scene, s)) {
    case IntegratorKind::Whitted:
      return std::make_unique<WhittedIntegrator>(scene, s.maxDepth, s.glassShadows, s.minWeight);
    case IntegratorKind::Path:
      return std::make_unique<PathIntegrator>(scene, s);
    case IntegratorKind::InstantRadiosity:
      return std::make_unique<InstantRadiosityIntegrator>(scene, s, settings.seed);
  }
  return nullptr;
}

}  // namespace glint
