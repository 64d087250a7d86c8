// glint — instant radiosity (Keller 1997, "Instant Radiosity", SIGGRAPH '97): indirect light
// from virtual point lights (VPLs) left by a fixed set of light paths.
//
// Setup (the constructor, once per render): `vplPaths` light paths leave the lights. Path i
// takes its numbers from the Halton sequence's point i, one prime base per dimension (light
// choice by power, the ray's origin and direction from Light::sampleLe, then five per bounce:
// pass-through, BSDF direction (two), lobe, roulette). Halton points are stratified in every
// dimension for any prefix length, so a few dozen paths already cover the lights' emission
// evenly (Keller's argument: the VPL set is a quasi-Monte Carlo quadrature of the light's
// flux); each base's digits are shifted by a hash of (render seed, dimension, digit) (random
// digit scrambling), which keeps the stratification, breaks the correlation of neighbouring
// large bases at small indices, and gives another VPL set for another seed. Beyond the prime
// table the dimensions are hashed. The set depends only on the scene, the settings and the
// seed: never on the thread count.
//
// Every vertex where a path meets a surface with a diffuse or glossy lobe becomes a VPL: its
// flux (the path's power / vplPaths), the incoming direction, the full SurfaceInteraction and
// the BSDF made there, so the VPL reflects with the real BSDF f(wo_vpl, ·) towards a gather
// point (glossy VPLs included). Paths continue by BSDF sampling (flux transport: shading-
// normal correction, no 1/eta^2 at refractions) with Russian roulette from `rrDepth`, and pass
// through mirrors and glass without leaving a VPL there, so light focused by glass still
// lands as VPLs behind it. A VPL at light-path vertex k lights paths of k + 1 bounces, so VPLs
// are kept up to vertex maxDepth - 1 (maxDepth 1: direct light only).
//
// Gather (per camera sample): Whitted's integrator, which this one holds (renderer/whitted.h:
// emission seen directly, mirror and glass recursion up to maxDepth, pass-through of
// transparent surfaces, eyelight), lit by the VPLs too, which it asks for at every diffuse or
// glossy point as its IndirectLight (gather, below):
//   direct light: one sample of every light with a shadow ray (Whitted's directLight, so
//     area lights and the environment are included);
//   indirect light: sum over VPLs of f(x, wi) f_vpl(wo_vpl, -wi) G flux with a shadow ray
//     each, G = |cos_x| |cos_vpl| / d^2.
// A VPL closer to the shading point than their combined rounding-error bounds (d -> 0, the
// VPL *is* the point) is skipped: G would be infinite or NaN there, and the light it stands
// for is already in the point's own emission and direct light.
//
// Clamping (`vplClamp` > 0): G is replaced by min(G, vplClamp). Unclamped, G's 1/d^2 makes
// bright splotches around VPLs near corners and contact points; clamping removes them at the
// price of bias: the energy of short VPL connections is lost (corners and creases come out too
// dark), never added. G is in 1/length^2, so the bound depends on the scene's scale: a bound
// of about 1 / (0.1 x scene size)^2 to 1 / (0.05 x scene size)^2 (for a box of size 1: 100 to
// 400) removes the splotches and loses a few percent; a bound below 1 / scene size^2 darkens
// all indirect light. Measured by benchmarks/vpl_bench on the Cornell box (2 wide, 1024 paths,
// image mean against unclamped): bound 100 loses 0.2%, bound 10 loses 1.0%; the unit tests
// check that clamping never brightens a pixel.
//
// Shadow rays by importance (`vplShadowShare` s > 0; Ward's adaptive shadow testing, 1991, in
// its unbiased form): at a point, every VPL's unshadowed contribution c_i is computed first
// (cheap: two BSDF values and G). A VPL with lum(c_i) >= s * sum lum(c) gets a shadow ray; each
// of the others is tested with probability p_i = lum(c_i) / (s * sum) < 1 and, when visible,
// counts c_i / p_i. The tested ones are picked by systematic sampling over the running sum of
// the p_i with one uniform number per point, so each VPL is picked with exactly its p_i (the
// estimate is unbiased) and the small ones together cost about sum p_i <= 1/s rays instead of
// one each. The noise added is at most s times the point's VPL light per pick; s = 0 tests
// every VPL.
//
// Cost: without that selection every lit camera hit traces one shadow ray per VPL (about 3.5
// VPLs per path in a box of albedo 0.7), so time grows linearly with vplPaths; the error falls
// roughly as 1/paths (vpl_bench: RMSE 0.094, 0.038, 0.015, 0.009 for 16, 64, 256, 1024 paths).
// Without Feature::Shadows (no light casts shadows) VPLs, like the lights, shine through walls.
//
// Participating media are rendered as the Whitted integrator renders them (emission and single
// scattering of the lights along camera and secondary rays). VPL light is attenuated by the
// media it crosses, both along the light paths (each segment's transmittance weights the
// path) and along the VPL shadow rays, but it does not scatter in them: VPLs stand only on
// surfaces. Fog therefore dims indirect light correctly but shows no in-scattered glow from it
// (the path tracer's multiple scattering has that).
//
// Not handled: motion (light paths are traced at shutter open,
// time 0), and light that reaches a diffuse point by a mirror after the gather point's own
// bounce (caustics seen on diffuse surfaces from the camera side): VPLs stand only on
// non-delta surfaces. `auto` never picks this integrator: its bias and splotches are a
// choice the scene should make.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "renderer/integrator.h"
#include "renderer/whitted.h"

namespace glint {

// One virtual point light: where a light path left power on a surface.
struct Vpl {
  SurfaceInteraction si;  // the surface there; si.wo points back along the light path (its
                          // objectFromWorld is cleared: the BSDF needs no textures)
  Bsdf bsdf;              // the surface's BSDF there, with wo = si.wo
  Rgb flux;               // the path's power there, divided by the number of paths
  int vertex = 1;         // which vertex of its light path (1: the first surface hit)
};

// The VPLs as the gather loop reads them, one array per quantity, so that where the gather
// point and every VPL are Lambert surfaces the loop runs several VPLs per instruction
// (InstantRadiosityIntegrator::gather).
struct VplArrays {
  std::vector<float> px, py, pz;   // si.p
  std::vector<float> errorLength;  // length(si.pError)
  std::vector<float> nx, ny, nz;   // si.ns
  std::vector<float> bx, by, bz;   // the BSDF's shading normal
  std::vector<float> gx, gy, gz;   // the BSDF's geometric normal
  // dot(BSDF shading normal, geometric normal) where the BSDF applies the terminator term,
  // else 0 (terminatorShadowing is 1 wherever this is not positive)
  std::vector<float> cosNsNg;
  std::vector<float> rr, rg, rb;  // Bsdf::lambertR (0 for other BSDFs)
  std::vector<float> fr, fg, fb;  // flux
  std::vector<uint8_t> lambert;   // Bsdf::lambertR exists
  void add(const Vpl& v);
  size_t size() const { return px.size(); }
};

// A Lambert gather point (Bsdf::lambertR), as lambertVplContributions reads it.
struct LambertGatherPoint {
  float x, y, z, error;  // si.p, length(si.pError)
  float nx, ny, nz;      // si.ns
  float bx, by, bz;      // its BSDF's shading normal
  float gx, gy, gz;      // its BSDF's geometric normal
  float cosNsNg;         // as VplArrays::cosNsNg
  float r, g, b;         // Bsdf::lambertR
  float clamp;           // the bound on G (0: none)
  // Null when `bsdf` is not a Lambert BSDF.
  static std::optional<LambertGatherPoint> at(const SurfaceInteraction& si, const Bsdf& bsdf,
                                              float clamp);
};

// The unshadowed light every VPL of `vpls` (all of them Lambert) sends to the Lambert gather
// point `q`, per channel into out*[k]: f(wi) fVpl(-wi) flux G, G bounded by q.clamp, exactly
// the values the general evaluation (Bsdf::f at both ends) gives, 0 where it gives nothing
// (wrong side, the VPL at the point itself). Several VPLs per instruction.
void lambertVplContributions(const VplArrays& vpls, const LambertGatherPoint& q, float* outR,
                             float* outG, float* outB);

// Whitted's integrator (renderer/whitted.h: direct light, emission, mirror and glass
// recursion) with the light of every VPL added at diffuse and glossy points: the VPLs are the
// IndirectLight of the Whitted integrator it holds.
class InstantRadiosityIntegrator final : public Integrator, private IndirectLight {
 public:
  // Traces the light paths (settings.vplPaths, seeded by `seed`). Throws InputError when
  // vplPaths <= 0.
  InstantRadiosityIntegrator(const RenderScene& scene, const IntegratorSettings& settings,
                             uint64_t seed = 0);
  Rgb LiFromHit(const Ray& ray, const Hit* hit, Sampler& sampler, RayCounters& counters,
                PathAovs& aovs) const override {
    return whitted_.LiFromHit(ray, hit, sampler, counters, aovs);
  }

  // The VPLs the light paths left.
  const std::vector<Vpl>& vpls() const { return vpls_; }
  // Rays traced to build them (light paths' segments).
  uint64_t lightPathRays() const { return lightPathRays_; }
  // vpl_paths, vpls, vpl_clamp, light_path_rays.
  std::vector<SetupStat> setupStats() const override;

 private:
  // Traces the light paths and keeps their VPLs.
  void traceLightPaths(int paths, uint64_t seed);
  // The light every VPL sends to `si`, with shadow rays (Whitted asks at diffuse and glossy
  // points). Draws one sampler dimension.
  Rgb gather(const SurfaceInteraction& si, const Bsdf& bsdf, float time, Sampler& sampler,
             RayCounters& counters) const override;

  int maxDepth_, rrDepth_;
  int paths_;                // light paths traced
  float clamp_;              // bound on G; 0 = none
  float shadowShare_;        // IntegratorSettings::vplShadowShare
  bool shadows_;             // some light casts shadows (Feature::Shadows): VPLs do too
  const MediaScene* media_;  // the scene's media when it has them (Feature::Volumes), else null
  std::vector<Vpl> vpls_;
  // What the gather loop reads of each VPL, one array per quantity (VplArrays): built from
  // vpls_ once the light paths are traced.
  VplArrays points_;
  bool allLambert_ = false;  // every VPL's BSDF is Lambert (Bsdf::lambertR)
  uint64_t lightPathRays_ = 0;
  // The camera paths: Whitted's recursion, lit by gather() as well. It only keeps a pointer to
  // this object, whose VPLs the constructor's body traces before any render.
  WhittedIntegrator whitted_;
};

// The scrambled radical inverse of `index` in `base` (a prime), its digits shifted by a hash of
// (`scramble`, digit position): a point of a scrambled Halton sequence's coordinate, in [0, 1).
float scrambledRadicalInverse(uint32_t base, uint64_t index, uint64_t scramble);

}  // namespace glint
