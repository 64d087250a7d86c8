// glint — the Whitted integrator.
#include "renderer/whitted.h"

#include <optional>

#include "renderer/direct_light.h"

namespace glint {

WhittedIntegrator::WhittedIntegrator(const RenderScene& scene, int maxDepth, bool glassShadows,
                                     float minWeight, const IndirectLight* indirect)
    : Integrator(scene), maxDepth_(maxDepth), minWeight_(minWeight), indirect_(indirect) {
  shadows_ = scene.features().has(Feature::Shadows);
  glassShadows_ = glassShadows && shadows_ && scene.features().has(Feature::Refraction);
  media_ = scene.features().has(Feature::Volumes) ? scene.media() : nullptr;
  plainShadows_ = !media_ && !glassShadows_;
  kinds_.resize(shading_.size());
  for (size_t m = 0; m < shading_.size(); ++m) {
    const MaterialShading& s = shading_[m];
    if (!indirect_ && !s.unlit && !s.transparent && !s.emits && !s.absorbs &&
        !(s.flags & kBsdfSpecular))
      kinds_[m] = HitKind::Plain;
    else if (s.unlit && !s.transparent && !s.absorbs)
      kinds_[m] = HitKind::Unlit;
    else
      kinds_[m] = HitKind::General;
  }
}

Rgb WhittedIntegrator::LiFromHit(const Ray& ray, const Hit* hit, Sampler& sampler,
                                 RayCounters& counters, PathAovs& aovs) const {
  // The camera's cone, read at every ray, not kept from construction: the preview changes the
  // scene's camera under a built integrator.
  return radiance(ray, hit, scene_.camera().pixelCone(), 0, 1, sampler, counters, &aovs);
}

Rgb WhittedIntegrator::trace(const Ray& ray, const RayCone& cone, int depth, float weight,
                             Sampler& sampler, RayCounters& counters) const {
  ++counters.secondary;
  Hit hit;
  const bool found = scene_.accel().closestHit(ray, &hit);
  return radiance(ray, found ? &hit : nullptr, cone, depth, weight, sampler, counters, nullptr);
}

Rgb WhittedIntegrator::radiance(const Ray& ray, const Hit* hit, const RayCone& cone, int depth,
                                float weight, Sampler& sampler, RayCounters& counters,
                                PathAovs* aovs) const {
  if (media_) return throughMedia(ray, hit, cone, depth, weight, sampler, counters, aovs);
  return surface(ray, hit, cone, depth, weight, sampler, counters, aovs);
}

Rgb WhittedIntegrator::throughMedia(const Ray& ray, const Hit* hit, const RayCone& cone, int depth,
                                    float weight, Sampler& sampler, RayCounters& counters,
                                    PathAovs* aovs) const {
  // What the media add (seg.L) and let through (seg.T).
  const VolumeSegment seg =
      media_->integrate(scene_, ray, hit ? hit->t : kInfinity, sampler, counters);
  // Behind an opaque medium the surface cannot be seen: no need to shade it (AOVs aside).
  if (maxComponent(seg.T) <= 0 && !aovs) return seg.L;
  return seg.T *
             surface(ray, hit, cone, depth, weight * maxComponent(seg.T), sampler, counters, aovs) +
         seg.L;
}

Rgb WhittedIntegrator::surface(const Ray& ray, const Hit* hit, const RayCone& cone, int depth,
                               float weight, Sampler& sampler, RayCounters& counters,
                               PathAovs* aovs) const {
  if (!hit) return scene_.escapedAlong(ray.d);
  const uint32_t m = scene_.materialIndex(*hit);
  const HitKind kind = kinds_[m];
  if (kind == HitKind::Plain)
    return shade<HitKind::Plain>(ray, *hit, m, cone, depth, weight, sampler, counters, aovs);
  if (kind == HitKind::Unlit)
    return shade<HitKind::Unlit>(ray, *hit, m, cone, depth, weight, sampler, counters, aovs);
  return shade<HitKind::General>(ray, *hit, m, cone, depth, weight, sampler, counters, aovs);
}

template <WhittedIntegrator::HitKind kKind>
Rgb WhittedIntegrator::shade(const Ray& ray, const Hit& hit, uint32_t materialIndex,
                             const RayCone& cone, int depth, float weight, Sampler& sampler,
                             RayCounters& counters, PathAovs* aovs) const {
  ShadedHit h(scene_, shading_, materialIndex, ray, hit, cone);
  const SurfaceInteraction& si = h.si;
  const MaterialShading& shading = h.shading;
  if (aovs) aovs->record(h);
  if constexpr (kKind == HitKind::Unlit) {
    return h.unlitRadiance();
  } else if constexpr (kKind == HitKind::Plain) {
    const Bsdf bsdf = h.bsdf();
    return plainShadows_ ? directLight<true>(si, bsdf, ray.time, sampler, counters)
                         : directLight<false>(si, bsdf, ray.time, sampler, counters);
  } else {
    // Light reaching a back face of an absorbing volume crossed its inside.
    const Rgb inside = h.inside();
    if (!(maxComponent(inside) > 0)) return {};
    // The cone at the hit, carried on by every secondary ray from here (only they need it).
    const RayCone next{cone.widthAt(h.distance), cone.spread};

    // Partly transparent surfaces: the rest of the light comes straight through.
    const float opacity = shading.transparent ? h.opacity() : 1.0f;
    Rgb behind;
    if (opacity < 1) {
      if (depth < maxDepth_)
        behind = trace(si.spawnRay(ray.d, ray.time), next, depth + 1, weight * (1 - opacity),
                       sampler, counters);
      if (opacity <= 0) return behind * inside;
    }

    Rgb L;
    if (shading.unlit) {
      L = h.unlitRadiance();
    } else {
      const Bsdf bsdf = h.bsdf();
      if (shading.emits) L = h.emitted();
      L += directLight<false>(si, bsdf, ray.time, sampler, counters);
      if (indirect_ && (shading.flags & (kBsdfDiffuse | kBsdfGlossy)))
        L += indirect_->gather(si, bsdf, ray.time, sampler, counters);
      // Mirror and glass: follow the reflected and the refracted ray, each with its own weight.
      if ((shading.flags & kBsdfSpecular) && depth < maxDepth_)
        L += specularBounces(bsdf, si, shading.flags, ray.time, next, depth + 1, weight, sampler,
                             counters);
    }
    return (opacity < 1 ? L * opacity + behind * (1 - opacity) : L) * inside;
  }
}

// Faint branches (POV-Ray's adc_bailout, made unbiased): a branch whose weight from the
// camera, w (the largest channel of the product of the weights on the way), falls below
// `minWeight_` is followed with probability w / minWeight_ and then weighted by its inverse:
// the expectation is unchanged, and the tree of reflected and refracted rays that glass spawns
// (two per hit, to the depth limit) loses the branches too faint to see. 0 follows every
// branch. A rule of its own rather than roulette.h's: it cuts a branch by what the camera
// sees of it, not by a path's throughput, and it keeps its own arithmetic (the weight divided
// by the survival probability), which the images depend on to the last bit.
Rgb WhittedIntegrator::specularBounces(const Bsdf& bsdf, const SurfaceInteraction& si,
                                       uint32_t flags, float time, const RayCone& cone, int depth,
                                       float pathWeight, Sampler& sampler,
                                       RayCounters& counters) const {
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
    if (branchWeight < minWeight_) {
      const float survive = branchWeight / minWeight_;
      if (!(uSurvive < survive)) continue;
      weight = weight / survive;
      branchWeight = minWeight_;
    }
    L += weight * trace(si.spawnRay(s.wi, time), cone, depth, branchWeight, sampler, counters);
  }
  return L;
}

template <bool kPlainShadows>
Rgb WhittedIntegrator::directLight(const SurfaceInteraction& si, const Bsdf& bsdf, float time,
                                   Sampler& sampler, RayCounters& counters) const {
  Rgb L;
  const LightSampleContext ctx(si, time);
  // Reflected light only: Whitted's shadow rays stop at glass, so nothing arrives from behind.
  auto scatter = [&](Vec3f wi, float*) -> Rgb {
    const float cosTheta = dot(si.ns, wi);
    if (cosTheta <= 0 || dot(si.ng, wi) <= 0) return {};
    return bsdf.f(wi) * cosTheta;
  };
  const DirectLightOptions options{.pmf = 1, .shadows = shadows_, .mis = false};
  for (const auto& light : scene_.lights()) {
    const Vec2f u = light->isDelta() ? Vec2f{0.5f, 0.5f} : sampler.get2D();
    if constexpr (kPlainShadows) {
      L += sampleDirectLight(scene_, ctx, *light, u, options, scatter, noMedia, counters);
    } else if (glassShadows_) {
      // The shadow ray is followed through glass here rather than stopped at the first hit.
      const DirectLightOptions through{
          .pmf = 1, .shadows = true, .mis = false, .transmittanceTraces = true};
      L += sampleDirectLight(
          scene_, ctx, *light, u, through, scatter,
          [&](const Ray& shadow) {
            const Rgb T = throughGlass(shadow, counters);
            if (!media_ || !(maxComponent(T) > 0)) return T;
            return T * media_->transmittance(shadow, shadow.tMax, sampler);
          },
          counters);
    } else if (media_)
      L += sampleDirectLight(
          scene_, ctx, *light, u, options, scatter,
          [&](const Ray& shadow) { return media_->transmittance(shadow, shadow.tMax, sampler); },
          counters);
    else
      L += sampleDirectLight(scene_, ctx, *light, u, options, scatter, noMedia, counters);
  }
  return L;
}

Rgb WhittedIntegrator::throughGlass(const Ray& shadow, RayCounters& counters) const {
  // A shadow ray crosses few surfaces; past this many it is taken as blocked.
  constexpr int kMaxCrossings = 16;
  const Vec3f end = shadow.at(shadow.tMax);  // where the ray must stop, whatever it crosses
  Ray ray = shadow;
  Rgb T{1, 1, 1};
  float entryR = 0;  // R where the ray entered the object it is in (0: not in one)
  for (int crossing = 0; crossing < kMaxCrossings; ++crossing) {
    ++counters.shadow;
    Hit hit;
    if (!scene_.accel().closestHit(ray, &hit)) return T;
    const uint32_t materialIndex = scene_.materialIndex(hit);
    if (!(shading_[materialIndex].flags & kBsdfTransmission) ||
        !scene_.materials()[materialIndex]->traits().refraction)
      return {};
    ShadedHit h(scene_, shading_, materialIndex, ray, hit, RayCone{});
    const SurfaceInteraction& si = h.si;
    const Bsdf::StraightCrossing c = h.bsdf().straightCrossing(ray.d, si.frontFace);
    if (si.frontFace) {
      T *= c.tint * (1 - c.R);
      entryR = c.R;
    } else {
      // Leaving: the light reflected back and forth between entry and exit adds up to
      // 1 / (1 - R1 R2); the inside absorbs along the way (KHR_materials_volume).
      T *= c.tint * ((1 - c.R) / std::max(1 - entryR * c.R, 1e-6f)) * h.inside();
      entryR = 0;
    }
    if (!(maxComponent(T) > 0)) return {};
    // On from just beyond the surface, to the same end.
    const Vec3f o = offsetRayOrigin(si.p, si.pError, si.ng, ray.d);
    const float rest = dot(end - o, ray.d);
    if (!(rest > 0)) return T;
    ray = Ray{o, ray.d, 0, rest, ray.time};
  }
  return {};
}

}  // namespace glint
