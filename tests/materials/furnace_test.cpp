// White-furnace tests of every non-emissive material: with albedo 1, the directional albedo
// E(wo) = integral of f(wo, wi) |cos theta_i| dwi must never exceed 1, and must equal 1 where
// the model conserves energy.
//
// E(wo) is estimated by Monte Carlo with the material's own sampling (the mean of
// f |cos| / pdf, the path throughput weight) and, for lobes that are not too peaked, with
// uniform sphere sampling as an independent cross-check (the mean of f |cos| 4 pi). Every bound
// carries 3 standard errors of the estimate (computed from the samples: a one-sided 3-sigma
// bound fails a correct material with probability ~0.13% per check, and the estimates are
// deterministic for a fixed seed, so a passing run stays passing) plus a stated tolerance.
//
// Transmission changes radiance by 1/eta^2 (specular.h): radiance entering a denser medium is
// compressed into a narrower cone. That is not a gain or loss of energy, so for transmitting
// materials the tests check energy, i.e. transmitted weights multiplied by eta^2 (eta the
// relative index crossed, BsdfSample::eta), and report radiance albedos only as such.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "materials/basic_materials.h"
#include "materials/layers.h"
#include "materials/pbr.h"
#include "materials/scattering.h"
#include "materials/specular.h"

namespace glint {
namespace {

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

// A hit built by hand: ng = ns = n, wo given in n's frame, dp/du and dp/dv along the frame.
SurfaceInteraction makeSurface(Vec3f n, Vec3f woLocal, bool frontFace) {
  SurfaceInteraction si;
  const Frame frame = Frame::fromZ(n);
  si.p = {0.25f, -0.5f, 1.0f};
  si.ng = si.ns = n;
  si.wo = normalize(frame.fromLocal(woLocal));
  si.frontFace = frontFace;
  si.uv = {0.3f, 0.6f};
  si.dpdu = frame.s;
  si.dpdv = frame.t;
  return si;
}

// A view direction with the given cosine to the normal, at azimuth 0.7 rad.
Vec3f viewWithCos(float cosTheta) {
  const float s = std::sqrt(std::max(0.0f, 1 - cosTheta * cosTheta));
  return {s * std::cos(0.7f), s * std::sin(0.7f), cosTheta};
}

// The normals the tests run on: the world's +Z and a tilted one (exercises the frames).
const Vec3f kTilted = normalize(Vec3f{0.3f, -0.5f, 0.8f});

// Views from normal incidence to grazing (cos theta = 0.05).
const std::vector<float> kViewCosines = {1.0f, 0.8f, 0.5f, 0.2f, 0.05f};

float uniformFloat(std::mt19937_64& rng) { return float(rng() >> 40) * 0x1p-24f; }

struct Estimate {
  double mean = 0, standardError = 0;
  int bad = 0;  // non-finite or negative weights, and samples whose pdf is not positive
};

// Accumulates the mean and the standard error of the mean.
class Accumulator {
 public:
  void add(double v) {
    ++n_;
    const double d = v - mean_;
    mean_ += d / double(n_);
    m2_ += d * (v - mean_);
  }
  void addBad() {
    add(0);
    ++bad_;
  }
  Estimate estimate() const {
    return {mean_, n_ > 1 ? std::sqrt(m2_ / double(n_ - 1) / double(n_)) : 0.0, bad_};
  }

 private:
  int64_t n_ = 0;
  double mean_ = 0, m2_ = 0;
  int bad_ = 0;
};

// Mean of the green channel of f |cos| / pdf over the material's own samples (failed samples
// count as 0). `energy`: transmitted samples are multiplied by eta^2 (see the top).
Estimate albedoBySampling(const Material& m, const SurfaceInteraction& si, int samples,
                          uint64_t seed, uint32_t lobes = kBsdfAllLobes, bool energy = false) {
  std::mt19937_64 rng(seed);
  Accumulator acc;
  for (int i = 0; i < samples; ++i) {
    const Vec2f u{uniformFloat(rng), uniformFloat(rng)};
    const float uLobe = uniformFloat(rng);
    std::optional<BsdfSample> s = m.bsdf(si).sample(u, uLobe, lobes);
    if (!s) {
      acc.add(0);
      continue;
    }
    if (!(s->pdf > 0)) {
      acc.addBad();
      continue;
    }
    double w = double(s->weight(si.ns).y);
    if (energy && (s->flags & kBsdfTransmission)) w *= double(s->eta) * s->eta;
    if (!std::isfinite(w) || w < 0) {
      acc.addBad();
      continue;
    }
    acc.add(w);
  }
  return acc.estimate();
}

// The same integral with directions uniform over the sphere: mean of f |cos| 4 pi. For
// `energy`, directions on the far side of ns are weighted by etaBelow^2.
Estimate albedoByUniformSampling(const Material& m, const SurfaceInteraction& si, int samples,
                                 uint64_t seed, float etaBelow = 1) {
  std::mt19937_64 rng(seed);
  Accumulator acc;
  for (int i = 0; i < samples; ++i) {
    const float z = 1 - 2 * uniformFloat(rng), phi = 2 * kPi * uniformFloat(rng);
    const float r = std::sqrt(std::max(0.0f, 1 - z * z));
    const Vec3f wi = Frame::fromZ(si.ns).fromLocal({r * std::cos(phi), r * std::sin(phi), z});
    double w = double(m.bsdf(si).f(wi).y) * std::abs(dot(wi, si.ns)) * 4 * kPi;
    if (dot(wi, si.ns) < 0) w *= double(etaBelow) * etaBelow;
    if (!std::isfinite(w) || w < 0) {
      acc.addBad();
      continue;
    }
    acc.add(w);
  }
  return acc.estimate();
}

constexpr int kSamples = 200'000;
constexpr double kSigmas = 3;
// Slack for float rounding in f, pdf and cosines summed over 2e5 samples.
constexpr double kRounding = 1e-4;

std::string describeView(const SurfaceInteraction& si) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "cos(wo) %.3f, n (%.2f %.2f %.2f), %s face",
                dot(si.wo, si.ns), si.ns.x, si.ns.y, si.ns.z, si.frontFace ? "front" : "back");
  return buffer;
}

// E <= 1 within the noise, with the estimate's own standard error.
void expectAtMostOne(const Estimate& e, const std::string& what, double tolerance = kRounding) {
  EXPECT_EQ(e.bad, 0) << what;
  EXPECT_LE(e.mean, 1 + kSigmas * e.standardError + tolerance)
      << what << ": albedo " << e.mean << " +- " << e.standardError;
}

// Two independent estimates of the same integral agree within their combined noise.
void expectAgree(const Estimate& a, const Estimate& b, double tolerance, const std::string& what) {
  const double sigma =
      std::sqrt(a.standardError * a.standardError + b.standardError * b.standardError);
  EXPECT_NEAR(a.mean, b.mean, kSigmas * sigma + tolerance)
      << what << ": sampled " << a.mean << " +- " << a.standardError << ", uniform " << b.mean
      << " +- " << b.standardError;
}

const ColorParam kWhite{{1, 1, 1}};
const ColorParam kBlack{{0, 0, 0}};

// ---------------------------------------------------------------------------------------------
// Lambert, Phong, Blinn-Phong
// ---------------------------------------------------------------------------------------------

// f = 1/pi sampled with pdf cos/pi: every weight is exactly 1, so E = 1 up to rounding (1e-5
// relative) for every view; uniform sampling agrees within 3 sigma (its SE is ~0.2%).
TEST(Furnace, WhiteLambertReflectsEverything) {
  LambertMaterial lambert(kWhite, kBlack);
  uint64_t seed = 1;
  for (Vec3f n : {Vec3f{0, 0, 1}, kTilted})
    for (float c : kViewCosines)
      for (bool front : {true, false}) {
        const SurfaceInteraction si = makeSurface(n, viewWithCos(c), front);
        const Estimate e = albedoBySampling(lambert, si, kSamples, ++seed);
        EXPECT_EQ(e.bad, 0);
        EXPECT_NEAR(e.mean, 1, 1e-5) << describeView(si);
        EXPECT_LE(e.standardError, 1e-6) << describeView(si);
        const Estimate uniform = albedoByUniformSampling(lambert, si, kSamples, ++seed);
        expectAgree(e, uniform, kRounding, describeView(si));
      }
}

// Blinn-Phong's specular lobe at normal incidence, in closed form: there cos(theta_o) = 1 is the
// max in the denominator, h.wi = cos(theta_h), dwi = 4 cos(theta_h) dwh and cos(theta_i) =
// cos(2 theta_h) = 2c^2 - 1 (c = cos theta_h, wi below the horizon for c < 1/sqrt 2), so
//   E_spec = (n + 1) integral_{1/sqrt2}^1 c^n (2 c^2 - 1) dc
//          = (n + 1) [2 (1 - s^(n+3)) / (n+3) - (1 - s^(n+1)) / (n+1)],   s = 1/sqrt2:
// 0.25 at n = 1, 0.696 at n = 10, 0.961 at n = 100. The loss is that of Ashikhmin and
// Shirley's normalization, whose 1 / max(cos_i, cos_o) trades the classic factor's excess
// for a deficit.
double blinnSpecularAlbedoAtNormalIncidence(double n) {
  const double s = 1 / std::sqrt(2.0);
  return (n + 1) * (2 * (1 - std::pow(s, n + 3)) / (n + 3) - (1 - std::pow(s, n + 1)) / (n + 1));
}

// kd + ks = 1. Phong's lobe, (n+2)/(2 pi) cos^n(alpha), integrates against cos(theta_i) to
// exactly 1 when the mirror direction is the normal (alpha = theta_i): at normal incidence
// E = kd + ks = 1 with no loss. At other views part of the lobe falls below the horizon and the
// cosine drops: E < 1. Blinn-Phong at normal incidence: kd + ks E_spec(n) above.
TEST(Furnace, PhongAndBlinnPhongNeverGainEnergy) {
  struct Split {
    float kd, ks;
  };
  uint64_t seed = 100;
  for (bool blinn : {false, true})
    for (float shininess : {1.0f, 10.0f, 100.0f})
      for (Split split : {Split{0, 1}, Split{0.5f, 0.5f}, Split{0.8f, 0.2f}}) {
        PhongMaterial phong(ColorParam{{split.kd, split.kd, split.kd}},
                            Rgb{split.ks, split.ks, split.ks}, shininess, kBlack, blinn);
        for (Vec3f n : {Vec3f{0, 0, 1}, kTilted})
          for (float c : kViewCosines) {
            const SurfaceInteraction si = makeSurface(n, viewWithCos(c), true);
            char name[128];
            std::snprintf(name, sizeof name, "%s n=%g kd=%g ks=%g, ", blinn ? "Blinn" : "Phong",
                          shininess, split.kd, split.ks);
            const std::string what = name + describeView(si);
            const Estimate e = albedoBySampling(phong, si, kSamples / 4, ++seed);
            expectAtMostOne(e, what);
            // Uniform sampling cannot resolve the n = 100 lobe (0.5% of the sphere) reliably.
            if (shininess <= 10) {
              const Estimate uniform = albedoByUniformSampling(phong, si, kSamples / 4, ++seed);
              expectAtMostOne(uniform, what + " (uniform)");
              expectAgree(e, uniform, 1e-3, what);
            }
            if (c == 1) {
              const double expected =
                  split.kd +
                  split.ks * (blinn ? blinnSpecularAlbedoAtNormalIncidence(shininess) : 1);
              EXPECT_NEAR(e.mean, expected, kSigmas * e.standardError + 1e-3) << what;
            }
          }
      }
}

// ---------------------------------------------------------------------------------------------
// Mirror and smooth glass
// ---------------------------------------------------------------------------------------------

// A white mirror reflects everything: the weight of its one delta sample is exactly 1.
TEST(Furnace, WhiteMirrorReflectsEverything) {
  MirrorMaterial mirror(kWhite);
  for (Vec3f n : {Vec3f{0, 0, 1}, kTilted})
    for (float c : kViewCosines)
      for (bool front : {true, false}) {
        const SurfaceInteraction si = makeSurface(n, viewWithCos(c), front);
        std::optional<BsdfSample> s = mirror.bsdf(si).sample({0.3f, 0.4f}, 0.5f);
        ASSERT_TRUE(s) << describeView(si);
        EXPECT_NEAR(s->weight(si.ns).y, 1, 1e-6) << describeView(si);
        EXPECT_EQ(s->pdf, 1);
      }
}

// Smooth glass, per view and exactly (no sampling noise: the lobes are deltas): the reflected
// weight (reflection lobe only) is R = F, the transmitted weight (transmission lobe only) is
// T / eta^2 with T = 1 - F, so energy R + T eta^2 = 1 to float rounding (1e-6). Radiance
// R + T / eta^2 is below 1 entering glass and above 1 leaving it (up to eta^2 = 2.25 times
// T). With all lobes the expected weight over uLobe, sum of P(lobe) weight(lobe), is the same
// R + T / eta^2, measured on a uniform grid of uLobe values (error <= 1/grid).
TEST(Furnace, SmoothGlassConservesEnergyPerDirection) {
  for (float ior : {1.5f, 1.33f}) {
    GlassMaterial glass(ior, kWhite);
    for (Vec3f n : {Vec3f{0, 0, 1}, kTilted})
      for (float c : {1.0f, 0.9f, 0.8f, 0.7f, 0.6f, 0.5f, 0.3f, 0.2f, 0.05f})
        for (bool front : {true, false}) {
          const SurfaceInteraction si = makeSurface(n, viewWithCos(c), front);
          const std::string what = "ior " + std::to_string(ior) + ", " + describeView(si);
          const float eta = front ? ior : 1 / ior;
          std::optional<BsdfSample> r = glass.bsdf(si).sample({0.5f, 0.5f}, 0.5f, kBsdfReflection);
          std::optional<BsdfSample> t =
              glass.bsdf(si).sample({0.5f, 0.5f}, 0.5f, kBsdfTransmission);
          ASSERT_TRUE(r) << what;
          const double R = r->weight(si.ns).y;
          double T = 0;
          if (t) {
            EXPECT_NEAR(t->eta, eta, 1e-6) << what;
            T = double(t->weight(si.ns).y) * t->eta * t->eta;
          }
          EXPECT_NEAR(R + T, 1, 1e-6) << what;
          EXPECT_NEAR(R, fresnelDielectric(c, eta), 1e-6) << what;
          // Expected radiance weight with both lobes.
          constexpr int kGrid = 10'000;
          double sum = 0;
          for (int i = 0; i < kGrid; ++i) {
            std::optional<BsdfSample> s = glass.bsdf(si).sample({0.5f, 0.5f}, (i + 0.5f) / kGrid);
            ASSERT_TRUE(s) << what;
            sum += s->weight(si.ns).y;
          }
          const double radiance = R + (1 - R) / (double(eta) * eta);
          EXPECT_NEAR(sum / kGrid, radiance, 2.0 / kGrid * std::max(1.0, radiance)) << what;
        }
  }
}

// ---------------------------------------------------------------------------------------------
// glTF metallic-roughness (GGX)
// ---------------------------------------------------------------------------------------------

PbrMaterial makePbr(float metallic, float roughness, float transmission) {
  PbrParams p;
  p.baseColor = kWhite;
  p.metallic.factor = metallic;
  p.roughness.factor = roughness;
  p.transmission.factor = transmission;
  return PbrMaterial(p);
}

// Smooth (roughness 0: delta lobes) white PBR: the dielectric's mirror lobe takes F(wo) and
// its diffuse lobe (1 - F(wo)) of a white Lambertian, so E = 1 exactly (to 1e-5) in every
// view; the white metal is a mirror with Schlick's F = 1: E = 1. Smooth PBR glass
// (transmission 1): energy R + T = 1.
TEST(Furnace, SmoothWhitePbrConservesEnergy) {
  uint64_t seed = 500;
  for (float metallic : {0.0f, 1.0f})
    for (float transmission : {0.0f, 1.0f})
      for (float c : kViewCosines)
        for (bool front : {true, false}) {
          PbrMaterial pbr = makePbr(metallic, 0, transmission);
          const SurfaceInteraction si = makeSurface(kTilted, viewWithCos(c), front);
          const Estimate e = albedoBySampling(pbr, si, kSamples / 4, ++seed, kBsdfAllLobes, true);
          EXPECT_EQ(e.bad, 0);
          EXPECT_NEAR(e.mean, 1, kSigmas * e.standardError + 1e-5)
              << "metallic " << metallic << " transmission " << transmission << ", "
              << describeView(si);
        }
}

struct PbrCase {
  float metallic, roughness, transmission;
};

// Rough PBR. Single-scattering GGX loses the light that scatters between microfacets more
// than once (a white metal reflected only 0.307 at roughness 1 and normal incidence, and a
// white dielectric 0.318 at cos(wo) = 0.05). The opaque PBR material restores it (pbr.h): the
// metal with Kulla and Conty's multiple-scattering lobe, the dielectric's diffuse layer with the
// reciprocal albedo scaling (1 - E_spec(wo)) (1 - E_spec(wi)) / (1 - E_spec,avg). So a white
// opaque material now reflects everything: |E - 1| within the noise plus `tolerance` (the
// albedo tables' accuracy, microfacet_albedo_test.cpp). Rough glass still loses energy (no
// compensation for refraction): E <= 1 only. The tables below (material sampling, 2e5
// samples, standard errors <= 0.003; energy albedo; tilted normal) are printed by the tests.
//
// glTF's own coupling of the diffuse layer, 1 - F(wo.h) with the half vector (Appendix B,
// fresnel_mix), is not energy conserving (the specification says so, B.3.6.3): a white
// dielectric reflected up to 1.68 at cos(wo) = 0.05 for roughness 0.05 and 1.28 at
// cos(wo) = 0.2. (From inside a partly transmitting surface past the critical angle, that
// coupling also had a diffuse part that sample() never chose:
// PbrSampling.PdfIsPositiveWhereverFIs.)
void runPbrFurnace(const std::vector<PbrCase>& cases, double tolerance, bool conserves) {
  std::printf("  energy albedo at cos(wo) = 1, 0.8, 0.5, 0.2, 0.05:\n");
  uint64_t seed = 1000;
  for (const PbrCase& pc : cases) {
    PbrMaterial pbr = makePbr(pc.metallic, pc.roughness, pc.transmission);
    for (bool front : {true, false}) {
      std::string row;
      for (float c : kViewCosines) {
        const SurfaceInteraction si = makeSurface(kTilted, viewWithCos(c), front);
        char name[96];
        std::snprintf(name, sizeof name, "metallic %g roughness %g transmission %g, ", pc.metallic,
                      pc.roughness, pc.transmission);
        const std::string what = name + describeView(si);
        const Estimate e = albedoBySampling(pbr, si, kSamples, ++seed, kBsdfAllLobes, true);
        expectAtMostOne(e, what, tolerance);
        if (conserves) {
          EXPECT_GE(e.mean, 1 - kSigmas * e.standardError - tolerance)
              << what << ": albedo " << e.mean << " +- " << e.standardError;
        }
        // Uniform sampling resolves lobes of roughness >= 0.3 (alpha >= 0.09); the narrow
        // roughness 0.05 lobe is left to the material's sampling. Agreement also shows that
        // sample() reaches every direction where eval() is not zero.
        if (pc.roughness >= 0.3f) {
          const float etaBelow = pc.transmission > 0 && !front ? 1 / 1.5f : 1.5f;
          const Estimate uniform = albedoByUniformSampling(pbr, si, kSamples / 2, ++seed, etaBelow);
          expectAtMostOne(uniform, what + " (uniform)", tolerance);
          expectAgree(e, uniform, 2e-3, what);
        }
        char cell[32];
        std::snprintf(cell, sizeof cell, " %.3f", e.mean);
        row += cell;
      }
      std::printf("  metallic %.0f roughness %.2f transmission %.0f %s: %s\n", pc.metallic,
                  pc.roughness, pc.transmission, front ? "front" : "back ", row.c_str());
    }
  }
}

// Front and back faces agree (an opaque surface has air on both sides). White metal, to 3
// decimals (before the multiple-scattering lobe: 0.307 0.351 0.449 0.640 0.848 at roughness 1):
//   roughness   cos(wo) = 1     0.8    0.5    0.2    0.05
//   0.05                1.000  1.000  1.000  1.000  1.000
//   0.3                 1.000  1.000  1.001  1.000  1.003
//   0.7                 1.000  0.999  1.000  1.001  0.998
//   1                   1.000  1.000  0.998  1.000  1.000
TEST(Furnace, RoughWhitePbrMetalReflectsEverything) {
  runPbrFurnace({{1, 0.05f, 0}, {1, 0.3f, 0}, {1, 0.7f, 0}, {1, 1, 0}}, 4e-3, true);
}

// White dielectric (opaque), both faces alike (before the albedo scaling, with 1 - F(wo.n):
// 0.972 0.972 0.934 0.704 0.318 at roughness 1):
//   roughness   cos(wo) = 1     0.8    0.5    0.2    0.05
//   0.05                1.000  1.000  0.999  1.000  1.002
//   0.3                 1.000  1.000  1.000  1.000  1.000
//   0.7                 1.000  1.000  1.000  1.001  1.000
//   1                   1.000  1.000  1.000  0.999  1.000
TEST(Furnace, RoughWhitePbrDielectricReflectsEverything) {
  runPbrFurnace({{0, 0.05f, 0}, {0, 0.3f, 0}, {0, 0.7f, 0}, {0, 1, 0}}, 4e-3, true);
}

// Rough glass (metallic 0, transmission 1, ior 1.5), energy R + T eta^2:
//   roughness  face   cos(wo) = 1     0.8    0.5    0.2    0.05
//   0.05       front          1.000  1.000  1.000  1.000  0.999
//   0.05       back           1.000  1.000  1.000  0.999  0.997
//   0.3        front          0.999  0.998  0.994  0.958  0.928
//   0.3        back           0.991  0.979  0.971  0.904  0.881
//   0.7        front          0.969  0.947  0.895  0.845  0.889
//   0.7        back           0.761  0.711  0.663  0.672  0.716
//   1          front          0.893  0.833  0.741  0.705  0.800
//   1          back           0.417  0.471  0.514  0.496  0.535
// From the back (inside, past the critical angle of 41.8 degrees for cos < 0.745) rough
// glass still transmits through tilted microfacets; before this test the lobe selection gave
// transmission zero probability there (Fresnel of the macro normal = 1), so sample() lost that
// light (E was 0.18 instead of 0.51 at roughness 1, cos 0.5) while eval() had it.
TEST(Furnace, RoughPbrGlassNeverGainsEnergy) {
  runPbrFurnace({{0, 0.05f, 1}, {0, 0.3f, 1}, {0, 0.7f, 1}, {0, 1, 1}}, kRounding, false);
}

// ---------------------------------------------------------------------------------------------
// glTF's material extensions
// ---------------------------------------------------------------------------------------------

PbrMaterial makeLayered(float metallic, float roughness, float transmission, Rgb base,
                        void (*layers)(PbrParams&)) {
  PbrParams p;
  p.baseColor = ColorParam{base};
  p.metallic.factor = metallic;
  p.roughness.factor = roughness;
  p.transmission.factor = transmission;
  layers(p);
  return PbrMaterial(p);
}

// KHR_materials_specular with strength 0 removes the dielectric's reflection: what is left is
// a white Lambertian, E = 1 exactly (every weight is 1) in every view, on a rough surface too.
TEST(Furnace, SpecularStrengthZeroLeavesALambertian) {
  PbrMaterial m = makeLayered(0, 0.5f, 0, {1, 1, 1}, [](PbrParams& p) { p.specular = {0}; });
  uint64_t seed = 3000;
  for (float c : kViewCosines)
    for (bool front : {true, false}) {
      const SurfaceInteraction si = makeSurface(kTilted, viewWithCos(c), front);
      const Estimate e = albedoBySampling(m, si, kSamples / 4, ++seed);
      EXPECT_EQ(e.bad, 0);
      EXPECT_NEAR(e.mean, 1, 1e-5) << describeView(si);
    }
}

// A smooth clear coat (index 1.5) over a white Lambertian with no reflection of its own: the
// coat reflects F(wo) into the mirror direction and the base gets the rest, E = 1 exactly.
// Over a black base, only the coat's mirror reflection remains: E = clearcoat x F(wo).
TEST(Furnace, SmoothClearcoatReflectsItsFresnelAndPassesTheRest) {
  PbrMaterial white = makeLayered(0, 1, 0, {1, 1, 1}, [](PbrParams& p) {
    p.specular = {0};
    p.clearcoat = {1};
  });
  PbrMaterial black = makeLayered(0, 1, 0, {0, 0, 0}, [](PbrParams& p) {
    p.specular = {0};
    p.clearcoat = {0.7f};
  });
  uint64_t seed = 3100;
  for (float c : kViewCosines) {
    const SurfaceInteraction si = makeSurface(kTilted, viewWithCos(c), true);
    const Estimate e = albedoBySampling(white, si, kSamples / 4, ++seed);
    EXPECT_EQ(e.bad, 0);
    EXPECT_NEAR(e.mean, 1, 1e-5) << describeView(si);
    const Estimate coat = albedoBySampling(black, si, kSamples / 4, ++seed);
    EXPECT_NEAR(coat.mean, 0.7 * fresnelDielectric(dot(si.wo, si.ns), 1.5f), 1e-5)
        << describeView(si);
  }
}

// A thin sheet (transmission without a volume) reflects F and passes 1 - F straight through,
// unbent: E = 1 exactly, and every transmitted sample leaves along -wo.
TEST(Furnace, SmoothThinSheetPassesWhatItDoesNotReflect) {
  PbrMaterial sheet = makeLayered(0, 0, 1, {1, 1, 1}, [](PbrParams& p) { p.thinWalled = true; });
  uint64_t seed = 3200;
  for (float c : kViewCosines)
    for (bool front : {true, false}) {
      const SurfaceInteraction si = makeSurface(kTilted, viewWithCos(c), front);
      const Estimate e = albedoBySampling(sheet, si, kSamples / 4, ++seed);
      EXPECT_EQ(e.bad, 0);
      EXPECT_NEAR(e.mean, 1, 1e-5) << describeView(si);
      const auto s = sheet.bsdf(si).sample({0.3f, 0.6f}, 0.5f, kBsdfTransmission);
      ASSERT_TRUE(s) << describeView(si);
      EXPECT_NEAR(length(s->wi + si.wo), 0, 1e-5f) << describeView(si);
      EXPECT_NEAR(s->weight(si.ns).y, 1 - fresnelDielectric(dot(si.wo, si.ns), 1.5f), 1e-5f);
    }
}

// Diffuse transmission moves the share dt of the diffuse light to the other side: with no
// specular reflection, a white surface reflects 1 - dt and transmits dt (its colour's), both
// exactly.
TEST(Furnace, DiffuseTransmissionSplitsTheDiffuseLight) {
  PbrMaterial m = makeLayered(0, 0.5f, 0, {1, 1, 1}, [](PbrParams& p) {
    p.specular = {0};
    p.diffuseTransmission = {0.3f};
  });
  uint64_t seed = 3300;
  for (float c : kViewCosines)
    for (bool front : {true, false}) {
      const SurfaceInteraction si = makeSurface(kTilted, viewWithCos(c), front);
      EXPECT_NEAR(albedoBySampling(m, si, kSamples / 4, ++seed, kBsdfReflection).mean, 0.7, 1e-5)
          << describeView(si);
      EXPECT_NEAR(albedoBySampling(m, si, kSamples / 4, ++seed, kBsdfTransmission).mean, 0.3, 1e-5)
          << describeView(si);
      EXPECT_NEAR(albedoBySampling(m, si, kSamples / 4, ++seed).mean, 1, 1e-5) << describeView(si);
    }
}

// A white sheen over a black base that reflects nothing else reflects its own directional
// albedo, the table the base's scaling uses (so the two add up to at most 1): sampled and
// uniform estimates agree with it within 3 sigma + 5e-3 (the table's interpolation).
TEST(Furnace, SheenReflectsItsTabulatedAlbedo) {
  for (float roughness : {0.3f, 0.7f, 1.0f}) {
    PbrParams p;
    p.baseColor = kBlack;
    p.metallic = {0};
    p.roughness = {1};
    p.specular = {0};
    p.sheenColor = kWhite;
    p.sheenRoughness = {roughness};
    PbrMaterial m(p);
    uint64_t seed = 3400;
    for (float c : kViewCosines) {
      const SurfaceInteraction si = makeSurface(kTilted, viewWithCos(c), true);
      const Estimate e = albedoBySampling(m, si, kSamples, ++seed);
      const Estimate uniform = albedoByUniformSampling(m, si, kSamples, ++seed);
      const double table = sheenAlbedo(c, roughness);
      EXPECT_NEAR(e.mean, table, kSigmas * e.standardError + 5e-3)
          << "roughness " << roughness << ", " << describeView(si);
      expectAgree(e, uniform, 2e-3, describeView(si));
    }
  }
}

// Every layer at once over rough white bases: a white material never reflects more than it
// receives (energy, for transmission). The sheen's albedo scaling is tabulated: 3e-3 for its
// interpolation.
TEST(Furnace, LayeredMaterialsNeverGainEnergy) {
  struct Case {
    const char* name;
    float metallic, roughness, transmission;
    void (*layers)(PbrParams&);
  };
  const Case cases[] = {
      {"rough clearcoat over rough dielectric", 0, 0.5f, 0,
       [](PbrParams& p) {
         p.clearcoat = {1};
         p.clearcoatRoughness = {0.3f};
       }},
      {"white sheen over white dielectric", 0, 0.7f, 0,
       [](PbrParams& p) {
         p.sheenColor = kWhite;
         p.sheenRoughness = {0.5f};
       }},
      {"coat, sheen and iridescence on a half metal", 0.5f, 0.4f, 0,
       [](PbrParams& p) {
         p.clearcoat = {0.8f};
         p.clearcoatRoughness = {0.2f};
         p.sheenColor = kWhite;
         p.sheenRoughness = {0.8f};
         p.iridescence = {1};
       }},
      {"anisotropic metal", 1, 0.3f, 0, [](PbrParams& p) { p.anisotropy = 0.9f; }},
      {"white specular colour", 0, 0.3f, 0,
       [](PbrParams& p) {
         p.specularColor = ColorParam{{2, 2, 2}};
       }},
      {"rough thin sheet", 0, 0.4f, 1, [](PbrParams& p) { p.thinWalled = true; }},
      {"dispersive smooth glass", 0, 0, 1, [](PbrParams& p) { p.dispersion = 1; }},
      {"diffuse transmission under a coat", 0, 0.6f, 0,
       [](PbrParams& p) {
         p.diffuseTransmission = {0.5f};
         p.clearcoat = {1};
         p.clearcoatRoughness = {0.5f};
       }},
  };
  uint64_t seed = 3500;
  for (const Case& c : cases) {
    PbrMaterial m = makeLayered(c.metallic, c.roughness, c.transmission, {1, 1, 1}, c.layers);
    for (float cosine : kViewCosines)
      for (bool front : {true, false}) {
        const SurfaceInteraction si = makeSurface(kTilted, viewWithCos(cosine), front);
        const std::string what = std::string(c.name) + ", " + describeView(si);
        expectAtMostOne(albedoBySampling(m, si, kSamples / 2, ++seed, kBsdfAllLobes, true), what,
                        3e-3);
      }
  }
}

}  // namespace
}  // namespace glint
