// glint — the path tracer.
#include "renderer/path.h"

#include <cmath>
#include <optional>

#include "materials/phase.h"
#include "renderer/direct_light.h"
#include "renderer/roulette.h"
#include "renderer/volume.h"

namespace glint {

namespace {

// The sampler dimensions of one path vertex (PathIntegrator::kVertexDimensions), drawn in this
// order at every vertex whatever it turns out to be.
struct VertexSamples {
  float uPass, uLight;
  Vec2f uLightPoint, uBsdf;
  float uLobe, uRoulette;
  explicit VertexSamples(Sampler& sampler)
      : uPass(sampler.get1D()),
        uLight(sampler.get1D()),
        uLightPoint(sampler.get2D()),
        uBsdf(sampler.get2D()),
        uLobe(sampler.get1D()),
        uRoulette(sampler.get1D()) {}
};

// The private random stream of a path's media tracking (see path.h): one 2D sample of the
// path's sampler, hashed into the key of a Sampler read at sample 0.
Sampler trackingStream(Sampler& sampler) {
  const Vec2f u = sampler.get2D();
  const uint64_t bits = (uint64_t(u.x * 0x1p24f) << 24) | uint64_t(u.y * 0x1p24f);
  return Sampler(mixBits(bits ^ 0x6a09e667f3bcc909ull), 0);
}

// Whether a vertex with this BSDF leaves the lights that allow it (Light::leftToBsdfSampling:
// a uniform sky) to its BSDF sampling, which is then nearly exact: the BSDF has a delta lobe,
// or its lobes are mostly narrow (at most 30% diffuse-like, none wider than alpha 0.3).
// There, also drawing a light sample splits only the non-delta or diffuse part between the
// two strategies, while the narrow branch, chosen by the lobes' albedos, still carries the
// whole albedo: the estimate swings between branches (a near-mirror plastic under a sky of 1
// read 1.42 on one branch, 0.93 on the other). Everywhere else (diffuse surfaces, rough lobes)
// the light sample is a second, MIS-weighted cosine sample and stays: leaving the sky to the
// BSDF there was 1.3 to 3.7 times noisier (benchmarks/README, issue 50).
bool leavesLights(const Bsdf& bsdf) {
  const float alpha = bsdf.narrowestAlpha();
  return alpha == 0 || (bsdf.diffuseProbability() <= 0.3f && alpha <= 0.3f);
}

}  // namespace

PathIntegrator::PathIntegrator(const RenderScene& scene, const IntegratorSettings& settings)
    : Integrator(scene),
      maxDepth_(settings.maxDepth),
      rrDepth_(settings.rrDepth),
      wholeSegmentEmission_(settings.wholeSegmentEmission) {
  shadows_ = scene.features().has(Feature::Shadows);
  lights_ = !scene.lights().empty() && scene.lightSampler();
  for (const Light* l : scene.infiniteLights())
    for (size_t i = 0; i < scene.lights().size(); ++i)
      if (scene.lights()[i].get() == l) infinite_.push_back({l, uint32_t(i)});
  bsdfFindable_.assign(scene.lights().size(), false);
  for (const auto& [light, index] : infinite_) bsdfFindable_[index] = true;
  for (int32_t l : scene.instanceLight())
    if (l >= 0) bsdfFindable_[size_t(l)] = true;
  bsdfOnlyAtSurfaces_.assign(scene.lights().size(), false);
  for (size_t i = 0; i < scene.lights().size(); ++i) {
    bsdfOnlyAtSurfaces_[i] = bsdfFindable_[i] && scene.lights()[i]->leftToBsdfSampling();
    someLeftToBsdf_ = someLeftToBsdf_ || bsdfOnlyAtSurfaces_[i];
  }
  if (scene.features().has(Feature::Volumes) && scene.media()) {
    media_ = scene.media();
    mediaScatter_ = settings.volume != "emission";
  }
  emissionFindable_ = !infinite_.empty() || maxComponent(scene.background()) > 0 || media_;
  for (const MaterialShading& s : shading_) emissionFindable_ = emissionFindable_ || s.emits;
}

// What a path carries from vertex to vertex.
struct PathIntegrator::Path {
  explicit Path(RayCone cameraCone) : cone(cameraCone) {}
  Rgb L;               // the radiance gathered so far
  Rgb beta{1, 1, 1};   // the throughput
  float etaScale = 1;  // the 1/eta^2 refractions put into beta, undone for roulette
  // The pixel cone along the current segment (texture footprints, bump steps).
  RayCone cone;
  // The previous scattering vertex, for MIS on emission the next one finds: whether it was a
  // delta bounce (or the camera), its BSDF (or phase) pdf, its light-sampling context, and
  // whether it left the lights that allow it to its BSDF sampling (leavesLights).
  bool specularBounce = true;
  float bsdfPdf = 0;
  LightSampleContext prev;
  bool prevLeftLights = false;
};

Rgb PathIntegrator::LiFromHit(const Ray& ray, const Hit* hit, Sampler& sampler,
                              RayCounters& counters, PathAovs& aovs) const {
  if (media_) return volumetricPath(ray, hit, sampler, counters, aovs);
  return surfacePath(ray, hit, sampler, counters, aovs);
}

// ---------------------------------------------------------------------------------------------
// The paths
// ---------------------------------------------------------------------------------------------

Rgb PathIntegrator::surfacePath(const Ray& cameraRay, const Hit* cameraHit, Sampler& sampler,
                                RayCounters& counters, PathAovs& aovs) const {
  // The camera's cone, read at every path, not kept from construction: the preview changes the
  // scene's camera under a built integrator.
  Path path(scene_.camera().pixelCone());
  Ray ray = cameraRay;
  Hit found;
  const Hit* hit = cameraHit;
  for (int depth = 0;; ++depth) {
    if (!hit) {
      addEscaped(path, ray.d);
      break;
    }
    ShadedHit h(scene_, shading_, ray, *hit, path.cone);
    if (depth == 0) aovs.record(h);
    if (!surfaceVertex(path, h, *hit, depth, sampler, noMedia, counters, &ray)) break;
    ++counters.secondary;
    hit = scene_.accel().closestHit(ray, &found) ? &found : nullptr;
  }
  return path.L;
}

Rgb PathIntegrator::volumetricPath(const Ray& cameraRay, const Hit* cameraHit, Sampler& sampler,
                                   RayCounters& counters, PathAovs& aovs) const {
  Path path(scene_.camera().pixelCone());
  // Tracking's own random stream (path.h), drawn before the vertices' dimensions.
  Sampler tracker = trackingStream(sampler);
  // Coloured extinction: one hero channel for the whole path (spectral MIS, volume.h).
  ChannelPath channels = media_->startPath(tracker);
  auto shadowMedia = [&](const Ray& shadow) {
    return media_->trackedTransmittance(shadow, shadow.tMax, tracker);
  };
  // The AOVs are the camera ray's first surface, seen through the media or not: shaded here
  // only for them, since the medium may scatter the path before it.
  if (cameraHit) {
    aovs.hit = true;
    if (aovs.wanted) {
      ShadedHit h(scene_, shading_, cameraRay, *cameraHit, path.cone);
      aovs.record(h);
    }
  }
  Ray ray = cameraRay;
  Hit found;
  const Hit* hit = cameraHit;
  for (int depth = 0;; ++depth) {
    // --- The media along the segment: their emission, then pass or scatter. The segment's
    // first free flight, event and emission offset come from the path's stratified dimensions
    // (SegmentSamples), the rest from the tracking stream. The flight and the event are one 2D
    // sample: stratified jointly, the camera ray's emission in the fire of scenes/volumes had
    // 0.7x the variance of two 1D samples'.
    const Vec2f uFirst = sampler.get2D();
    SegmentSamples first;
    first.flight = uFirst.x;
    first.event = uFirst.y;
    first.jitter = sampler.get1D();
    // The camera ray gathers the emission of its whole segment, not only up to where it
    // scatters (SegmentSamples): in a fire it is what the camera sees directly, and where the
    // ray stops in the smoke had been most of the noise. Deeper segments keep the
    // track-length estimator: there the extra tracking past the collision costs what it saves
    // (benchmarks/README, issue 52).
    first.wholeSegmentEmission = wholeSegmentEmission_ && depth == 0;
    Rgb Le;
    const MediumEvent event = media_->sampleScatteringAndEmission(ray, hit ? hit->t : kInfinity,
                                                                  tracker, &Le, &channels, &first);
    path.L += path.beta * Le;
    path.beta *= event.weight;
    if (!(maxComponent(path.beta) > 0)) break;  // absorbed
    if (event.scattered) {
      if (!mediumVertex(path, event, depth, sampler, tracker, counters, &ray)) break;
    } else if (!hit) {
      addEscaped(path, ray.d);
      break;
    } else {
      ShadedHit h(scene_, shading_, ray, *hit, path.cone);
      if (!surfaceVertex(path, h, *hit, depth, sampler, shadowMedia, counters, &ray)) break;
    }
    ++counters.secondary;
    hit = scene_.accel().closestHit(ray, &found) ? &found : nullptr;
  }
  return path.L;
}

// ---------------------------------------------------------------------------------------------
// The vertices
// ---------------------------------------------------------------------------------------------

template <class ShadowMedia>
bool PathIntegrator::surfaceVertex(Path& path, ShadedHit& h, const Hit& hit, int depth,
                                   Sampler& sampler, ShadowMedia&& shadowMedia,
                                   RayCounters& counters, Ray* ray) const {
  const SurfaceInteraction& si = h.si;
  const MaterialShading& shading = h.shading;
  path.beta *= h.inside();  // KHR_materials_volume
  if (!(maxComponent(path.beta) > 0)) return false;
  path.cone = RayCone{path.cone.widthAt(h.distance), path.cone.spread};

  // The vertex's sampler dimensions, all drawn whatever happens below (kVertexDimensions).
  const VertexSamples u(sampler);

  // --- Partly transparent: pass straight through with probability 1 - opacity (beta
  // unchanged: the probability and the weight cancel). The previous vertex stays the MIS
  // reference, since the direction does not change.
  if (shading.transparent && u.uPass >= h.opacity()) {
    if (depth >= maxDepth_) return false;
    *ray = si.spawnRay(ray->d, ray->time);
    return true;
  }

  // --- Unlit (eyelight): its colour, and the path ends.
  if (shading.unlit) {
    path.L += path.beta * h.unlitRadiance();
    return false;
  }

  // --- Emission found by the camera or a BSDF sample.
  if (shading.emits) {
    const Rgb Le = h.emitted();
    if (maxComponent(Le) > 0) {
      uint32_t index = 0;
      const Light* area = scene_.areaLight(hit, &index);
      if (path.specularBounce || !area) {
        path.L += path.beta * Le;
      } else {
        const float pdf = lightPdf(path.prev, index, *area, -si.wo, {si.p, si.ng, si.prim});
        path.L += path.beta * Le * powerHeuristic(path.bsdfPdf, pdf);
      }
    }
  }
  if (depth >= maxDepth_) return false;

  // The material's parameters, read once for next-event estimation and the next direction.
  const Bsdf bsdf = h.bsdf();

  // --- Next-event estimation, at surfaces with a non-delta lobe.
  const bool leftLights = someLeftToBsdf_ && leavesLights(bsdf);
  if (lights_ && (shading.flags & (kBsdfDiffuse | kBsdfGlossy)))
    path.L += path.beta * sampleLight(si, bsdf, leftLights, ray->time, u.uLight, u.uLightPoint,
                                      shadowMedia, counters);

  // --- The next direction.
  BsdfSample s;
  if (!bsdf.sample(u.uBsdf, u.uLobe, &s) || !(s.pdf > 0) || !std::isfinite(s.pdf)) return false;
  const Rgb weight = s.weight(si.ns);
  if (!(maxComponent(weight) > 0) || !isFinite(weight)) return false;
  path.beta *= weight;
  path.specularBounce = (s.flags & kBsdfSpecular) != 0;
  path.bsdfPdf = s.pdf;
  path.prev = LightSampleContext(si, ray->time);
  path.prevLeftLights = leftLights;
  if (s.flags & kBsdfTransmission) path.etaScale *= s.eta * s.eta;

  // The last bounce can only add the emission it finds: where nothing can be found (no
  // emitting surface, environment, background or medium), tracing it is wasted.
  if (depth + 1 >= maxDepth_ && !emissionFindable_) return false;
  if (!survivesRoulette(depth + 1, rrDepth_, path.etaScale, u.uRoulette, &path.beta)) return false;
  *ray = si.spawnRay(s.wi, ray->time);
  return true;
}

bool PathIntegrator::mediumVertex(Path& path, const MediumEvent& event, int depth, Sampler& sampler,
                                  Sampler& tracker, RayCounters& counters, Ray* ray) const {
  const VertexSamples u(sampler);
  if (!mediaScatter_ || depth >= maxDepth_) return false;
  const float len = length(ray->d);
  const Vec3f d = ray->d / len;
  const LightSampleContext ctx =
      LightSampleContext::inMedium(ray->at(event.t), ray->time, d, event.g);
  path.cone = RayCone{path.cone.widthAt(event.t * len), path.cone.spread};

  // --- Next-event estimation from the medium point.
  if (lights_)
    path.L += path.beta *
              sampleLightInMedium(ctx, d, event.g, u.uLight, u.uLightPoint, tracker, counters);

  // --- The next direction: the phase function sampled exactly (weight phase / pdf = 1).
  float phasePdf = 0;
  const Vec3f wi = sampleHenyeyGreenstein(d, event.g, u.uBsdf, &phasePdf);
  if (!(phasePdf > 0) || !std::isfinite(phasePdf)) return false;
  path.specularBounce = false;
  path.prevLeftLights = false;
  path.bsdfPdf = phasePdf;
  path.prev = ctx;
  if (!survivesRoulette(depth + 1, rrDepth_, path.etaScale, u.uRoulette, &path.beta)) return false;
  // A point in a medium lies on no surface: no offset needed.
  *ray = Ray{ctx.p, wi, 0, kInfinity, ray->time};
  return true;
}

void PathIntegrator::addEscaped(Path& path, Vec3f direction) const {
  const Vec3f d = normalize(direction);
  if (path.specularBounce || infinite_.empty()) {
    path.L += path.beta * scene_.escaped(d);
    return;
  }
  for (const auto& [light, index] : infinite_) {
    const Rgb Le = light->Le(d);
    if (maxComponent(Le) <= 0) continue;
    // Found by a BSDF sample where it is left to them: weight 1.
    const float pdf = path.prevLeftLights && bsdfOnlyAtSurfaces_[index]
                          ? 0.0f
                          : lightPdf(path.prev, index, *light, d, LightHit{});
    path.L += path.beta * Le * powerHeuristic(path.bsdfPdf, pdf);
  }
}

// ---------------------------------------------------------------------------------------------
// Next-event estimation
// ---------------------------------------------------------------------------------------------

template <class ShadowMedia>
Rgb PathIntegrator::sampleLight(const SurfaceInteraction& si, const Bsdf& bsdf, bool leftLights,
                                float time, float uLight, Vec2f uPoint, ShadowMedia&& shadowMedia,
                                RayCounters& counters) const {
  const LightSampleContext ctx(si, time);
  const std::optional<SampledLight> picked = scene_.lightSampler()->sample(ctx, uLight);
  if (!picked || !(picked->p > 0)) return {};
  // Left to BSDF sampling: the other lights keep their probabilities, so nothing is lost but
  // this sample (pbrt-v4 does the same).
  if (leftLights && bsdfOnlyAtSurfaces_[picked->index]) return {};
  // Light must arrive on the side of the geometric surface the BSDF says it can; f checks the
  // hemispheres (reflection and transmission alike).
  auto scatter = [&](Vec3f wi, float* pdf) -> Rgb {
    const Rgb f = pdf ? bsdf.evaluate(wi, pdf) : bsdf.f(wi);
    return f * std::abs(dot(si.ns, wi));
  };
  const DirectLightOptions options{
      .pmf = picked->p, .shadows = shadows_, .mis = bsdfFindable_[picked->index]};
  return sampleDirectLight(scene_, ctx, *scene_.lights()[picked->index], uPoint, options, scatter,
                           shadowMedia, counters);
}

Rgb PathIntegrator::sampleLightInMedium(const LightSampleContext& ctx, Vec3f d, float g,
                                        float uLight, Vec2f uPoint, Sampler& tracker,
                                        RayCounters& counters) const {
  const std::optional<SampledLight> picked = scene_.lightSampler()->sample(ctx, uLight);
  if (!picked || !(picked->p > 0)) return {};
  // The phase function stands for f |cos|; it is also the density phase sampling has.
  auto scatter = [&](Vec3f wi, float* pdf) -> Rgb {
    const float phase = henyeyGreenstein(dot(wi, d), g);
    if (pdf) *pdf = phase;
    return Rgb{phase, phase, phase};
  };
  // Surfaces shadow medium points even where no surface is lit (Feature::Shadows unset), so
  // only the light's own flag decides, as in Whitted's single scattering.
  const DirectLightOptions options{
      .pmf = picked->p, .shadows = true, .mis = bsdfFindable_[picked->index]};
  return sampleDirectLight(
      scene_, ctx, *scene_.lights()[picked->index], uPoint, options, scatter,
      [&](const Ray& shadow) { return media_->trackedTransmittance(shadow, shadow.tMax, tracker); },
      counters);
}

}  // namespace glint
