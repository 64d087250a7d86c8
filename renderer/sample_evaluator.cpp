// glint — a pixel's samples evaluated (see sample_evaluator.h).
#include "renderer/sample_evaluator.h"

namespace glint {

SampleEvaluator::SampleEvaluator(const RenderScene& scene, const Integrator& integrator,
                                 const RenderSettings& settings)
    : scene_(scene),
      integrator_(integrator),
      filter_(settings.filter),
      seed_(settings.seed),
      aovs_(settings.aovs) {
  // The camera decides whether there is a lens to sample (the scene builder reports it as
  // Feature::Lens); time is sampled only when the builder found something moving. Neither, on
  // a static pinhole: the pinhole rays of before, with no per-ray test.
  const bool lens = scene.camera().hasLens();
  const bool motion = scene.features().has(Feature::MotionBlur);
  if (!lens && !motion)
    cameraRays_ = scene.camera().isStaticPinhole() ? CameraRays::Pinhole : CameraRays::Generic;
  else
    cameraRays_ = !motion ? CameraRays::Lens
                  : !lens ? CameraRays::Motion
                          : CameraRays::LensAndMotion;
}

PixelKeys SampleEvaluator::keys(int x, int y) const {
  PixelKeys k;
  k.x = x, k.y = y;
  k.key = pixelSampleKey(seed_, size_t(y) * size_t(scene_.camera().width()) + size_t(x));
  k.film = DimensionSeeds(k.key, kFilmDimension);
  if (cameraRays_ == CameraRays::Lens || cameraRays_ == CameraRays::LensAndMotion)
    k.lens = DimensionSeeds(k.key, kLensDimension);
  return k;
}

namespace {

// The shutter times of samples first .. first + n - 1 of a pixel: a 1D Owen-scrambled Sobol
// dimension, stratified over the pixel's samples. Flattened so that Sampler::get1D is inlined
// and its dimension's hash, the same for every sample, is computed once.
[[gnu::flatten]] void shutterTimes(uint64_t pixelKey, uint32_t first, uint32_t n, float* time) {
  for (uint32_t i = 0; i < n; ++i) time[i] = Sampler(pixelKey, first + i, kTimeDimension).get1D();
}

}  // namespace

template <bool kLens, bool kMotion>
void SampleEvaluator::sampledRays(const PixelKeys& pixel, uint32_t first, uint32_t n,
                                  const float* filmX, const float* filmY, Ray* rays) const {
  uint32_t lx[kCameraBatch], ly[kCameraBatch];
  if constexpr (kLens) sample2DFractionBatch(first, n, pixel.lens, lx, ly);
  float time[kCameraBatch];
  if constexpr (kMotion) shutterTimes(pixel.key, first, n, time);
  for (uint32_t i = 0; i < n; ++i) {
    CameraSample cs;
    cs.pFilm = {filmX[i], filmY[i]};
    if constexpr (kLens) cs.pLens = Fraction2{lx[i], ly[i]}.toFloat();
    if constexpr (kMotion) cs.time = time[i];
    rays[i] = scene_.camera().generateRay(cs);
  }
}

void SampleEvaluator::evaluate(const PixelKeys& pixel, uint32_t n, bool centre, Batch& batch,
                               PixelSums& sums, SampleTally& tally) const {
  const uint32_t first = sums.taken;
  // The places on the film: drawn from the filter around the pixel's centre, or the centre.
  float filmX[kCameraBatch], filmY[kCameraBatch];
  if (centre) {
    for (uint32_t i = 0; i < n; ++i)
      filmX[i] = float(pixel.x) + 0.5f, filmY[i] = float(pixel.y) + 0.5f;
  } else {
    uint32_t fx[kCameraBatch], fy[kCameraBatch];
    sample2DFractionBatch(first, n, pixel.film, fx, fy);
    for (uint32_t i = 0; i < n; ++i) {
      const Vec2f offset = filter_.sampleOffsetFraction({fx[i], fy[i]});
      filmX[i] = float(pixel.x) + 0.5f + offset.x, filmY[i] = float(pixel.y) + 0.5f + offset.y;
    }
  }
  switch (cameraRays_) {
    case CameraRays::Pinhole:
      scene_.camera().pinholeRays(filmX, filmY, int(n), batch.rays);
      break;
    case CameraRays::Generic:
      sampledRays<false, false>(pixel, first, n, filmX, filmY, batch.rays);
      break;
    case CameraRays::Lens:
      sampledRays<true, false>(pixel, first, n, filmX, filmY, batch.rays);
      break;
    case CameraRays::Motion:
      sampledRays<false, true>(pixel, first, n, filmX, filmY, batch.rays);
      break;
    case CameraRays::LensAndMotion:
      sampledRays<true, true>(pixel, first, n, filmX, filmY, batch.rays);
      break;
  }
  scene_.accel().closestHits(batch.rays, batch.found, int(n));
  tally.rays.camera += n;
  if (aovs_)
    shade<true>(pixel, n, batch, sums, tally);
  else
    shade<false>(pixel, n, batch, sums, tally);
}

template <bool kAovs>
void SampleEvaluator::shade(const PixelKeys& pixel, uint32_t n, const Batch& batch, PixelSums& sums,
                            SampleTally& tally) const {
  // The sums in a local while the integrator runs: it is called through a pointer, and the
  // compiler would otherwise store them back around every call.
  PixelSums s = sums;
  const uint32_t first = s.taken;
  for (uint32_t i = 0; i < n; ++i) {
    Sampler sampler(pixel.key, first + i, kIntegratorDimension);
    PathAovs aovs;
    aovs.wanted = kAovs;
    const Rgb L = cameraRadiance(integrator_, batch.rays[i], batch.found[i], sampler, tally.rays,
                                 aovs, &tally.checks);
    if constexpr (kAovs)
      s.add(L, aovs);
    else
      s.add(L, aovs.hit);
  }
  sums = s;
}

}  // namespace glint
