// glint — instant radiosity.
#include "renderer/instant_radiosity.h"

#include <algorithm>
#include <cmath>

#include "geometry/error.h"

namespace glint {

// ---------------------------------------------------------------------------------------------
// The Halton sequence
// ---------------------------------------------------------------------------------------------

namespace {

// The first primes, one per Halton dimension (enough for 5 + 5 x 40 bounces).
const std::vector<uint32_t>& primes() {
  static const std::vector<uint32_t> table = [] {
    std::vector<uint32_t> p;
    for (uint32_t n = 2; p.size() < 256; ++n) {
      bool prime = true;
      for (uint32_t q : p) {
        if (q * q > n) break;
        if (n % q == 0) prime = false;
      }
      if (prime) p.push_back(n);
    }
    return p;
  }();
  return table;
}

// Dimension `dim` of light path `index`: a scrambled Halton coordinate while primes last,
// then a hash (deep bounces are rare and need no stratification).
class HaltonPoint {
 public:
  HaltonPoint(uint64_t index, uint64_t seed) : index_(index), seed_(seed) {}
  float get1D() {
    const uint64_t scramble = mixBits(seed_ ^ mixBits(dim_ + 1));
    const uint32_t d = dim_++;
    if (d < primes().size()) return scrambledRadicalInverse(primes()[d], index_, scramble);
    return fractionToFloatBits(mixBits(scramble ^ (index_ * 0xd1b54a32d192ed03ull)));
  }
  Vec2f get2D() {
    const float x = get1D();
    return {x, get1D()};
  }

 private:
  static float fractionToFloatBits(uint64_t h) { return float(h >> 40) * 0x1p-24f; }
  uint64_t index_, seed_;
  uint32_t dim_ = 0;
};

}  // namespace

float scrambledRadicalInverse(uint32_t base, uint64_t index, uint64_t scramble) {
  const double invBase = 1.0 / base;
  double r = 0, weight = invBase;
  // Digits until they no longer change a float; the shift applies to the trailing zero digits
  // too, which spreads each point uniformly within its stratum.
  for (uint64_t digitPos = 0; weight > 1e-9; ++digitPos, weight *= invBase) {
    const uint64_t digit = index % base;
    index /= base;
    const uint64_t shift = mixBits(scramble + digitPos * 0x9e3779b97f4a7c15ull) % base;
    r += double((digit + shift) % base) * weight;
  }
  return std::min(float(r), 0x1.fffffep-1f);
}

// ---------------------------------------------------------------------------------------------
// Setup: light paths and their VPLs
// ---------------------------------------------------------------------------------------------

InstantRadiosityIntegrator::InstantRadiosityIntegrator(const RenderScene& scene,
                                                       const IntegratorSettings& settings,
                                                       uint64_t seed)
    : WhittedIntegrator(scene, settings.maxDepth, settings.glassShadows, settings.minWeight),
      rrDepth_(settings.rrDepth),
      paths_(settings.vplPaths),
      clamp_(settings.vplClamp),
      shadowShare_(settings.vplShadowShare) {
  if (settings.vplPaths <= 0) throw InputError("instant radiosity: vpl_paths must be > 0");
  indirect_ = true;
  traceLightPaths(settings.vplPaths, seed);
}

std::vector<Integrator::SetupStat> InstantRadiosityIntegrator::setupStats() const {
  return {{"vpl_paths", double(paths_)},
          {"vpls", double(vpls_.size())},
          {"vpl_clamp", double(clamp_)},
          {"vpl_shadow_share", double(shadowShare_)},
          {"light_path_rays", double(lightPathRays_)}};
}

void InstantRadiosityIntegrator::traceLightPaths(int paths, uint64_t seed) {
  // A VPL at light-path vertex k lights camera paths of k + 1 bounces.
  const int lastVertex = maxDepth_ - 1;
  if (scene_.lights.empty() || lastVertex < 1) return;
  // Lights by power, as the power light sampler picks them (but independent of the NEE
  // sampler setting: a BVH sampler needs a receiving point, a light path has none).
  std::vector<float> power;
  for (const auto& light : scene_.lights) {
    const float p = luminance(light->phi());
    power.push_back(std::isfinite(p) && p > 0 ? p : 0);
  }
  const DiscreteDistribution lightDistribution(power);
  const float invPaths = 1.0f / float(paths);

  for (int path = 0; path < paths; ++path) {
    // Index 0 of a Halton sequence is the origin in every dimension: start at 1.
    HaltonPoint u(uint64_t(path) + 1, seed);
    float pLight = 0;
    const float uLight = u.get1D();
    const Vec2f uPos = u.get2D(), uDir = u.get2D();
    const uint32_t index = lightDistribution.sample(uLight, &pLight);
    if (!(pLight > 0)) continue;
    const std::optional<LightLeSample> le = scene_.lights[index]->sampleLe(uPos, uDir, 0);
    if (!le || !(le->pdfPos > 0) || !(le->pdfDir > 0)) continue;
    const Rgb power0 = le->beta() * (invPaths / pLight);
    if (!(maxComponent(power0) > 0) || !isFinite(power0)) continue;

    Rgb throughput{1, 1, 1};  // product of the flux weights since the light (for roulette)
    // Transmittance estimates through heterogeneous media draw their own numbers, from a
    // stream of the path's own (the Halton dimensions stay the same with or without media).
    Sampler mediaSampler(mixBits(seed ^ 0x6d656469615f7670ull) ^ uint64_t(path), 0);
    Ray ray = le->ray;
    Hit hit;
    for (int vertex = 1; vertex <= lastVertex; ++vertex) {
      // The vertex's Halton dimensions, all drawn whatever happens below.
      const float uPass = u.get1D();
      const Vec2f uBsdf = u.get2D();
      const float uLobe = u.get1D();
      const float uRoulette = u.get1D();

      ++lightPathRays_;
      if (!scene_.accel->closestHit(ray, &hit)) break;
      if (media()) {
        // The flux that arrives: the segment's transmittance (estimated, unbiased for
        // tracking) weights the rest of the path.
        throughput *= media()->transmittance(ray, hit.t, mediaSampler);
        if (!(maxComponent(throughput) > 0)) break;
      }
      const uint32_t materialIndex = scene_.materialIndex(hit);
      const Material& material = *scene_.materials[materialIndex];
      const MaterialShading& shading = shading_[materialIndex];
      MovingFrame movingFrame;
      SurfaceInteraction si = shadingPoint(ray, hit, RayCone{}, materialIndex, &movingFrame);
      TextureLookups lookups(si);
      throughput *= insideTransmittance(material, shading, si, hit.t * length(ray.d));
      if (!(maxComponent(throughput) > 0)) break;

      // Partly transparent: light passes straight through with probability 1 - opacity.
      if (shading.transparent && uPass >= material.opacity(si, lookups)) {
        ray = si.spawnRay(ray.d, ray.time);
        continue;
      }
      if (shading.unlit) break;
      const Bsdf bsdf = material.bsdf(si, lookups);

      // A VPL wherever a non-delta lobe can reflect the light on; it keeps its BSDF.
      if (shading.flags & (kBsdfDiffuse | kBsdfGlossy)) {
        Vpl& v = vpls_.emplace_back();
        v.si = si;
        v.si.objectFromWorld = nullptr;  // may point to movingFrame, which ends here
        v.bsdf = bsdf;
        v.flux = power0 * throughput;
        v.vertex = vertex;
      }
      if (vertex == lastVertex) break;

      std::optional<BsdfSample> s = bsdf.sample(uBsdf, uLobe);
      if (!s || !(s->pdf > 0) || !std::isfinite(s->pdf)) break;
      // Flux, not radiance, travels along a light path: the shading-normal correction
      // |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|) (Veach 1997, 5.3) and no 1/eta^2 at refractions.
      const float cosOg = std::abs(dot(si.wo, si.ng));
      if (!(cosOg > 0)) break;
      Rgb weight =
          s->f * (std::abs(dot(si.wo, si.ns)) * std::abs(dot(s->wi, si.ng)) / (cosOg * s->pdf));
      if (s->flags & kBsdfTransmission) weight *= s->eta * s->eta;
      if (!(maxComponent(weight) > 0) || !isFinite(weight)) break;
      throughput *= weight;

      // Russian roulette on the throughput, as the path tracer does.
      if (vertex >= rrDepth_) {
        const float survive = std::clamp(maxComponent(throughput), 0.05f, 1.0f);
        if (survive < 1) {
          if (uRoulette >= survive) break;
          throughput *= 1 / survive;
        }
      }
      ray = si.spawnRay(s->wi, ray.time);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Gather: Whitted's recursion, lit by the lights and the VPLs
// ---------------------------------------------------------------------------------------------

Rgb InstantRadiosityIntegrator::indirectLight(const SurfaceInteraction& si, const Bsdf& bsdf,
                                              float time, Sampler& sampler,
                                              RayCounters& counters) const {
  // Every VPL's unshadowed contribution first (see "Shadow rays by importance" in the header).
  struct Candidate {
    Rgb c;
    uint32_t vpl;
  };
  thread_local std::vector<Candidate> candidates;
  candidates.clear();
  double total = 0;
  const float pointError = length(si.pError);
  for (uint32_t k = 0; k < vpls_.size(); ++k) {
    const Vpl& v = vpls_[k];
    const Vec3f d = v.si.p - si.p;
    const float dist2 = dot(d, d);
    const float dist = std::sqrt(dist2);
    // The VPL is the shading point itself, as far as rounding can tell: G has no meaning.
    if (!(dist > pointError + length(v.si.pError)) || !(dist2 > 0)) continue;
    const Vec3f wi = d / dist;
    const Rgb f = bsdf.f(wi);
    if (!(maxComponent(f) > 0)) continue;
    const Rgb fVpl = v.bsdf.f(-wi);
    if (!(maxComponent(fVpl) > 0)) continue;
    float G = std::abs(dot(si.ns, wi)) * std::abs(dot(v.si.ns, wi)) / dist2;
    if (clamp_ > 0) G = std::min(G, clamp_);
    const Rgb contribution = f * fVpl * v.flux * G;
    if (!(maxComponent(contribution) > 0) || !isFinite(contribution)) continue;
    candidates.push_back({contribution, k});
    total += maxComponent(contribution);
  }
  // Drawn whether or not it is needed: the dimensions after it do not depend on the scene.
  const float u = sampler.get1D();
  if (candidates.empty()) return {};
  // Visible light of VPL `k` sending `c`, 0 when shadowed.
  auto visible = [&](const Candidate& cand) -> Rgb {
    if (!shadows_) return cand.c;
    const Vpl& v = vpls_[cand.vpl];
    // Both ends leave their surfaces by their error bounds, as area-light shadow rays do.
    ++counters.shadow;
    const Ray shadow =
        spawnRayToSurface(si.p, si.pError, si.ng, v.si.p, v.si.pError, v.si.ng, time);
    if (scene_.accel->anyHit(shadow)) return {};
    if (!media()) return cand.c;
    const Rgb Tr = media()->transmittance(shadow, shadow.tMax, sampler);
    return maxComponent(Tr) > 0 ? cand.c * Tr : Rgb{};
  };
  Rgb L;
  const double share = shadowShare_ > 0 && shadows_ ? double(shadowShare_) * total : 0.0;
  // Systematic sampling: the running sum of the small VPLs' p_i crosses u, u + 1, u + 2, ...
  // once per pick; a VPL is picked when one of those falls in its stretch [sum, sum + p_i).
  double running = 0, next = u;
  for (const Candidate& cand : candidates) {
    const double importance = maxComponent(cand.c);
    if (share <= 0 || importance >= share) {
      L += visible(cand);
      continue;
    }
    const double p = importance / share;
    running += p;
    if (running <= next) continue;
    next += 1;
    L += visible(cand) * float(1 / p);
  }
  return L;
}

}  // namespace glint
