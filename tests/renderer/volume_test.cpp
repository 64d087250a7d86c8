// Participating media: transmittance and emission against closed forms, single scattering
// against a numerically integrated reference, and rendered scenes (density 0, a volumetric
// shadow, scenes without media).
#include "renderer/volume.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "geometry/shapes/box.h"
#include "geometry/shapes/sphere.h"
#include "materials/phase.h"
#include "renderer/render.h"
#include "scenes/build.h"

namespace glint {
namespace {

std::unique_ptr<Medium> makeMedium(Rgb sigmaA, Rgb sigmaS, Rgb Le, float g,
                                   std::unique_ptr<DensityField> density) {
  auto m = std::make_unique<Medium>();
  m->sigmaA = sigmaA, m->sigmaS = sigmaS, m->Le = Le, m->g = g;
  m->density = std::move(density);
  return m;
}

IntegratorSettings settingsFor(const std::string& estimator, const std::string& volume = "single",
                               float step = 0) {
  IntegratorSettings s;
  s.volumeEstimator = estimator;
  s.volume = volume;
  s.volumeStep = step;
  return s;
}

// A slab |x| <= 1 (a box, as large as needed in y and z), crossed along +x from x = -3.
const Ray kAcross{{-3, 0.1f, 0.2f}, {2, 0, 0}};  // |d| = 2: t and distance differ
constexpr float kSlab = 2;                       // thickness crossed

void addSlab(MediaScene* media, std::unique_ptr<Medium> m) {
  media->addRegion(std::move(m), std::make_unique<Box>(Vec3f{-1, -5, -5}, Vec3f{1, 5, 5}),
                   Transform());
}

// Mean and standard error of `n` samples of f(sampler).
template <class F>
std::pair<Rgb, Rgb> meanAndError(int n, F&& f) {
  Rgb sum, sum2;
  for (int i = 0; i < n; ++i) {
    Sampler sampler(mixBits(uint64_t(i) + 12345), 0);
    Rgb v = f(sampler);
    sum += v, sum2 += v * v;
  }
  Rgb mean = sum / float(n);
  Rgb var = max(Rgb{}, sum2 / float(n) - mean * mean);
  return {mean, Rgb{std::sqrt(var.x), std::sqrt(var.y), std::sqrt(var.z)} / std::sqrt(float(n))};
}

// A segment's first numbers as the path tracer draws them from a pixel's dimensions.
SegmentSamples segmentSamples(Sampler& sampler, bool wholeSegmentEmission = false) {
  SegmentSamples first;
  const Vec2f u = sampler.get2D();
  first.flight = u.x, first.event = u.y, first.jitter = sampler.get1D();
  first.wholeSegmentEmission = wholeSegmentEmission;
  return first;
}

// Density nodes 0.5 apart along x across the slab (x fastest in a 5 x 2 x 2 GridDensity over
// the slab's box, the same across y and z): it varies under its majorant of 1.
constexpr float kSlabNodes[5] = {1, 0.2f, 0.6f, 0.1f, 0.8f};
std::vector<float> varyingSlabValues() {
  std::vector<float> values;
  for (int k = 0; k < 4; ++k)
    for (float v : kSlabNodes) values.push_back(v);
  return values;
}

// ---------------------------------------------------------------------------------------------
// Transmittance
// ---------------------------------------------------------------------------------------------

TEST(Volume, HomogeneousSlabTransmittanceIsExactlyExponential) {
  const Rgb sigmaA{0.1f, 0.3f, 0.6f}, sigmaS{0.2f, 0.2f, 0.1f};
  for (const char* estimator : {"march", "track"}) {
    MediaScene media(settingsFor(estimator));
    addSlab(&media, makeMedium(sigmaA, sigmaS, {}, 0, std::make_unique<ConstantDensity>(1.5f)));
    Sampler sampler(1, 0);
    const Rgb T = media.transmittance(kAcross, kInfinity, sampler);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(T[c], std::exp(-(sigmaA[c] + sigmaS[c]) * 1.5f * kSlab), 1e-6f) << estimator;
    // Analytic: no random numbers used.
    EXPECT_EQ(sampler.dimension(), 0u);
    // A segment ending inside the slab (t = 1.75: x = 0.5) crosses 1.5 units of it.
    const Rgb Tpart = media.transmittance(kAcross, 1.75f, sampler);
    EXPECT_NEAR(Tpart.x, std::exp(-0.3f * 1.5f * 1.5f), 1e-6f);
  }
}

TEST(Volume, SegmentsMissingTheRegionTransmitEverything) {
  MediaScene media(settingsFor("march"));
  addSlab(&media, makeMedium({1, 1, 1}, {}, {}, 0, std::make_unique<ConstantDensity>(1)));
  Sampler sampler(1, 0);
  EXPECT_EQ(media.transmittance(kAcross, 0.9f, sampler), (Rgb{1, 1, 1}));  // ends at x = -1.2
  const Ray away{{-3, 0, 0}, {-1, 0, 0}};
  EXPECT_EQ(media.transmittance(away, kInfinity, sampler), (Rgb{1, 1, 1}));
}

// A grid of constant values takes the heterogeneous code paths with a known answer.
std::unique_ptr<DensityField> constantGrid(float value) {
  return std::make_unique<GridDensity>(3, 2, 4, std::vector<float>(24, value),
                                       Bounds3f{{-1, -5, -5}, {1, 5, 5}});
}

TEST(Volume, HeterogeneousEstimatorsMatchTheExponential) {
  const float sigmaT = 0.7f, density = 0.8f;
  const float exact = std::exp(-sigmaT * density * kSlab);
  {
    // Marching a constant field sums equal steps: exact up to rounding.
    MediaScene media(settingsFor("march"));
    addSlab(&media,
            makeMedium({0.3f, 0.3f, 0.3f}, {0.4f, 0.4f, 0.4f}, {}, 0, constantGrid(density)));
    Sampler sampler(1, 0);
    EXPECT_NEAR(media.transmittance(kAcross, kInfinity, sampler).y, exact, 1e-5f);
  }
  // Ratio tracking is unbiased: the mean over many samples, within 4 standard errors.
  for (bool grid : {true, false}) {
    MediaScene media(settingsFor("track"));
    // A noise field of threshold 0 is a heterogeneous field; scale it to the same answer only
    // for the grid. The noise case is compared with marching at a fine step below.
    addSlab(&media, makeMedium({0.3f, 0.3f, 0.3f}, {0.4f, 0.4f, 0.4f}, {}, 0,
                               grid ? constantGrid(density)
                                    : std::make_unique<NoiseDensity>(1.3f, 4, 0.2f, 7)));
    auto [mean, error] =
        meanAndError(20000, [&](Sampler& s) { return media.transmittance(kAcross, kInfinity, s); });
    float expected = exact;
    if (!grid) {
      MediaScene fine(settingsFor("march", "single", 0.001f));
      addSlab(&fine, makeMedium({0.3f, 0.3f, 0.3f}, {0.4f, 0.4f, 0.4f}, {}, 0,
                                std::make_unique<NoiseDensity>(1.3f, 4, 0.2f, 7)));
      Sampler s(3, 0);
      expected = fine.transmittance(kAcross, kInfinity, s).y;
      EXPECT_GT(expected, exact);  // the thresholded noise is thinner than density 0.8
      EXPECT_LT(expected, 1);
    }
    EXPECT_NEAR(mean.y, expected, 4 * error.y + 1e-4f) << (grid ? "grid" : "noise");
    EXPECT_GT(error.y, 0);
  }
}

TEST(Volume, OverlappingRegionsAddTheirCoefficients) {
  MediaScene media(settingsFor("march"));
  addSlab(&media, makeMedium({0.2f, 0.2f, 0.2f}, {}, {}, 0, std::make_unique<ConstantDensity>(1)));
  addSlab(&media, makeMedium({0.5f, 0.5f, 0.5f}, {}, {}, 0, std::make_unique<ConstantDensity>(1)));
  Sampler sampler(1, 0);
  EXPECT_NEAR(media.transmittance(kAcross, kInfinity, sampler).x, std::exp(-0.7f * kSlab), 1e-6f);
}

// ---------------------------------------------------------------------------------------------
// Emission
// ---------------------------------------------------------------------------------------------

TEST(Volume, EmissionOnlyHomogeneousSegmentMatchesClosedForm) {
  const Rgb sigmaA{0.5f, 1.0f, 0.0f}, Le{2, 3, 4};
  const float density = 1.2f;
  RenderScene noLights;
  RayCounters counters;
  for (const char* estimator : {"march", "track"}) {
    MediaScene media(settingsFor(estimator, "emission"));
    addSlab(&media, makeMedium(sigmaA, {0.1f, 0.1f, 0.1f}, Le, 0,
                               std::make_unique<ConstantDensity>(density)));
    Sampler sampler(1, 0);
    VolumeSegment seg = media.integrate(noLights, kAcross, kInfinity, sampler, counters);
    for (int c = 0; c < 3; ++c) {
      const float st = (sigmaA[c] + 0.1f) * density;
      const float exact = Le[c] * density / st * (1 - std::exp(-st * kSlab));
      EXPECT_NEAR(seg.L[c], exact, 1e-5f * exact) << estimator << " channel " << c;
      EXPECT_NEAR(seg.T[c], std::exp(-st * kSlab), 1e-6f);
    }
  }
}

TEST(Volume, HeterogeneousEmissionConvergesToTheSameAnswer) {
  // The constant grid through the marching and tracking paths (emission mode).
  const float sigmaT = 0.6f, Le = 2;
  const float exact = Le / sigmaT * (1 - std::exp(-sigmaT * kSlab));
  RenderScene noLights;
  RayCounters counters;
  MediaScene march(settingsFor("march", "emission"));
  addSlab(&march, makeMedium({sigmaT, sigmaT, sigmaT}, {}, {Le, Le, Le}, 0, constantGrid(1)));
  Sampler s(1, 0);
  EXPECT_NEAR(march.integrate(noLights, kAcross, kInfinity, s, counters).L.x, exact, 1e-4f);
  MediaScene track(settingsFor("track", "emission"));
  addSlab(&track, makeMedium({sigmaT, sigmaT, sigmaT}, {}, {Le, Le, Le}, 0, constantGrid(1)));
  auto [mean, error] = meanAndError(20000, [&](Sampler& sampler) {
    return track.integrate(noLights, kAcross, kInfinity, sampler, counters).L;
  });
  EXPECT_NEAR(mean.x, exact, 4 * error.x + 1e-4f);
}

// ---------------------------------------------------------------------------------------------
// Single scattering
// ---------------------------------------------------------------------------------------------

// A scene with one point light and nothing else to hit (a small far-away quad keeps the
// geometry non-empty), and a homogeneous medium in the box [-1, 1]^3.
struct LitMedium {
  SceneDescription desc;
  RenderScene scene;
  static constexpr float kSigmaA = 0.2f, kSigmaS = 0.5f, kG = 0.3f, kI = 10;
  static constexpr Vec3f kLight{0.3f, 2, 0};

  explicit LitMedium(const std::string& estimator, float step) {
    MeshDesc m;
    m.positions = {{100, 100, 100}, {101, 100, 100}, {100, 101, 100}};
    m.indices = {0, 1, 2};
    desc.meshes.push_back(m);
    desc.instances.push_back({0, Transform(), "far", {}});
    LightDesc light;
    light.type = LightType::Point;
    light.intensity = kI;
    light.worldFromLight = Transform::translate(kLight);
    desc.lights.push_back(light);
    MediumDesc medium;
    medium.region = MediumDesc::Region::Shape;
    medium.shape = std::make_shared<Box>(Vec3f{-1, -1, -1}, Vec3f{1, 1, 1});
    medium.sigmaA = {kSigmaA, kSigmaA, kSigmaA};
    medium.sigmaS = {kSigmaS, kSigmaS, kSigmaS};
    medium.g = kG;
    desc.media.push_back(medium);
    desc.render.integrator.volumeEstimator = estimator;
    desc.render.integrator.volumeStep = step;
    scene = buildRenderScene(desc);
  }

  // The reference by Simpson's rule along the ray inside the box.
  static double reference(const Ray& ray) {
    const double st = kSigmaA + kSigmaS;
    // The ray runs along +x at (y, z) inside the box, from x = -1 to 1.
    const double y = ray.o.y, z = ray.o.z;
    auto f = [&](double x) {
      const double dx = kLight.x - x, dy = kLight.y - y, dz = kLight.z - z;
      const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
      // The shadow ray leaves the box at y = 1: the part of it below y = 1.
      const double inside = r * (1 - y) / dy;
      const double cosTheta = dx / r;  // dot(towards the light, ray direction +x)
      return std::exp(-st * (x + 1)) * kSigmaS * henyeyGreenstein(float(cosTheta), kG) * kI /
             (r * r) * std::exp(-st * inside);
    };
    const int n = 20000;
    const double h = 2.0 / n;
    double sum = f(-1) + f(1);
    for (int i = 1; i < n; ++i) sum += f(-1 + i * h) * (i % 2 ? 4 : 2);
    return sum * h / 3;
  }
};

TEST(Volume, SingleScatteringMatchesNumericalIntegration) {
  const Ray ray{{-4, 0.2f, -0.3f}, {1, 0, 0}};
  const double exact = LitMedium::reference(ray);
  ASSERT_GT(exact, 0.01);
  {
    LitMedium lit("march", 0.002f);
    ASSERT_TRUE(lit.scene.features().has(Feature::Volumes));
    RayCounters counters;
    auto [mean, error] = meanAndError(64, [&](Sampler& s) {
      return lit.scene.media()->integrate(lit.scene, ray, kInfinity, s, counters).L;
    });
    EXPECT_NEAR(mean.y, exact, 0.005 * exact);
    EXPECT_GT(counters.shadow, 0u);
  }
  {
    LitMedium lit("track", 0);
    RayCounters counters;
    auto [mean, error] = meanAndError(40000, [&](Sampler& s) {
      return lit.scene.media()->integrate(lit.scene, ray, kInfinity, s, counters).L;
    });
    EXPECT_NEAR(mean.y, exact, 4 * error.y + 0.002 * exact);
  }
}

TEST(Volume, DeltaTrackingScattersWithTheRightProbability) {
  // Grey homogeneous slab. Absorption is weighed, not sampled, where the medium scatters: every
  // real collision scatters, P(scatter before leaving) = 1 - exp(-sigma_t d), with the weight
  // sigma_s / sigma_t, so the expected weight of scattering is sigma_s / sigma_t (1 -
  // exp(-sigma_t d)) as for the analogue tracker; paths that leave carry exactly 1. Without
  // scattering (sigma_s = 0) absorption still ends paths.
  const float sa = 0.3f, ss = 0.6f;
  for (float sigmaS : {ss, 0.0f}) {
    SCOPED_TRACE(sigmaS);
    const float sigmaT = sa + sigmaS;
    MediaScene media(settingsFor("track"));
    addSlab(&media, makeMedium({sa, sa, sa}, {sigmaS, sigmaS, sigmaS}, {}, 0.4f,
                               std::make_unique<ConstantDensity>(1)));
    const int n = 100000;
    int scattered = 0, passed = 0, absorbed = 0;
    for (int i = 0; i < n; ++i) {
      Sampler s(mixBits(uint64_t(i)), 0);
      MediumEvent e = media.sampleScattering(kAcross, kInfinity, s);
      if (e.scattered) {
        ++scattered;
        EXPECT_NEAR(e.weight.x, sigmaS / sigmaT, 1e-5f);
        EXPECT_EQ(e.g, 0.4f);
        EXPECT_GE(e.t, 1.0f);  // inside the slab: x in [-1, 1] is t in [1, 2]
        EXPECT_LE(e.t, 2.0f);
      } else if (e.weight.x > 0) {
        EXPECT_NEAR(e.weight.x, 1, 1e-5f);
        ++passed;
      } else {
        ++absorbed;
      }
    }
    const double pPass = std::exp(-sigmaT * kSlab);
    const double pScatter = sigmaS > 0 ? 1 - pPass : 0;
    EXPECT_NEAR(double(scattered) / n, pScatter, 4 * std::sqrt(pScatter * (1 - pScatter) / n));
    EXPECT_NEAR(double(passed) / n, pPass, 4 * std::sqrt(pPass * (1 - pPass) / n));
    if (sigmaS > 0) {
      EXPECT_EQ(absorbed, 0);
    } else {
      EXPECT_NEAR(double(absorbed) / n, 1 - pPass, 4 * std::sqrt(pPass * (1 - pPass) / n));
    }
  }
}

// Emission that varies along the ray independently of the density (a fire's temperature in
// soot), gathered by delta tracking (the path tracer's estimator): the mean over paths of the
// emitted estimate is the integral of T(t) emission(t) dt up to the absorption or the exit.
// The density is a constant grid, so the medium takes the heterogeneous tracker; sigma_t is
// grey and scattering-free, so every path is absorbed or passes with weight 1.
class RampEmission final : public EmissionField {
 public:
  Rgb emission(Vec3f p) const override {
    const float e = 3 * std::max(0.0f, p.x + 1);  // 0 at the slab's entry, 6 at its exit
    return {e, 0.5f * e, 0.25f * e};
  }
};

TEST(Volume, DeltaTrackingGathersEmissionThatVariesWithoutTheDensity) {
  for (float sigmaA : {0.05f, 0.8f, 4.0f}) {  // thin soot to dense smoke
    MediaScene media(settingsFor("track"));
    auto m = makeMedium({sigmaA, sigmaA, sigmaA}, {}, {}, 0, constantGrid(1));
    m->emissionField = std::make_unique<RampEmission>();
    addSlab(&media, std::move(m));
    // The integral over the slab's thickness by Simpson's rule: T = exp(-sigma_a x), x from
    // the entry, and emission 3 x.
    const int n = 2000;
    double exact = 0;
    for (int i = 0; i <= n; ++i) {
      const double x = kSlab * i / n;
      exact += (i == 0 || i == n ? 1 : i % 2 ? 4 : 2) * std::exp(-sigmaA * x) * 3 * x;
    }
    exact *= kSlab / n / 3;
    auto [mean, error] = meanAndError(40000, [&](Sampler& sampler) {
      Rgb emitted;
      const MediumEvent e =
          media.sampleScatteringAndEmission(kAcross, kInfinity, sampler, &emitted);
      EXPECT_FALSE(e.scattered);
      return emitted;
    });
    EXPECT_NEAR(mean.x, exact, 4 * error.x + 1e-4) << "sigma_a " << sigmaA;
    EXPECT_NEAR(mean.z, 0.25 * exact, 4 * error.z + 1e-4) << "sigma_a " << sigmaA;
    // The spread per path, in thin soot: weighing emission / sigma_a at collisions of rate
    // sigma_a had the variance of that compound Poisson sum, the integral of emission^2 /
    // sigma_a (about 3.9 x the mean here); the track-length estimator's must stay far below.
    if (sigmaA < 0.1f) {
      const double collisionSpread = std::sqrt(9 * std::pow(kSlab, 3) / 3 / sigmaA);
      EXPECT_LT(error.x * std::sqrt(40000.0), 0.25 * collisionSpread) << collisionSpread;
    }
  }
}

// The same with coloured extinction, which spectral MIS tracks (heroTrack): each channel's
// mean is its own integral of exp(-sigma_t,c x) emission_c(x), in strongly coloured and in
// thin soot, with and without scattering (absorption weighed where the medium scatters, so
// nothing is absorbed then). In thin soot without scattering one path's spread stays below
// 1.5x the mean: the track-length estimator with the MIS weight where each sample lies, where
// weighing the emission at the collisions had 3.4x.
TEST(Volume, SpectralMisGathersEmissionPerChannel) {
  const Rgb strong{0.05f, 0.8f, 2.5f}, thin{0.02f, 0.05f, 0.1f};
  for (const Rgb& sigmaA : {strong, thin})
    for (float sigmaS : {0.0f, 0.6f}) {
      SCOPED_TRACE(testing::Message() << "sigma_a " << sigmaA.x << " sigma_s " << sigmaS);
      MediaScene media(settingsFor("track"));
      auto m = makeMedium(sigmaA, {sigmaS, sigmaS, sigmaS}, {}, 0.3f, constantGrid(1));
      m->emissionField = std::make_unique<RampEmission>();
      addSlab(&media, std::move(m));
      Rgb exact;
      const int n = 2000;
      for (int c = 0; c < 3; ++c) {
        const double sigmaT = sigmaA[c] + sigmaS;
        double sum = 0;
        for (int i = 0; i <= n; ++i) {
          const double x = kSlab * i / n;
          sum += (i == 0 || i == n ? 1 : i % 2 ? 4 : 2) * std::exp(-sigmaT * x) * 3 * x;
        }
        exact[c] = float(sum * kSlab / n / 3) * (c == 0 ? 1.0f : c == 1 ? 0.5f : 0.25f);
      }
      int scattered = 0;
      auto [mean, error] = meanAndError(40000, [&](Sampler& sampler) {
        Rgb emitted;
        const MediumEvent e =
            media.sampleScatteringAndEmission(kAcross, kInfinity, sampler, &emitted);
        if (e.scattered) ++scattered;
        return emitted;
      });
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(mean[c], exact[c], 4 * error[c] + 1e-4) << "channel " << c;
        if (sigmaS == 0 && sigmaA.z < 0.5f) {
          EXPECT_LT(error[c] * std::sqrt(40000.0), 1.5 * exact[c]) << "channel " << c;
        }
      }
      if (sigmaS == 0) {
        EXPECT_EQ(scattered, 0);
      } else {
        EXPECT_GT(scattered, 1000);
      }
    }
}

// A segment's first numbers from a pixel's stratified dimensions (SegmentSamples), as the path
// tracer passes them: the emission a ray gathers before it collides keeps its mean, and a
// pixel's 64 samples of it spread far less than with every number from the tracking stream
// (where the segment collides is what varied most in the fire of scenes/volumes).
class UniformEmission final : public EmissionField {
 public:
  Rgb emission(Vec3f) const override { return {2, 2, 2}; }
};

TEST(Volume, SegmentSamplesStratifyWhereTheSegmentCollides) {
  // A constant density grid (the heterogeneous tracker, no null collisions) glowing evenly:
  // a ray gathers 2 x the distance to its collision, so where it collides is all that varies.
  const float sigma = 0.4f;  // sigma_a = sigma_s: half the collisions' weight scatters
  MediaScene media(settingsFor("track"));
  auto m = makeMedium({sigma, sigma, sigma}, {sigma, sigma, sigma}, {}, 0, constantGrid(1));
  m->emissionField = std::make_unique<UniformEmission>();
  addSlab(&media, std::move(m));
  const double sigmaT = 2 * sigma;
  const double exact = 2 * (1 - std::exp(-sigmaT * kSlab)) / sigmaT;
  const int pixels = 400, spp = 64;
  for (bool stratified : {false, true}) {
    SCOPED_TRACE(stratified);
    double sum = 0, sum2 = 0, pixelSum2 = 0;
    for (int p = 0; p < pixels; ++p) {
      double pixel = 0;
      for (int i = 0; i < spp; ++i) {
        Sampler sampler(mixBits(uint64_t(p) + 777), uint32_t(i));
        Sampler tracker(mixBits(uint64_t(p * spp + i) ^ 0x5bd1e995u), 0);
        const SegmentSamples first = segmentSamples(sampler);
        Rgb emitted;
        media.sampleScatteringAndEmission(kAcross, kInfinity, tracker, &emitted, nullptr,
                                          stratified ? &first : nullptr);
        sum += emitted.x, sum2 += double(emitted.x) * emitted.x, pixel += emitted.x;
      }
      pixel /= spp;
      pixelSum2 += (pixel - exact) * (pixel - exact);
    }
    const double count = double(pixels) * spp;
    const double mean = sum / count;
    const double perSample = sum2 / count - mean * mean;
    // The pixels are independent of each other, so their mean's error follows their spread.
    const double pixelVariance = pixelSum2 / pixels;
    EXPECT_NEAR(mean, exact, 4 * std::sqrt(pixelVariance / pixels));
    if (stratified) {
      // Unstratified, a pixel's variance is one sample's over 64; stratified, far lower.
      EXPECT_LT(pixelVariance, 0.05 * perSample / spp);
    } else {
      EXPECT_NEAR(pixelVariance, perSample / spp, 0.3 * perSample / spp);
    }
  }
}

// The camera ray's whole segment (SegmentSamples::wholeSegmentEmission): its emission under a
// ratio-tracked transmittance, past the collision that scatters it, keeps each channel's mean
// (the integral of exp(-sigma_t,c tau(x)) emission_c(x)) and spreads less than the
// track-length estimator, which gathers up to the collision only, in smoke whose density
// varies under its majorant (where the majorant is tight, ratio tracking is the track-length
// estimator); the same collisions decide the event, so the same random numbers give the very
// same events. Grey extinction, and coloured tracked against the largest channel
// (chromatic_tracking "max_channel"; spectral MIS keeps the track-length estimator).
TEST(Volume, WholeSegmentEmissionKeepsTheMeanWithLessSpread) {
  const std::vector<float> values = varyingSlabValues();
  auto densityAt = [&](double x) {  // x from the slab's entry, in [0, 2]; linear between nodes
    const double u = std::clamp(x / 0.5, 0.0, 4.0);
    const int i = std::min(3, int(u));
    return kSlabNodes[i] + (u - i) * (kSlabNodes[i + 1] - kSlabNodes[i]);
  };
  const Rgb grey{0.5f, 0.5f, 0.5f}, coloured{0.2f, 0.5f, 1.2f};
  for (const Rgb& sigmaA : {grey, coloured}) {
    SCOPED_TRACE(testing::Message() << "sigma_a " << sigmaA.x << " " << sigmaA.z);
    const float sigmaS = 1.0f;
    MediaScene media(settingsFor("track"));
    auto m = makeMedium(
        sigmaA, {sigmaS, sigmaS, sigmaS}, {}, 0.3f,
        std::make_unique<GridDensity>(5, 2, 2, values, Bounds3f{{-1, -5, -5}, {1, 5, 5}}));
    m->emissionField = std::make_unique<RampEmission>();
    m->heroTracking = false;
    addSlab(&media, std::move(m));
    Rgb exact;
    const int n = 20000;
    for (int c = 0; c < 3; ++c) {
      const double sigmaT = sigmaA[c] + sigmaS, h = kSlab / n;
      double tau = 0, sum = 0;
      for (int i = 0; i < n; ++i) {  // midpoints: exp(-sigma_t tau(x)) emission(x)
        const double x = (i + 0.5) * h;
        const double t = tau + 0.5 * h * 0.5 * (densityAt(i * h) + densityAt(x));
        sum += std::exp(-sigmaT * t) * 3 * x * h;
        tau += h * 0.5 * (densityAt(i * h) + densityAt((i + 1) * h));
      }
      exact[c] = float(sum) * (c == 0 ? 1.0f : c == 1 ? 0.5f : 0.25f);
    }
    const int samples = 40000;
    Rgb spread[2];
    std::vector<MediumEvent> events[2];
    for (int whole = 0; whole < 2; ++whole) {
      auto [mean, error] = meanAndError(samples, [&](Sampler& sampler) {
        const SegmentSamples first = segmentSamples(sampler, whole == 1);
        Rgb emitted;
        events[whole].push_back(media.sampleScatteringAndEmission(kAcross, kInfinity, sampler,
                                                                  &emitted, nullptr, &first));
        return emitted;
      });
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(mean[c], exact[c], 4 * error[c] + 1e-4)
            << "whole " << whole << ", channel " << c;
      spread[whole] = error * std::sqrt(float(samples));
    }
    // Every channel spreads less; summed over the channels, the variance falls by a third or more
    // (the largest channel the least: its majorant is the tightest).
    for (int c = 0; c < 3; ++c) EXPECT_LT(spread[1][c], 0.9f * spread[0][c]) << "channel " << c;
    EXPECT_LT(dot(spread[1], spread[1]), 0.67f * dot(spread[0], spread[0]));
    int scattered = 0;
    for (int i = 0; i < samples; ++i) {
      ASSERT_EQ(events[0][i].scattered, events[1][i].scattered) << i;
      ASSERT_EQ(events[0][i].t, events[1][i].t) << i;
      ASSERT_EQ(events[0][i].weight, events[1][i].weight) << i;
      scattered += events[0][i].scattered ? 1 : 0;
    }
    EXPECT_GT(scattered, samples / 4);
    std::printf(
        "sigma_a %.2f..%.2f: spread of one sample R %.3f -> %.3f, G %.3f -> %.3f, "
        "B %.3f -> %.3f\n",
        sigmaA.x, sigmaA.z, spread[0].x, spread[1].x, spread[0].y, spread[1].y, spread[0].z,
        spread[1].z);
  }
}

// The whole segment's tracking ends past the last medium that emits: a thin fog beyond a fire
// (its density 0.01 under a majorant of 1, so ratio tracking would cross all of it) is tracked
// by the rays that pass the fire, as before, and not for the fire's sake by those it scattered
// (or that scatter in the fog itself). So the collisions the whole segment adds are the fire's
// own, exactly as many with the fog as without it (the same random numbers per ray); a ray
// that crosses the fog alone is tracked exactly as without the whole segment.
TEST(Volume, WholeSegmentEmissionStopsPastTheLastEmitter) {
  const std::vector<float> fire = varyingSlabValues();
  std::vector<float> fog(5 * 2 * 2, 0.01f);
  fog[0] = 1;  // the fog's maximum density
  const Bounds3f fireBox{{-1, -5, -5}, {1, 5, 5}}, fogBox{{2, -5, -5}, {10, 5, 5}};
  uint64_t added[2], fogAlone[2];
  for (int withFog = 0; withFog < 2; ++withFog) {
    MediaScene media(settingsFor("track"));
    auto m = makeMedium({1, 1, 1}, {1, 1, 1}, {}, 0,
                        std::make_unique<GridDensity>(5, 2, 2, fire, fireBox));
    m->emissionField = std::make_unique<UniformEmission>();
    media.addRegion(std::move(m), std::make_unique<Box>(fireBox.lower, fireBox.upper), Transform());
    if (withFog)
      media.addRegion(makeMedium({1, 1, 1}, {1, 1, 1}, {}, 0,
                                 std::make_unique<GridDensity>(5, 2, 2, fog, fogBox)),
                      std::make_unique<Box>(fogBox.lower, fogBox.upper), Transform());
    auto collisions = [&](const Ray& ray, bool whole) {
      resetTrackingCounts();
      for (int i = 0; i < 4000; ++i) {
        Sampler sampler(mixBits(uint64_t(i) + 99), 0);
        const SegmentSamples first = segmentSamples(sampler, whole);
        Rgb emitted;
        media.sampleScatteringAndEmission(ray, kInfinity, sampler, &emitted, nullptr, &first);
      }
      // (Past the event, the collisions are ratio tracking's and counted so.)
      return trackingCounts().tentative + trackingCounts().ratioTentative;
    };
    const uint64_t trackLength = collisions(kAcross, false), whole = collisions(kAcross, true);
    ASSERT_GT(whole, trackLength);  // the fire is tracked past the collision
    added[withFog] = whole - trackLength;
    const Ray intoTheFog{{1.5f, 0.1f, 0.2f}, {1, 0, 0}};
    fogAlone[withFog] = collisions(intoTheFog, true) - collisions(intoTheFog, false);
  }
  EXPECT_EQ(added[1], added[0]);
  EXPECT_EQ(fogAlone[1], 0u);
}

// ---------------------------------------------------------------------------------------------
// Rendered scenes
// ---------------------------------------------------------------------------------------------

// A white Lambert floor at y = -1 under a point light, seen from the front, with an opaque
// sphere between the light and the floor; media are added by the tests.
SceneDescription shadowScene(int size) {
  SceneDescription d;
  d.file = "volume shadow (in code)";
  MaterialDesc white;
  white.name = "white";
  white.type = MaterialType::Lambert;
  white.baseColor = {0.8f, 0.8f, 0.8f};
  d.materials.push_back(white);
  MeshDesc floor;
  floor.positions = {{-5, -1, -5}, {5, -1, -5}, {5, -1, 5}, {-5, -1, 5}};
  floor.normals.assign(4, {0, 1, 0});
  floor.indices = {0, 2, 1, 0, 3, 2};
  floor.material = 0;
  d.meshes.push_back(floor);
  d.instances.push_back({0, Transform(), "floor", {}});
  ObjectDesc ball;
  ball.name = "ball";
  ball.shape = std::make_shared<Sphere>(Vec3f{0, 1.5f, 0}, 0.6f);
  ball.material = 0;
  d.objects.push_back(ball);
  CameraDesc cam;
  cam.type = CameraType::Orthographic;
  cam.xmag = cam.ymag = 2;
  cam.worldFromCamera = Transform::lookAt({0, 0, 6}, {0, 0, 0}, {0, 1, 0});
  d.cameras.push_back(cam);
  LightDesc light;
  light.type = LightType::Point;
  light.intensity = 20;
  light.worldFromLight = Transform::translate({0, 3, 0});
  d.lights.push_back(light);
  d.render.width = d.render.height = size;
  d.render.spp = 4;
  return d;
}

MediumDesc fogBox(float density) {
  MediumDesc m;
  m.name = "fog";
  m.region = MediumDesc::Region::Shape;
  m.shape = std::make_shared<Box>(Vec3f{-2, -1, -1}, Vec3f{2, 1, 1});
  m.sigmaA = {0.05f, 0.05f, 0.05f};
  m.sigmaS = {0.4f, 0.4f, 0.4f};
  m.value = density;
  return m;
}

Film renderIt(const SceneDescription& d) {
  RenderScene scene = buildRenderScene(d);
  auto integrator = makeIntegrator(scene, d.render);
  RenderOptions options;
  options.threads = 2;
  RenderStats stats;
  Film film = render(scene, *integrator, d.render, options, &stats);
  EXPECT_EQ(stats.nonfiniteSamples, 0u);
  return film;
}

TEST(VolumeRender, ScenesWithoutMediaTakeTheMediaFreePath) {
  SceneDescription d = shadowScene(24);
  RenderScene scene = buildRenderScene(d);
  EXPECT_FALSE(scene.features().has(Feature::Volumes));
  EXPECT_EQ(scene.media(), nullptr);
  // The same scene with a medium that was then removed renders exactly as before.
  SceneDescription withFog = d;
  withFog.media.push_back(fogBox(1));
  withFog.media.clear();
  Film a = renderIt(d), b = renderIt(withFog);
  ASSERT_EQ(a.color.size(), b.color.size());
  for (size_t i = 0; i < a.color.size(); ++i) ASSERT_EQ(a.color[i], b.color[i]) << i;
}

TEST(VolumeRender, DensityZeroMediaLeaveTheImageUnchanged) {
  const int size = 24;
  SceneDescription d = shadowScene(size);
  Film plain = renderIt(d);
  for (const char* estimator : {"march", "track"}) {
    for (DensityType type : {DensityType::Constant, DensityType::Grid}) {
      SceneDescription z = d;
      MediumDesc m = fogBox(0);
      m.density = type;
      m.gridRes[0] = m.gridRes[1] = m.gridRes[2] = 2;
      m.gridValues.assign(8, 0.0f);
      m.emission = {1, 1, 1};  // emission scales with density: none either
      z.media.push_back(m);
      z.media.push_back(fogBox(0));  // a whole-scene medium of density 0 as well
      z.media.back().region = MediumDesc::Region::Scene;
      z.render.integrator.volumeEstimator = estimator;
      Film f = renderIt(z);
      for (size_t i = 0; i < f.color.size(); ++i) {
        ASSERT_TRUE(isFinite(f.color[i]));
        ASSERT_NEAR(f.color[i].y, plain.color[i].y, 1e-4f + 1e-4f * plain.color[i].y)
            << estimator << " pixel " << i;
      }
    }
  }
}

TEST(VolumeRender, SphereCastsAVolumetricShadow) {
  const int size = 48;
  SceneDescription d = shadowScene(size);
  d.media.push_back(fogBox(1));
  d.render.spp = 8;
  for (const char* estimator : {"march", "track"}) {
    d.render.integrator.volumeEstimator = estimator;
    Film f = renderIt(d);
    // Rows through the medium between the ball and the floor (world y in [-0.6, 0.6]):
    // the shaft below the ball (|x| < 0.25) against the lit fog beside it (1.6 < |x| < 1.95).
    double shaft = 0, beside = 0;
    int nShaft = 0, nBeside = 0;
    for (int y = 0; y < size; ++y) {
      const float wy = 2 - 4 * (y + 0.5f) / size;
      if (std::abs(wy) > 0.6f) continue;
      for (int x = 0; x < size; ++x) {
        const float wx = -2 + 4 * (x + 0.5f) / size;
        const double v = f.color[f.index(x, y)].y;
        if (std::abs(wx) < 0.25f) shaft += v, ++nShaft;
        if (std::abs(wx) > 1.6f && std::abs(wx) < 1.95f) beside += v, ++nBeside;
      }
    }
    shaft /= nShaft, beside /= nBeside;
    EXPECT_GT(beside, 0.02) << estimator;
    EXPECT_LT(shaft, 0.6 * beside) << estimator;
  }
}

// A noise density's offset moves the whole pattern: the field at p + offset is the field
// without offset at p, and a non-zero offset changes what a fixed point sees (rising smoke).
TEST(NoiseDensity, OffsetMovesThePattern) {
  const NoiseDensity still(1.3f, 4, 0.2f, 7);
  const Vec3f offset{0.25f, 1.5f, -0.75f};
  const NoiseDensity moved(1.3f, 4, 0.2f, 7, offset);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-2, 2);
  int differ = 0;
  for (int i = 0; i < 200; ++i) {
    const Vec3f p{u(rng), u(rng), u(rng)};
    EXPECT_NEAR(moved.density(p + offset), still.density(p), 1e-5f);
    differ += std::abs(moved.density(p) - still.density(p)) > 1e-3f;
  }
  EXPECT_GT(differ, 50);
}

}  // namespace
}  // namespace glint
