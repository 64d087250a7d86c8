// glint — instant radiosity.
#include "renderer/instant_radiosity.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "geometry/error.h"
#include "renderer/roulette.h"

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
    : Integrator(scene),
      maxDepth_(settings.maxDepth),
      rrDepth_(settings.rrDepth),
      paths_(settings.vplPaths),
      clamp_(settings.vplClamp),
      shadowShare_(settings.vplShadowShare),
      shadows_(scene.features().has(Feature::Shadows)),
      media_(scene.features().has(Feature::Volumes) ? scene.media() : nullptr),
      whitted_(scene, settings.maxDepth, settings.glassShadows, settings.minWeight, this) {
  if (settings.vplPaths <= 0) throw InputError("instant radiosity: vpl_paths must be > 0");
  traceLightPaths(settings.vplPaths, seed);
  allLambert_ = true;
  for (const Vpl& v : vpls_) {
    points_.add(v);
    allLambert_ = allLambert_ && points_.lambert.back();
  }
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
  if (scene_.lights().empty() || lastVertex < 1) return;
  // Lights by power, as the power light sampler picks them (but independent of the NEE
  // sampler setting: a BVH sampler needs a receiving point, a light path has none).
  std::vector<float> power;
  for (const auto& light : scene_.lights()) {
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
    const std::optional<LightLeSample> le = scene_.lights()[index]->sampleLe(uPos, uDir, 0);
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
      if (!scene_.accel().closestHit(ray, &hit)) break;
      if (media_) {
        // The flux that arrives: the segment's transmittance (estimated, unbiased for
        // tracking) weights the rest of the path.
        throughput *= media_->transmittance(ray, hit.t, mediaSampler);
        if (!(maxComponent(throughput) > 0)) break;
      }
      ShadedHit h(scene_, shading_, ray, hit, RayCone{});
      const SurfaceInteraction& si = h.si;
      const MaterialShading& shading = h.shading;
      throughput *= h.inside();
      if (!(maxComponent(throughput) > 0)) break;

      // Partly transparent: light passes straight through with probability 1 - opacity.
      if (shading.transparent && uPass >= h.opacity()) {
        ray = si.spawnRay(ray.d, ray.time);
        continue;
      }
      if (shading.unlit) break;
      const Bsdf bsdf = h.bsdf();

      // A VPL wherever a non-delta lobe can reflect the light on; it keeps its BSDF.
      if (shading.flags & (kBsdfDiffuse | kBsdfGlossy)) {
        Vpl& v = vpls_.emplace_back();
        v.si = si;
        v.si.objectFromWorld = nullptr;  // may point into `h`, which ends here
        v.bsdf = bsdf;
        v.flux = power0 * throughput;
        v.vertex = vertex;
      }
      if (vertex == lastVertex) break;

      BsdfSample s;
      if (!bsdf.sample(uBsdf, uLobe, &s) || !(s.pdf > 0) || !std::isfinite(s.pdf)) break;
      // Flux, not radiance, travels along a light path: the shading-normal correction
      // |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|) (Veach 1997, 5.3) and no 1/eta^2 at refractions.
      const float cosOg = std::abs(dot(si.wo, si.ng));
      if (!(cosOg > 0)) break;
      Rgb weight =
          s.f * (std::abs(dot(si.wo, si.ns)) * std::abs(dot(s.wi, si.ng)) / (cosOg * s.pdf));
      if (s.flags & kBsdfTransmission) weight *= s.eta * s.eta;
      if (!(maxComponent(weight) > 0) || !isFinite(weight)) break;
      throughput *= weight;

      // Russian roulette on the throughput, as the path tracer's (flux: no 1/eta^2 to undo).
      if (!survivesRoulette(vertex, rrDepth_, 1, uRoulette, &throughput)) break;
      ray = si.spawnRay(s.wi, ray.time);
    }
  }
}

void VplArrays::add(const Vpl& v) {
  px.push_back(v.si.p.x), py.push_back(v.si.p.y), pz.push_back(v.si.p.z);
  errorLength.push_back(length(v.si.pError));
  nx.push_back(v.si.ns.x), ny.push_back(v.si.ns.y), nz.push_back(v.si.ns.z);
  const Vec3f bn = v.bsdf.ns(), bg = v.bsdf.ng();
  bx.push_back(bn.x), by.push_back(bn.y), bz.push_back(bn.z);
  gx.push_back(bg.x), gy.push_back(bg.y), gz.push_back(bg.z);
  // terminatorShadowing is 1 where this is not positive, and so is a BSDF without the term.
  cosNsNg.push_back(v.bsdf.terminator() ? dot(bn, bg) : 0.0f);
  const std::optional<Rgb> r = v.bsdf.lambertR();
  lambert.push_back(r.has_value());
  const Rgb R = r.value_or(Rgb{});
  rr.push_back(R.x), rg.push_back(R.y), rb.push_back(R.z);
  fr.push_back(v.flux.x), fg.push_back(v.flux.y), fb.push_back(v.flux.z);
}

std::optional<LambertGatherPoint> LambertGatherPoint::at(const SurfaceInteraction& si,
                                                         const Bsdf& bsdf, float clamp) {
  const std::optional<Rgb> R = bsdf.lambertR();
  if (!R) return std::nullopt;
  const Vec3f bn = bsdf.ns(), bg = bsdf.ng();
  LambertGatherPoint q;
  q.x = si.p.x, q.y = si.p.y, q.z = si.p.z, q.error = length(si.pError);
  q.nx = si.ns.x, q.ny = si.ns.y, q.nz = si.ns.z;
  q.bx = bn.x, q.by = bn.y, q.bz = bn.z;
  q.gx = bg.x, q.gy = bg.y, q.gz = bg.z;
  // As VplArrays::cosNsNg: 0 without the terminator term.
  q.cosNsNg = bsdf.terminator() ? dot(bn, bg) : 0.0f;
  q.r = R->x, q.g = R->y, q.b = R->z;
  q.clamp = clamp;
  return q;
}

namespace {

// terminatorShadowing for a direction on the side of both normals (cosNs, cosNg > 0), computed
// whatever cosNsNg is (the caller selects 1 where cosNsNg <= 0): no branch, so that the loop
// below vectorises.
inline float terminatorSmooth(float cosNs, float cosNg, float cosNsNg) {
  const float g = std::min(1.0f, cosNg / (cosNs * cosNsNg));
  return -g * g * g + g * g + g;  // the smooth form of the paper's eq. 4
}

// Every VPL's unshadowed contribution to a Lambert gather point when every VPL is Lambert too:
// the scalar loop of gather with Bsdf::lambertF written out, the same operations in the
// same order (so the same values), a VPL that contributes nothing given 0. Branch-free, one
// array per quantity, so that it runs 4 or 8 VPLs per instruction (the gather point's own
// choices are template arguments: the vectoriser takes no scalar condition in the loop).
template <bool kTerminator, bool kClamp>
[[gnu::always_inline]] inline void lambertVplLoop(const VplArrays& a,
                                                  const LambertGatherPoint& gather,
                                                  float* __restrict outR, float* __restrict outG,
                                                  float* __restrict outB) {
  const LambertGatherPoint q = gather;  // a copy: the stores below cannot change it
  const size_t n = a.size();
  const float* __restrict px = a.px.data();
  const float* __restrict py = a.py.data();
  const float* __restrict pz = a.pz.data();
  const float* __restrict err = a.errorLength.data();
  const float* __restrict nx = a.nx.data();
  const float* __restrict ny = a.ny.data();
  const float* __restrict nz = a.nz.data();
  const float* __restrict bx = a.bx.data();
  const float* __restrict by = a.by.data();
  const float* __restrict bz = a.bz.data();
  const float* __restrict gx = a.gx.data();
  const float* __restrict gy = a.gy.data();
  const float* __restrict gz = a.gz.data();
  const float* __restrict cnn = a.cosNsNg.data();
  const float* __restrict rr = a.rr.data();
  const float* __restrict rg = a.rg.data();
  const float* __restrict rb = a.rb.data();
  const float* __restrict fr = a.fr.data();
  const float* __restrict fg = a.fg.data();
  const float* __restrict fb = a.fb.data();
  for (size_t k = 0; k < n; ++k) {
    const float dx = px[k] - q.x, dy = py[k] - q.y, dz = pz[k] - q.z;
    const float dist2 = dx * dx + dy * dy + dz * dz;
    const float dist = std::sqrt(dist2);
    const float wx = dx / dist, wy = dy / dist, wz = dz / dist;
    // The gather point's f(wi).
    const float cs = wx * q.bx + wy * q.by + wz * q.bz;
    const float cg = wx * q.gx + wy * q.gy + wz * q.gz;
    float t = 1.0f;
    if constexpr (kTerminator) t = terminatorSmooth(cs, cg, q.cosNsNg);
    const float f0 = q.r * t, f1 = q.g * t, f2 = q.b * t;
    // The VPL's f(-wi).
    const float vx = -wx, vy = -wy, vz = -wz;
    const float vs = vx * bx[k] + vy * by[k] + vz * bz[k];
    const float vg = vx * gx[k] + vy * gy[k] + vz * gz[k];
    const float tvs = terminatorSmooth(vs, vg, cnn[k]);
    const float tv = cnn[k] > 0 ? tvs : 1.0f;
    const float v0 = rr[k] * tv, v1 = rg[k] * tv, v2 = rb[k] * tv;
    float G = std::abs(q.nx * wx + q.ny * wy + q.nz * wz) *
              std::abs(nx[k] * wx + ny[k] * wy + nz[k] * wz) / dist2;
    if constexpr (kClamp) G = std::min(G, q.clamp);
    const float cR = f0 * v0 * fr[k] * G, cG = f1 * v1 * fg[k] * G, cB = f2 * v2 * fb[k] * G;
    // Every test of the scalar loop, none of them short-circuited, applied as a bit mask (GCC
    // turns a condition used three times back into a branch).
    const bool ok = (dist > q.error + err[k]) & (dist2 > 0) & (cs > 0) & (cg > 0) & (vs > 0) &
                    (vg > 0) & (std::max(f0, std::max(f1, f2)) > 0) &
                    (std::max(v0, std::max(v1, v2)) > 0);
    const uint32_t mask = 0u - uint32_t(ok);
    outR[k] = std::bit_cast<float>(std::bit_cast<uint32_t>(cR) & mask);
    outG[k] = std::bit_cast<float>(std::bit_cast<uint32_t>(cG) & mask);
    outB[k] = std::bit_cast<float>(std::bit_cast<uint32_t>(cB) & mask);
  }
}

// A free function for target_clones: 8 VPLs per instruction where the CPU has AVX2 (the loops
// are inlined, so that each clone has its own).
}  // namespace

__attribute__((target_clones("avx2", "default"))) void lambertVplContributions(
    const VplArrays& a, const LambertGatherPoint& q, float* __restrict outR, float* __restrict outG,
    float* __restrict outB) {
  // terminatorShadowing is 1 where the normals' cosine is not positive.
  const bool terminator = q.cosNsNg > 0, clamp = q.clamp > 0;
  if (terminator && clamp)
    lambertVplLoop<true, true>(a, q, outR, outG, outB);
  else if (terminator)
    lambertVplLoop<true, false>(a, q, outR, outG, outB);
  else if (clamp)
    lambertVplLoop<false, true>(a, q, outR, outG, outB);
  else
    lambertVplLoop<false, false>(a, q, outR, outG, outB);
}

// ---------------------------------------------------------------------------------------------
// Gather: the VPLs' light at a point of Whitted's recursion
// ---------------------------------------------------------------------------------------------

Rgb InstantRadiosityIntegrator::gather(const SurfaceInteraction& si, const Bsdf& bsdf, float time,
                                       Sampler& sampler, RayCounters& counters) const {
  // Every VPL's unshadowed contribution first (see "Shadow rays by importance" in the header).
  struct Candidate {
    Rgb c;
    uint32_t vpl;
  };
  thread_local std::vector<Candidate> candidates;
  candidates.clear();
  double total = 0;
  const float pointError = length(si.pError);
  auto consider = [&](Rgb contribution, uint32_t k) {
    if (!(maxComponent(contribution) > 0) || !isFinite(contribution)) return;
    candidates.push_back({contribution, k});
    total += maxComponent(contribution);
  };
  // Lambert surfaces (often all the VPLs, and the gather point) skip the general BSDF
  // evaluation: the same values, from the side tests and the terminator term alone.
  const std::optional<Rgb> lambertHere = bsdf.lambertR();
  const size_t n = points_.size();
  if (lambertHere && allLambert_) {
    thread_local std::vector<float> c;
    c.resize(3 * n);
    const LambertGatherPoint q = *LambertGatherPoint::at(si, bsdf, clamp_);
    lambertVplContributions(points_, q, c.data(), c.data() + n, c.data() + 2 * n);
    for (uint32_t k = 0; k < n; ++k) consider({c[k], c[n + k], c[2 * n + k]}, k);
  } else {
    const VplArrays& a = points_;
    for (uint32_t k = 0; k < n; ++k) {
      const Vec3f d = Vec3f{a.px[k], a.py[k], a.pz[k]} - si.p;
      const float dist2 = dot(d, d);
      const float dist = std::sqrt(dist2);
      // The VPL is the shading point itself, as far as rounding can tell: G has no meaning.
      if (!(dist > pointError + a.errorLength[k]) || !(dist2 > 0)) continue;
      const Vec3f wi = d / dist;
      const Rgb f = lambertHere ? bsdf.lambertF(wi, *lambertHere) : bsdf.f(wi);
      if (!(maxComponent(f) > 0)) continue;
      const Rgb fVpl = a.lambert[k] ? Bsdf::lambertF(-wi, {a.bx[k], a.by[k], a.bz[k]},
                                                     {a.gx[k], a.gy[k], a.gz[k]}, a.cosNsNg[k] > 0,
                                                     {a.rr[k], a.rg[k], a.rb[k]})
                                    : vpls_[k].bsdf.f(-wi);
      if (!(maxComponent(fVpl) > 0)) continue;
      float G =
          std::abs(dot(si.ns, wi)) * std::abs(dot(Vec3f{a.nx[k], a.ny[k], a.nz[k]}, wi)) / dist2;
      if (clamp_ > 0) G = std::min(G, clamp_);
      consider(f * fVpl * Vec3f{a.fr[k], a.fg[k], a.fb[k]} * G, k);
    }
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
    if (scene_.accel().anyHit(shadow)) return {};
    if (!media_) return cand.c;
    const Rgb Tr = media_->transmittance(shadow, shadow.tMax, sampler);
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
