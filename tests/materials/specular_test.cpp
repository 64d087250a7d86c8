// Delta lobes: the mirror, smooth glass and smooth glTF PBR surfaces. Their directions are
// exact (mirror and Snell), their lobe probabilities are the Fresnel weights, and the lobe
// masks (kBsdfReflection, kBsdfTransmission, kBsdfSpecular) give the weights the Whitted
// integrator relies on. (Fresnel's values themselves are tested in scattering_test.cpp.)
#include "materials/specular.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "geometry/sampling.h"
#include "materials/microfacet_albedo.h"
#include "materials/pbr.h"
#include "materials/scattering.h"

namespace glint {
namespace {

SurfaceInteraction makeSurface(Vec3f n, Vec3f woLocal, bool frontFace) {
  SurfaceInteraction si;
  const Frame frame = Frame::fromZ(n);
  si.p = {1.0f, 2.0f, -0.5f};
  si.ng = si.ns = n;
  si.wo = normalize(frame.fromLocal(woLocal));
  si.frontFace = frontFace;
  si.uv = {0.5f, 0.25f};
  si.dpdu = frame.s;
  si.dpdv = frame.t;
  return si;
}

Vec3f viewAtDegrees(float degrees) {
  const float t = degrees * kPi / 180;
  return {std::sin(t) * std::cos(1.1f), std::sin(t) * std::sin(1.1f), std::cos(t)};
}

const std::vector<Vec3f> kNormals = {{0, 0, 1}, normalize(Vec3f{-0.4f, 0.2f, 0.9f})};

// Snell's law in vector form, independently of scattering.h: the tangential part of the
// direction scales by 1/eta and the refracted ray leaves on the other side.
Vec3f snell(Vec3f wo, Vec3f n, float eta) {
  const float cosI = dot(wo, n);
  const Vec3f tangential = wo - n * cosI;
  const float sin2T = lengthSquared(tangential) / (eta * eta);
  return -tangential / eta - n * std::sqrt(std::max(0.0f, 1 - sin2T));
}

void expectDirection(Vec3f actual, Vec3f expected, const std::string& what) {
  EXPECT_NEAR(actual.x, expected.x, 2e-6f) << what;
  EXPECT_NEAR(actual.y, expected.y, 2e-6f) << what;
  EXPECT_NEAR(actual.z, expected.z, 2e-6f) << what;
}

const ColorParam kWhite{{1, 1, 1}};

// ---------------------------------------------------------------------------------------------
// Mirror
// ---------------------------------------------------------------------------------------------

TEST(Mirror, ReflectsIntoTheMirrorDirectionWithItsTint) {
  MirrorMaterial mirror(ColorParam{{0.9f, 0.5f, 0.2f}});
  for (Vec3f n : kNormals)
    for (float degrees : {0.0f, 30.0f, 60.0f, 85.0f, 89.0f}) {
      const SurfaceInteraction si = makeSurface(n, viewAtDegrees(degrees), true);
      const std::string what = std::to_string(degrees) + " degrees";
      for (float uLobe : {0.0f, 0.5f, 0.999f}) {
        std::optional<BsdfSample> s = mirror.bsdf(si).sample({0.2f, 0.7f}, uLobe);
        ASSERT_TRUE(s) << what;
        expectDirection(s->wi, 2 * dot(si.wo, n) * n - si.wo, what);
        EXPECT_EQ(s->flags, kBsdfSpecular | kBsdfReflection);
        EXPECT_EQ(s->pdf, 1);
        const Rgb w = s->weight(si.ns);
        EXPECT_NEAR(w.x, 0.9f, 1e-6f) << what;
        EXPECT_NEAR(w.y, 0.5f, 1e-6f) << what;
        EXPECT_NEAR(w.z, 0.2f, 1e-6f) << what;
        // Delta lobes: eval and pdf are zero, even in the mirror direction itself.
        EXPECT_EQ(mirror.bsdf(si).f(s->wi), Rgb{}) << what;
        EXPECT_EQ(mirror.bsdf(si).pdf(s->wi), 0) << what;
      }
      EXPECT_FALSE(mirror.bsdf(si).sample({0.2f, 0.7f}, 0.5f, kBsdfTransmission)) << what;
    }
}

// ---------------------------------------------------------------------------------------------
// Smooth glass
// ---------------------------------------------------------------------------------------------

TEST(Glass, ReflectsFourPercentAtNormalIncidence) {
  GlassMaterial glass(1.5f, kWhite);
  for (bool front : {true, false}) {
    const SurfaceInteraction si = makeSurface({0, 0, 1}, {0, 0, 1}, front);
    std::optional<BsdfSample> r = glass.bsdf(si).sample({0.5f, 0.5f}, 0.0f);
    ASSERT_TRUE(r);
    EXPECT_TRUE(r->flags & kBsdfReflection);
    EXPECT_NEAR(r->pdf, 0.04f, 1e-6f);
    EXPECT_NEAR(r->weight(si.ns).y, 1, 1e-5f);  // F / P(reflection)
    // Reflection-only (Whitted): weight F = 0.04.
    std::optional<BsdfSample> ro = glass.bsdf(si).sample({0.5f, 0.5f}, 0.7f, kBsdfReflection);
    ASSERT_TRUE(ro);
    EXPECT_EQ(ro->pdf, 1);
    EXPECT_NEAR(ro->weight(si.ns).y, 0.04f, 1e-6f);
    std::optional<BsdfSample> t = glass.bsdf(si).sample({0.5f, 0.5f}, 0.5f);
    ASSERT_TRUE(t);
    EXPECT_TRUE(t->flags & kBsdfTransmission);
    EXPECT_NEAR(t->pdf, 0.96f, 1e-6f);
    expectDirection(t->wi, {0, 0, -1}, "normal incidence goes straight through");
  }
}

// Over many uLobe values on a uniform grid, the fraction that picks reflection is F (to the
// grid's resolution, 1e-4) and the reported discrete probabilities are F and 1 - F; the
// directions are the exact mirror and Snell directions (2e-6 per component, float rounding).
TEST(Glass, PicksLobesWithFresnelProbabilitiesAndExactDirections) {
  constexpr int kGrid = 10'000;
  for (float ior : {1.5f, 1.33f, 2.4f}) {
    GlassMaterial glass(ior, kWhite);
    for (Vec3f n : kNormals)
      for (float degrees : {0.0f, 20.0f, 40.0f, 60.0f, 75.0f, 88.0f})
        for (bool front : {true, false}) {
          const SurfaceInteraction si = makeSurface(n, viewAtDegrees(degrees), front);
          const std::string what = "ior " + std::to_string(ior) + " at " + std::to_string(degrees) +
                                   (front ? " front" : " back");
          const float eta = front ? ior : 1 / ior;
          const float cosO = dot(si.wo, n);
          const float F = fresnelDielectric(cosO, eta);
          int reflections = 0, transmissions = 0;
          for (int i = 0; i < kGrid; ++i) {
            std::optional<BsdfSample> s = glass.bsdf(si).sample({0.3f, 0.3f}, (i + 0.5f) / kGrid);
            ASSERT_TRUE(s) << what;
            ASSERT_TRUE(s->flags & kBsdfSpecular);
            if (s->flags & kBsdfReflection) {
              ++reflections;
              EXPECT_NEAR(s->pdf, F, 1e-6f) << what;
              if (i % 97 == 0) expectDirection(s->wi, 2 * cosO * n - si.wo, what);
            } else {
              ++transmissions;
              EXPECT_NEAR(s->pdf, 1 - F, 1e-6f) << what;
              EXPECT_NEAR(s->eta, eta, 1e-6f) << what;
              if (i % 97 == 0) {
                expectDirection(s->wi, snell(si.wo, n, eta), what);
                // Snell: sin(theta_t) = sin(theta_i) / eta (the lengths of the tangential
                // parts, which stay accurate near normal incidence), on the far side.
                const float sinI = length(si.wo - n * cosO);
                const float cosT = -dot(s->wi, n);
                EXPECT_GT(cosT, 0) << what;
                EXPECT_NEAR(length(s->wi + n * cosT), sinI / eta, 2e-6f) << what;
              }
            }
            EXPECT_EQ(glass.bsdf(si).f(s->wi), Rgb{}) << what;
            EXPECT_EQ(glass.bsdf(si).pdf(s->wi), 0) << what;
          }
          EXPECT_NEAR(double(reflections) / kGrid, F, 1.0 / kGrid + 1e-6) << what;
          EXPECT_EQ(reflections + transmissions, kGrid);
        }
  }
}

// From inside (frontFace false: eta = 1/1.5) past the critical angle asin(1/1.5) = 41.8 degrees
// there is no refracted direction: the transmission lobe returns nothing and reflection takes
// weight 1 whatever the lobe mask and uLobe. Just below the critical angle both exist.
TEST(Glass, TotalInternalReflectionFromInside) {
  GlassMaterial glass(1.5f, ColorParam{{0.5f, 0.8f, 1}});
  for (Vec3f n : kNormals) {
    for (float degrees : {42.5f, 50.0f, 70.0f, 89.0f}) {
      const SurfaceInteraction si = makeSurface(n, viewAtDegrees(degrees), false);
      const std::string what = std::to_string(degrees) + " degrees";
      EXPECT_FALSE(glass.bsdf(si).sample({0.5f, 0.5f}, 0.99f, kBsdfTransmission)) << what;
      for (uint32_t lobes : {kBsdfAllLobes, uint32_t(kBsdfReflection)})
        for (float uLobe : {0.0f, 0.5f, 0.9999f}) {
          std::optional<BsdfSample> s = glass.bsdf(si).sample({0.5f, 0.5f}, uLobe, lobes);
          ASSERT_TRUE(s) << what;
          EXPECT_EQ(s->flags, kBsdfSpecular | kBsdfReflection) << what;
          EXPECT_EQ(s->pdf, 1) << what;
          // The reflection is not tinted: white, weight 1 in every channel.
          const Rgb w = s->weight(si.ns);
          EXPECT_NEAR(w.x, 1, 1e-6f) << what;
          EXPECT_NEAR(w.z, 1, 1e-6f) << what;
        }
    }
    const SurfaceInteraction below = makeSurface(n, viewAtDegrees(41.0f), false);
    EXPECT_TRUE(glass.bsdf(below).sample({0.5f, 0.5f}, 0.99f, kBsdfTransmission));
    // From outside there is never total internal reflection.
    const SurfaceInteraction outside = makeSurface(n, viewAtDegrees(70.0f), true);
    EXPECT_TRUE(glass.bsdf(outside).sample({0.5f, 0.5f}, 0.99f, kBsdfTransmission));
  }
}

// Whitted follows each lobe separately: reflection weight F (white), transmission weight
// (1 - F) / eta^2 x tint, each with probability 1.
TEST(Glass, LobeMasksGiveWhittedWeights) {
  const Rgb tint{0.9f, 0.6f, 0.3f};
  for (float ior : {1.5f, 1.33f}) {
    GlassMaterial glass(ior, ColorParam{tint});
    for (Vec3f n : kNormals)
      for (float degrees : {0.0f, 35.0f, 60.0f, 80.0f})
        for (bool front : {true, false}) {
          const SurfaceInteraction si = makeSurface(n, viewAtDegrees(degrees), front);
          const std::string what = "ior " + std::to_string(ior) + " at " + std::to_string(degrees) +
                                   (front ? " front" : " back");
          const float eta = front ? ior : 1 / ior;
          const float F = fresnelDielectric(dot(si.wo, n), eta);
          std::optional<BsdfSample> r =
              glass.bsdf(si).sample({0.1f, 0.9f}, 0.999f, kBsdfReflection);
          ASSERT_TRUE(r) << what;
          EXPECT_EQ(r->pdf, 1);
          const Rgb wr = r->weight(si.ns);
          for (int c = 0; c < 3; ++c) EXPECT_NEAR(wr[c], F, 1e-6f) << what;
          std::optional<BsdfSample> t =
              glass.bsdf(si).sample({0.1f, 0.9f}, 0.0f, kBsdfTransmission);
          if (F >= 1) {
            EXPECT_FALSE(t) << what;
            continue;
          }
          ASSERT_TRUE(t) << what;
          EXPECT_EQ(t->pdf, 1);
          EXPECT_TRUE(t->flags & kBsdfTransmission);
          const Rgb wt = t->weight(si.ns);
          for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(wt[c], (1 - F) / (eta * eta) * tint[c], 2e-6f) << what;
        }
  }
}

// ---------------------------------------------------------------------------------------------
// Smooth glTF PBR (roughness 0: delta lobes)
// ---------------------------------------------------------------------------------------------

PbrMaterial makePbr(Rgb base, float metallic, float roughness, float transmission) {
  PbrParams p;
  p.baseColor = ColorParam{base};
  p.metallic.factor = metallic;
  p.roughness.factor = roughness;
  p.transmission.factor = transmission;
  return PbrMaterial(p);
}

Rgb schlickReference(Rgb f0, float c) {
  const float m = std::pow(1 - c, 5.0f);
  return f0 + (Rgb{1, 1, 1} - f0) * m;
}

// kBsdfSpecular restricts the choice to the delta lobes: the mirror lobe with weight
// metallic Schlick(base) + (1 - metallic) F and the refraction with weight
// (1 - metallic) transmission (1 - F) / eta^2 x base, with a reflection or transmission mask
// each with probability 1; with both, in proportion to these weights' Fresnel parts. The
// diffuse lobe (not a delta) is never returned; a rough surface has no delta lobe at all.
TEST(SmoothPbr, SpecularMaskGivesTheDeltaLobeWeights) {
  const Rgb base{0.8f, 0.5f, 0.3f};
  for (float metallic : {0.0f, 0.4f, 1.0f})
    for (float transmission : {0.0f, 0.6f, 1.0f})
      for (Vec3f n : kNormals)
        for (float degrees : {0.0f, 40.0f, 75.0f})
          for (bool front : {true, false}) {
            PbrMaterial pbr = makePbr(base, metallic, 0, transmission);
            EXPECT_TRUE(pbr.flags() & kBsdfSpecular);
            const SurfaceInteraction si = makeSurface(n, viewAtDegrees(degrees), front);
            const std::string what = "metallic " + std::to_string(metallic) + " transmission " +
                                     std::to_string(transmission) + " at " +
                                     std::to_string(degrees) + (front ? " front" : " back");
            const float eta = transmission > 0 && !front ? 1 / 1.5f : 1.5f;
            const float cosO = dot(si.wo, n);
            const float F = fresnelDielectric(cosO, eta);
            const Rgb expectedR =
                schlickReference(base, cosO) * metallic + Rgb{1, 1, 1} * ((1 - metallic) * F);
            std::optional<BsdfSample> r =
                pbr.bsdf(si).sample({0.4f, 0.6f}, 0.5f, kBsdfSpecular | kBsdfReflection);
            ASSERT_TRUE(r) << what;
            EXPECT_EQ(r->flags, kBsdfSpecular | kBsdfReflection) << what;
            EXPECT_NEAR(r->pdf, 1, 1e-6f) << what;
            expectDirection(r->wi, 2 * cosO * n - si.wo, what);
            const Rgb wr = r->weight(si.ns);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(wr[c], expectedR[c], 1e-5f) << what;

            std::optional<BsdfSample> t =
                pbr.bsdf(si).sample({0.4f, 0.6f}, 0.5f, kBsdfSpecular | kBsdfTransmission);
            const float Tweight = (1 - metallic) * transmission * (1 - F);
            if (Tweight <= 0) {
              EXPECT_FALSE(t) << what;
            } else {
              ASSERT_TRUE(t) << what;
              EXPECT_EQ(t->flags, kBsdfSpecular | kBsdfTransmission) << what;
              EXPECT_NEAR(t->pdf, 1, 1e-6f) << what;
              EXPECT_NEAR(t->eta, eta, 1e-6f) << what;
              expectDirection(t->wi, snell(si.wo, n, eta), what);
              const Rgb wt = t->weight(si.ns);
              for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(wt[c], Tweight / (eta * eta) * base[c], 1e-5f) << what;
            }

            // Both delta lobes: never the diffuse one, reflection chosen in proportion
            // F_spec : T_weight (the Fresnel weights at wo; the metal's by its largest channel).
            const float specWeight =
                metallic * maxComponent(schlickReference(base, cosO)) + (1 - metallic) * F;
            constexpr int kGrid = 2000;
            int reflections = 0;
            for (int i = 0; i < kGrid; ++i) {
              std::optional<BsdfSample> s = pbr.bsdf(si).sample({0.4f, 0.6f}, (i + 0.5f) / kGrid,
                                                                kBsdfSpecular | kBsdfAllLobes);
              ASSERT_TRUE(s) << what;
              ASSERT_TRUE(s->flags & kBsdfSpecular) << what;
              if (s->flags & kBsdfReflection) ++reflections;
            }
            EXPECT_NEAR(double(reflections) / kGrid, specWeight / (specWeight + Tweight),
                        1.0 / kGrid + 1e-6)
                << what;

            // Only the specular bit: neither hemisphere is allowed.
            EXPECT_FALSE(pbr.bsdf(si).sample({0.4f, 0.6f}, 0.5f, kBsdfSpecular)) << what;
          }
}

// With all lobes, a smooth PBR surface returns its delta lobes with their discrete
// probabilities and the diffuse lobe as a density: eval and pdf see only the diffuse lobe
// (zero for the delta directions' own share), and a delta sample's pdf is its lobe's
// probability.
TEST(SmoothPbr, DeltaSamplesAreExcludedFromEvalAndPdf) {
  PbrMaterial pbr = makePbr({1, 1, 1}, 0, 0, 0);
  PbrMaterial metal = makePbr({1, 1, 1}, 1, 0, 0);
  for (Vec3f n : kNormals)
    for (float degrees : {10.0f, 60.0f}) {
      const SurfaceInteraction si = makeSurface(n, viewAtDegrees(degrees), true);
      const float F = fresnelDielectric(dot(si.wo, n), 1.5f);
      int delta = 0;
      for (int i = 0; i < 1000; ++i) {
        std::optional<BsdfSample> s = pbr.bsdf(si).sample({0.37f, 0.61f}, (i + 0.5f) / 1000);
        ASSERT_TRUE(s);
        if (s->flags & kBsdfSpecular) {
          ++delta;
          EXPECT_NEAR(s->pdf, F, 1e-6f);
        } else {
          EXPECT_TRUE(s->flags & kBsdfDiffuse);
          // The diffuse lobe of a white dielectric, (1 - F(wo)) (1 - F(wi)) / (1 - F_avg) / pi
          // (the albedo scaling of pbr.h; F_avg = 0.0918 for index 1.5), picked with
          // probability 1 - F(wo).
          const float Fi = fresnelDielectric(dot(s->wi, n), 1.5f);
          EXPECT_NEAR(s->f.y, (1 - F) * (1 - Fi) / (1 - dielectricFresnelAverage(1.5f)) * kInvPi,
                      1e-6f);
          EXPECT_NEAR(s->pdf, (1 - F) * cosineHemispherePdf(dot(s->wi, n)), 1e-5f);
        }
      }
      EXPECT_NEAR(delta / 1000.0, F, 1e-3);
      // The metal has no diffuse lobe: eval and pdf are zero everywhere, even in the mirror
      // direction.
      const Vec3f mirror = 2 * dot(si.wo, n) * n - si.wo;
      EXPECT_EQ(metal.bsdf(si).f(mirror), Rgb{});
      EXPECT_EQ(metal.bsdf(si).pdf(mirror), 0);
      std::optional<BsdfSample> m = metal.bsdf(si).sample({0.5f, 0.5f}, 0.5f);
      ASSERT_TRUE(m);
      EXPECT_EQ(m->pdf, 1);
      expectDirection(m->wi, mirror, "metal");
    }
}

TEST(RoughPbr, HasNoDeltaLobes) {
  PbrMaterial pbr = makePbr({1, 1, 1}, 0, 0.3f, 1);
  EXPECT_FALSE(pbr.flags() & kBsdfSpecular);
  const SurfaceInteraction si = makeSurface({0, 0, 1}, viewAtDegrees(30), true);
  for (float uLobe : {0.01f, 0.5f, 0.99f})
    EXPECT_FALSE(pbr.bsdf(si).sample({0.5f, 0.5f}, uLobe, kBsdfSpecular | kBsdfAllLobes));
}

// Issue 49, item 0: a mirror whose shading normal is tilted away from a grazing view (a normal
// map on DamagedHelmet's visor rim) reflects into the surface and is folded back above it.
// The fold kept f = F / cos of the unfolded direction, times the folded direction's cosine:
// weights of 1,393 where F is 0.9. Whatever the tilt, a delta sample's weight is F.
TEST(Mirror, AFoldedReflectionStillWeighsItsReflectance) {
  MirrorMaterial mirror(ColorParam{{0.9f, 0.5f, 0.2f}});
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0, 1);
  int folded = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3f ng{0, 0, 1};
    // A shading normal tilted 60-88 degrees towards +x, a grazing view from the same side:
    // its mirror image about ns dips under the geometric plane.
    const float tilt = (60 + 28 * u(rng)) * kPi / 180, phi = 0.3f * (u(rng) - 0.5f);
    SurfaceInteraction si = makeSurface(ng, {0, 0, 1}, true);
    si.ns = normalize(
        Vec3f{std::sin(tilt) * std::cos(phi), std::sin(tilt) * std::sin(phi), std::cos(tilt)});
    const float view = (2 + 60 * u(rng)) * kPi / 180;  // above the geometric plane
    si.wo = normalize(Vec3f{std::cos(view), 0.2f * (u(rng) - 0.5f), std::sin(view)});
    if (dot(si.wo, si.ns) <= 0) continue;
    const std::optional<BsdfSample> s = mirror.bsdf(si).sample({0.5f, 0.5f}, 0.5f);
    if (!s) continue;
    EXPECT_GT(dot(s->wi, ng), 0);
    const Rgb w = s->weight(si.ns);
    EXPECT_NEAR(w.x, 0.9f, 1e-4f) << i;
    EXPECT_NEAR(w.z, 0.2f, 1e-4f) << i;
    if (dot(2 * dot(si.wo, si.ns) * si.ns - si.wo, ng) <= 0) ++folded;
  }
  EXPECT_GT(folded, 100);  // the case was reached
}

}  // namespace
}  // namespace glint
