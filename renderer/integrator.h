// glint — integrators: radiance along a camera ray.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "renderer/ray_counters.h"
#include "renderer/sampler.h"
#include "renderer/scene.h"
#include "renderer/settings.h"
#include "renderer/shading.h"

namespace glint {

// First-hit attributes: `hit` always (for alpha); the rest only when `wanted` (AOV output).
struct PathAovs {
  bool wanted = false;
  Rgb albedo;
  Vec3f normal;
  float depth = 0;
  bool hit = false;

  // Records the first hit: `hit` always, the attributes only when wanted.
  void record(ShadedHit& h) {
    hit = true;
    if (!wanted) return;
    albedo = h.albedo();
    normal = h.si.ns;
    depth = h.distance;
  }
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
  // What each material's hits need, per material: hits are shaded as
  // ShadedHit h(scene_, shading_, ray, hit, cone).
  std::vector<MaterialShading> shading_;
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
