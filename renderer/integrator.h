// glint — integrators: radiance along a camera ray.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "renderer/ray_counters.h"
#include "renderer/sampler.h"
#include "renderer/scene.h"
#include "renderer/settings.h"

namespace glint {

// First-hit attributes: `hit` always (for alpha); the rest only when `wanted` (AOV output).
struct PathAovs {
  bool wanted = false;
  Rgb albedo;
  Vec3f normal;
  float depth = 0;
  bool hit = false;

  // Records the first hit (material `m` at `si`, its textures read through `lookups`,
  // `distance` along the camera ray): `hit` always, the attributes only when wanted.
  void record(const Material& m, const SurfaceInteraction& si, TextureLookups& lookups,
              float distance) {
    hit = true;
    if (!wanted) return;
    albedo = m.albedo(si, lookups);
    normal = si.ns;
    depth = distance;
  }
};

// What shading a material's hits needs, decided once per material (not per hit).
struct MaterialShading {
  SurfaceNeeds needs;
  bool objectSpace = false;  // object-space textures or snow: set objectFromWorld
  bool footprint = false;    // filtered textures or bump steps: set the pixel footprint
  bool unlit = false;
  bool transparent = false;  // may let light pass straight through (opacity < 1)
  bool emits = false;        // Material::emitted can be non-zero
  // Its inside absorbs (Material::absorption): a ray reaching its back face has crossed the
  // inside and is attenuated by the distance (closed surfaces; see insideTransmittance).
  bool absorbs = false;
  uint32_t flags = 0;
};

// The fraction of light that crosses `distance` inside `material` to reach the back face at
// si: exp(-absorption * distance) there, 1 at front faces or for clear materials. Integrators
// apply it to every segment that ends on a back face, which needs no record of which objects a
// path is inside; the price is that nested or open volumes are not modelled.
inline Rgb insideTransmittance(const Material& material, const MaterialShading& shading,
                               const SurfaceInteraction& si, float distance) {
  if (!shading.absorbs || si.frontFace) return {1, 1, 1};
  const Rgb sigma = material.absorption();
  return {std::exp(-sigma.x * distance), std::exp(-sigma.y * distance),
          std::exp(-sigma.z * distance)};
}

// Sets si.dpdx/dpdy and si.duvdx/duvdy for a ray of unit direction `d` whose pixel cone is
// `width` wide at the hit: two perpendicular cone radii projected onto the surface's tangent
// plane along d, then expressed in uv by least squares on dp/du and dp/dv (pbrt-v4's
// SurfaceInteraction::ComputeDifferentials).
void setPixelFootprint(SurfaceInteraction& si, Vec3f d, float width);

// Room for a moving object's frame at one ray's time, which a SurfaceInteraction may point to
// (si.objectFromWorld); constructed only when a hit needs it. A std::optional<Transform> in its
// place was zero-filled (128 bytes, `rep stos`) on every hit: a fifth of Whitted's own time per
// hit in features_bench's profile.
class MovingFrame {
 public:
  MovingFrame() {}
  MovingFrame(const MovingFrame&) = delete;
  MovingFrame& operator=(const MovingFrame&) = delete;
  const Transform* set(const Transform& t) {
    static_assert(std::is_trivially_destructible_v<Transform>);
    return new (&frame_) Transform(t);
  }

 private:
  union {
    Transform frame_;
  };
};

class Integrator {
 public:
  explicit Integrator(const RenderScene& scene);
  virtual ~Integrator() = default;
  const RenderScene& scene() const { return scene_; }

  // Radiance arriving at the camera along `ray`, whose closest hit the caller already found
  // (`hit` is null when the ray escapes): the render loop traces a pixel's camera rays
  // together and hands each result here. Draws random numbers from `sampler` in a fixed order;
  // counts the further rays it traces (not the camera ray); fills `aovs` from the first hit.
  virtual Rgb LiFromHit(const Ray& ray, const Hit* hit, Sampler& sampler, RayCounters& counters,
                        PathAovs& aovs) const = 0;

  // The same for a camera ray not yet traced: traces it, counts it, then LiFromHit.
  Rgb Li(const Ray& ray, Sampler& sampler, RayCounters& counters, PathAovs& aovs) const;

  // What the integrator prepared before rendering, for the statistics, as (name, value)
  // pairs: instant radiosity's VPLs and clamp; nothing for the others.
  struct SetupStat {
    std::string name;
    double value;
  };
  virtual std::vector<SetupStat> setupStats() const { return {}; }

 protected:
  // The surface details of `hit` for shading with material `materialIndex`: only the
  // attributes that material needs, its object frame and pixel footprint when it reads them,
  // and its shading normal perturbed (bump, normal map, snow). A moving object's frame at the
  // ray's time goes into `movingFrame`, which the caller keeps alive while it uses the result
  // (SurfaceInteraction points to it; holding it inline would enlarge every hit's record).
  SurfaceInteraction shadingPoint(const Ray& ray, const Hit& hit, const RayCone& cone,
                                  uint32_t materialIndex, MovingFrame* movingFrame) const;

  // Whitted-style delta bounces at `si`: for each specular lobe (reflection, transmission) in
  // `flags` (the material's, so that every hit on it draws the same dimensions), one sample of
  // the BSDF's delta part, its weight times trace(ray, branchWeight) for the spawned ray.
  // Glossy and diffuse light is the caller's to gather from the lights. Draws four sampler
  // dimensions per lobe.
  //
  // Faint branches (POV-Ray's adc_bailout, made unbiased): `pathWeight` is what the camera
  // sees of this point (the largest channel of the product of the weights on the way). A
  // branch whose weight from the camera, w, falls below `minWeight` is followed with
  // probability w / minWeight and then weighted by its inverse (Russian roulette): the
  // expectation is unchanged, and the tree of reflected and refracted rays that glass spawns
  // (two per hit, to the depth limit) loses the branches too faint to see. 0 follows every
  // branch.
  template <class TraceFn>
  static Rgb specularBounces(const Bsdf& bsdf, const SurfaceInteraction& si, uint32_t flags,
                             float time, Sampler& sampler, float pathWeight, float minWeight,
                             TraceFn&& trace) {
    Rgb L;
    for (uint32_t lobe : {kBsdfReflection, kBsdfTransmission}) {
      if (!(flags & lobe)) continue;
      const Vec2f u = sampler.get2D();
      const float uLobe = sampler.get1D();
      const float uSurvive = sampler.get1D();  // drawn always: later dimensions keep their use
      BsdfSample s;
      if (!bsdf.sample(u, uLobe, &s, lobe | kBsdfSpecular) || !(s.flags & kBsdfSpecular) ||
          s.pdf <= 0)
        continue;
      Rgb weight = s.weight(si.ns);
      if (maxComponent(weight) <= 0) continue;
      float branchWeight = pathWeight * maxComponent(weight);
      if (branchWeight < minWeight) {
        const float survive = branchWeight / minWeight;
        if (!(uSurvive < survive)) continue;
        weight = weight / survive;
        branchWeight = minWeight;
      }
      L += weight * trace(si.spawnRay(s.wi, time), branchWeight);
    }
    return L;
  }

  const RenderScene& scene_;
  std::vector<MaterialShading> shading_;  // per material
};

// The integrators there are.
enum class IntegratorKind { Whitted, Path, InstantRadiosity };

// The integrator settings.type asks for, with "auto" resolved for `scene`: the path tracer when
// the scene has light with an extent (an environment, emitting surfaces that are lights, any
// non-delta light) or media asked to scatter multiply, else Whitted. Throws
// InputError for unknown names (the loaders accept only integratorNames()).
IntegratorKind resolveIntegrator(const RenderScene& scene, const IntegratorSettings& settings);
// "whitted", "path", "instant-radiosity": the name the settings use.
const char* integratorName(IntegratorKind kind);
// Builds the integrator settings.integrator.type names for `scene` ("auto" resolved as
// above). Throws InputError for unknown names.
std::unique_ptr<Integrator> makeIntegrator(const RenderScene& scene,
                                           const RenderSettings& settings);
// The names makeIntegrator accepts.
const std::vector<std::string>& integratorNames();

}  // namespace glint
