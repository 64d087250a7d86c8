// Area lights: sampleLi against pdfLi (chi-square), samples that trace back to the light,
// sampleLe's power against phi, and irradiance against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <random>

#include "geometry/sampling.h"
#include "geometry/shapes/box.h"
#include "geometry/shapes/cone.h"
#include "geometry/shapes/cylinder.h"
#include "geometry/shapes/disk.h"
#include "geometry/shapes/quad.h"
#include "geometry/shapes/sphere.h"
#include "image/oiio/plugin.h"
#include "materials/basic_materials.h"
#include "materials/image_texture.h"
#include "renderer/area_lights.h"
#include "renderer/environment_light.h"
#include "renderer/projective_light.h"
#include "tests/chi2.h"

namespace glint {
namespace {

// A light with the shape that traces rays against it.
struct LightCase {
  std::string name;
  std::unique_ptr<AreaLight> light;
  std::unique_ptr<Shape> shape;
  Vec3f receiver;  // a point that sees the whole light
  Vec3f receiverNormal;
  Transform world;      // places `shape` (the light is built placed already)
  bool closed = false;  // a closed solid seen from outside: only its near side is sampled
};

AreaEmission constant(Rgb L, bool twoSided) {
  AreaEmission e;
  e.radiance = L;
  e.twoSided = twoSided;
  return e;
}

// Two triangles covering the quad corner + [0,1] edgeU + [0,1] edgeV.
std::unique_ptr<AreaLight> meshQuad(Vec3f c, Vec3f eu, Vec3f ev, const AreaEmission& e) {
  return std::make_unique<AreaLight>(
      EmissiveMesh{{c, c + eu, c + eu + ev, c + ev}, {0, 1, 2, 0, 2, 3}, {}, {}}, e);
}

// Closed shapes under a placement with non-uniform scale and shear (a scale after a rotation).
const Transform kSheared = Transform::translate({0.3f, 2.2f, -0.2f}) *
                           Transform::scale({1.0f, 0.6f, 1.4f}) *
                           Transform::rotate(35, {1, 1, 0.3f}) * Transform::scale({0.8f, 1.2f, 1});

std::unique_ptr<Shape> closedShape(const std::string& name) {
  const Vec3f lo{-0.5f, -0.3f, -0.4f};
  if (name == "box") return std::make_unique<Box>(lo, lo + Vec3f{1, 0.6f, 0.8f});
  if (name == "cylinder") return std::make_unique<Cylinder>(0.4f, 0.7f, true);
  if (name == "cone") return std::make_unique<Cone>(0.5f, 0.8f, true);
  return std::make_unique<Sphere>(Vec3f{0.1f, 0, 0}, 0.5f);  // an ellipsoid once sheared
}

std::vector<LightCase> lightCases() {
  std::vector<LightCase> cases;
  const Vec3f c{-0.5f, 2, -0.75f}, eu{1, 0, 0}, ev{0, 0.2f, 1.5f};  // tilted, facing down-ish
  // cross(eu, ev) = (0, -1.5, 0.2): the emitting side is below.
  auto quad = [&] { return std::make_unique<Quad>(c, eu, ev); };
  cases.push_back({"quad",
                   makeShapeLight(quad(), {}, constant({1, 2, 3}, false)),
                   quad(),
                   {0.2f, 0, 0.1f},
                   {0, 1, 0}});
  cases.push_back({"quad two-sided",
                   makeShapeLight(quad(), {}, constant({1, 1, 1}, true)),
                   quad(),
                   {0.3f, 3, 0},
                   {0, -1, 0}});
  // The disk shape: radius 0.8 at the origin, normal +Y; the receiver is above.
  cases.push_back({"disk",
                   makeShapeLight(std::make_unique<Disk>(0.8f), {}, constant({2, 1, 1}, false)),
                   std::make_unique<Disk>(0.8f),
                   {0.3f, 1.5f, -0.2f},
                   {0, -1, 0}});
  auto sphere = [](Vec3f centre, float r) { return std::make_unique<Sphere>(centre, r); };
  cases.push_back({"sphere outside",
                   makeShapeLight(sphere({1, 2, 0}, 0.5f), {}, constant({1, 1, 2}, false)),
                   sphere({1, 2, 0}, 0.5f),
                   {0, 0, 0},
                   {0, 1, 0}});
  cases.push_back({"sphere far",
                   makeShapeLight(sphere({0, 6, 0}, 0.5f), {}, constant({1, 1, 1}, false)),
                   sphere({0, 6, 0}, 0.5f),
                   {0, 0, 0},
                   {0, 1, 0}});
  cases.push_back({"sphere inside",
                   makeShapeLight(sphere({0, 0, 0}, 2.0f), {}, constant({1, 1, 1}, true)),
                   sphere({0, 0, 0}, 2.0f),
                   {0.5f, -0.3f, 0.2f},
                   {}});
  // Inside a glowing box: every face, from a point in a medium.
  auto room = [] { return std::make_unique<Box>(Vec3f{-1, -0.5f, -2}, Vec3f{1, 1.5f, 1}); };
  cases.push_back({"box inside",
                   makeShapeLight(room(), {}, constant({1, 1, 1}, true)),
                   room(),
                   {0.2f, -0.1f, 0.3f},
                   {}});
  cases.push_back({"mesh",
                   meshQuad(c, eu, ev, constant({1, 2, 3}, false)),
                   quad(),
                   {0.2f, 0, 0.1f},
                   {0, 1, 0}});
  // One-sided, so that samples anywhere but the side the receiver sees would come back empty.
  for (const char* name : {"box", "cylinder", "cone", "ellipsoid"}) {
    LightCase lc{name,
                 makeShapeLight(closedShape(name), kSheared, constant({1, 2, 1}, false)),
                 closedShape(name),
                 {0, 0, 0},
                 {0, 1, 0}};
    lc.world = kSheared;
    lc.closed = true;
    cases.push_back(std::move(lc));
  }
  return cases;
}

LightSampleContext contextAt(const LightCase& lc) {
  LightSampleContext ctx;
  ctx.p = lc.receiver;
  ctx.n = ctx.ns = lc.receiverNormal;
  return ctx;
}

// The first point where the ray from p along unit w meets the shape placed by `world`.
std::optional<LightHit> trace(const Shape& shape, Vec3f p, Vec3f w,
                              const Transform& world = Transform()) {
  const Transform objectFromWorld = world.inverse();
  Ray ray{objectFromWorld.point(p), objectFromWorld.vector(w), 0, kInfinity, 0};
  ShapeHit h;
  if (!shape.intersect(ray, &h)) return std::nullopt;
  ShapeSurface s = shape.surface(ray, h, {});
  return LightHit{p + w * h.t, normalize(world.normal(s.n))};
}

TEST(AreaLights, SampleLiMatchesPdfLiChi2) {
  auto cases = lightCases();
  for (const LightCase& lc : cases) {
    SCOPED_TRACE(lc.name);
    // A distant sphere's cone is too narrow for float directions: samples on its silhouette
    // land one rounding step outside the bins that hold it. The closed-form irradiance test
    // below covers distant spheres instead.
    if (lc.name == "sphere far") continue;
    const LightSampleContext ctx = contextAt(lc);
    test::Chi2Options options;
    options.sampleCount = 300'000;
    options.testCount = int(cases.size()) - 1;
    // Peaked lights get a fine cap around the direction towards them.
    const Vec3f towards = normalize(lc.light->bounds()->bounds.center() - ctx.p);
    if (lc.name.find("inside") == std::string::npos) {
      options.binFrame = Frame::fromZ(towards);
      options.capCosTheta = 0.5f;
      // A sphere's cone edge on a bin edge: cubature never straddles its discontinuity.
      if (lc.name.rfind("sphere", 0) == 0) {
        const Vec3f c = lc.light->bounds()->bounds.center();
        const float r = 0.5f, d2 = lengthSquared(c - ctx.p);
        options.capCosTheta = std::sqrt(1 - r * r / d2);
      }
    }
    auto sample = [&](Vec2f u, float) -> std::optional<Vec3f> {
      auto s = lc.light->sampleLi(ctx, u);
      if (!s) return std::nullopt;
      return s->wi;
    };
    auto pdf = [&](Vec3f w) -> float {
      auto hit = trace(*lc.shape, ctx.p, w, lc.world);
      return hit ? lc.light->pdfLi(ctx, w, *hit) : 0.0f;
    };
    test::Chi2Result r = test::chi2Test(sample, pdf, options);
    EXPECT_TRUE(r.passed) << r.message;
    // Closed shapes too: only the side the receiver sees is sampled, and it emits towards it.
    EXPECT_NEAR(r.pdfIntegral, 1.0, 2e-3);
  }
}

TEST(AreaLights, SampledDirectionsTraceBackToTheLight) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uni(0.0f, 0.999999f);
  for (const LightCase& lc : lightCases()) {
    SCOPED_TRACE(lc.name);
    const LightSampleContext ctx = contextAt(lc);
    int found = 0, misses = 0;
    for (int i = 0; i < 2000; ++i) {
      auto s = lc.light->sampleLi(ctx, {uni(rng), uni(rng)});
      if (!s) continue;
      ++found;
      EXPECT_FALSE(s->delta);
      EXPECT_NEAR(length(s->wi), 1.0f, 1e-5f);
      auto hit = trace(*lc.shape, ctx.p, s->wi, lc.world);
      if (!hit) {  // a closed shape's silhouette: a sample at cos ~ 0 may round to a miss
        ++misses;
        continue;
      }
      const float scale = std::max(1.0f, length(s->pLight - ctx.p));
      EXPECT_LT(length(hit->p - s->pLight), 2e-4f * scale);
      EXPECT_NEAR(std::abs(dot(hit->n, s->nLight)), 1.0f, 1e-4f);
      const float pdf = lc.light->pdfLi(ctx, s->wi, *hit);
      // pdf ∝ 1 / cos at the light: near the silhouette the normals' rounding (the traced hit's
      // from its own point, the sample's from its parameters) grows by 1 / cos.
      const float cosLight = std::abs(dot(s->nLight, s->wi));
      EXPECT_NEAR(pdf, s->pdf, (2e-3f + 2e-4f / cosLight) * s->pdf);
      // The shadow ray ends just short of the light and starts just off the receiver.
      Ray shadow = shadowRay(ctx, *s);
      const Transform objectFromWorld = lc.world.inverse();
      shadow.o = objectFromWorld.point(shadow.o);
      shadow.d = objectFromWorld.vector(shadow.d);
      ShapeHit h;
      EXPECT_FALSE(lc.shape->intersect(shadow, &h)) << "the shadow ray reaches the light itself";
    }
    EXPECT_GT(found, 1990);
    EXPECT_LE(misses, lc.closed ? found / 200 : 0);
  }
}

TEST(AreaLights, LightPathPowerMatchesPhi) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> uni(0.0f, 0.999999f);
  for (const LightCase& lc : lightCases()) {
    SCOPED_TRACE(lc.name);
    constexpr int kN = 200'000;
    Rgb sum;
    for (int i = 0; i < kN; ++i) {
      auto s = lc.light->sampleLe({uni(rng), uni(rng)}, {uni(rng), uni(rng)}, 0);
      if (!s) continue;
      EXPECT_NEAR(length(s->ray.d), 1.0f, 1e-5f);
      sum += s->beta();
    }
    const Rgb phi = lc.light->phi();
    const Rgb mean = sum * (1.0f / kN);
    EXPECT_GT(phi.x, 0);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], phi[c], 0.01f * phi[c]) << "channel " << c;
    EXPECT_NEAR(lc.light->bounds()->phi, luminance(phi), 1e-4f * luminance(phi));
  }
}

// The mean of L cos / pdf over `n` samples: the irradiance at ctx.
float irradiance(const Light& light, const LightSampleContext& ctx, int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uni(0.0f, 0.999999f);
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    auto s = light.sampleLi(ctx, {uni(rng), uni(rng)});
    if (!s) continue;
    sum += double(s->L.x) * std::max(0.0f, dot(ctx.n, s->wi)) / s->pdf;
  }
  return float(sum / n);
}

TEST(AreaLights, SquareIrradianceMatchesClosedForm) {
  // A square of half-side a at height h over the receiver, facing it: the form factor of a
  // differential area to a parallel square centred above it gives
  // E = 4 L X / sqrt(1 + X^2) atan(X / sqrt(1 + X^2)), X = a / h.
  const float a = 0.5f, L = 3;
  for (float h : {0.25f, 1.0f, 4.0f}) {
    SCOPED_TRACE(h);
    auto quad = makeShapeLight(
        std::make_unique<Quad>(Vec3f{-a, h, -a}, Vec3f{2 * a, 0, 0}, Vec3f{0, 0, 2 * a}), {},
        constant({L, L, L}, false));
    LightSampleContext ctx;
    ctx.n = ctx.ns = {0, 1, 0};
    const float X = a / h, s = std::sqrt(1 + X * X);
    const float exact = 4 * L * X / s * std::atan(X / s);
    EXPECT_NEAR(irradiance(*quad, ctx, 200'000, 1), exact, 0.01f * exact);
  }
}

TEST(AreaLights, SphereIrradianceMatchesClosedForm) {
  // A sphere above the horizon: E = pi L sin^2(theta_max), whatever its size.
  const float L = 2;
  for (float d : {1.5f, 10.0f, 1000.0f}) {
    SCOPED_TRACE(d);
    auto sphere = makeShapeLight(std::make_unique<Sphere>(Vec3f{0, d, 0}, 1.0f), {},
                                 constant({L, L, L}, false));
    LightSampleContext ctx;
    ctx.n = ctx.ns = {0, 1, 0};
    const float exact = kPi * L / (d * d);
    EXPECT_NEAR(irradiance(*sphere, ctx, 100'000, 2), exact, 0.01f * exact);
  }
}

TEST(AreaLights, EmissiveMeshIrradianceEqualsQuad) {
  const Vec3f c{-1, 2, -0.5f}, eu{2, 0.5f, 0}, ev{0, 0, 1};  // facing down
  const AreaEmission e = constant({1.5f, 1.5f, 1.5f}, false);
  auto quad = makeShapeLight(std::make_unique<Quad>(c, eu, ev), {}, e);
  auto mesh = meshQuad(c, eu, ev, e);
  EXPECT_NEAR(mesh->area(), quad->area(), 1e-5f);
  for (Vec3f p : {Vec3f{0, 0, 0}, Vec3f{1, 1, 1}, Vec3f{-2, 0.5f, 0}}) {
    LightSampleContext ctx;
    ctx.p = p;
    ctx.n = ctx.ns = {0, 1, 0};
    const float q = irradiance(*quad, ctx, 200'000, 5), m = irradiance(*mesh, ctx, 200'000, 6);
    EXPECT_GT(q, 0);
    EXPECT_NEAR(m, q, 0.015f * q);
  }
}

// A mesh whose emissive texture glows on a small patch (a glTF lamp or screen): its light
// samples land on the patch, not spread over the mesh by area, and next-event estimation still
// gives the irradiance the texture's radiance does, with pdfLi at each sampled triangle equal to
// the sample's density.
TEST(AreaLights, TexturedMeshLightsSampleWhereTheTextureGlows) {
  // An 8x8 grid of quads over [-1, 1]² at height 2, facing down, uv = [0, 1]² over it; the
  // texture (64² texels) emits 4 on uv [0.625, 0.875) x [0.125, 0.375): 8 of its 128 triangles.
  constexpr int kCells = 8, kTexels = 64;
  constexpr float kL = 4, kHeight = 2;
  EmissiveMesh grid;
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i) {
      const float u = float(i) / kCells, v = float(j) / kCells;
      grid.positions.push_back({-1 + 2 * u, kHeight, -1 + 2 * v});
      grid.uvs.push_back({u, v});
    }
  for (uint32_t j = 0; j < kCells; ++j)
    for (uint32_t i = 0; i < kCells; ++i) {
      const uint32_t v00 = j * (kCells + 1) + i, v10 = v00 + 1, v01 = v00 + kCells + 1,
                     v11 = v01 + 1;
      grid.indices.insert(grid.indices.end(), {v00, v10, v11, v00, v11, v01});
    }
  auto glows = [](Vec2f uv) {
    return uv.x >= 0.625f && uv.x < 0.875f && uv.y >= 0.125f && uv.y < 0.375f;
  };
  std::vector<float> texels(size_t(kTexels) * kTexels * 3, 0.0f);
  for (int y = 0; y < kTexels; ++y)
    for (int x = 0; x < kTexels; ++x)
      if (glows({(float(x) + 0.5f) / kTexels, (float(y) + 0.5f) / kTexels}))
        for (int c = 0; c < 3; ++c) texels[size_t((y * kTexels + x) * 3 + c)] = kL;
  TextureImages images(&oiio::imageDecoder);
  const auto image = images.addPixels("lamp", kTexels, kTexels, 3, texels, ColorEncoding::Linear);
  for (TextureFilter filter : {TextureFilter::Linear, TextureFilter::Mipmap}) {
    SCOPED_TRACE(filter == TextureFilter::Mipmap ? "mipmap" : "linear");
    const ImageTexture texture(images, image, TextureMapping{}, TextureWrap::Clamp,
                               TextureWrap::Clamp, filter);
    const LambertMaterial material(ColorParam{{0, 0, 0}}, ColorParam{{1, 1, 1}, &texture});
    AreaEmission emission;
    emission.material = &material;
    const AreaLight light(grid, emission);

    // Power: pi L times the glowing area (0.5 x 0.5).
    EXPECT_NEAR(light.phi().x, kPi * kL * 0.25f, 0.01f * kPi * kL * 0.25f);

    LightSampleContext ctx;
    ctx.p = {0.1f, 0, -0.2f};
    ctx.n = ctx.ns = {0, 1, 0};
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> uni(0.0f, 0.999999f);
    int samples = 0, dark = 0, checked = 0;
    for (int k = 0; k < 20'000; ++k) {
      auto s = light.sampleLi(ctx, {uni(rng), uni(rng)});
      ++samples;  // a dark point gives no sample at all: count every draw
      if (!s) {
        ++dark;
        continue;
      }
      // The triangle under the sample, and its density there through pdfLi.
      const float gx = (s->pLight.x + 1) / 2 * kCells, gz = (s->pLight.z + 1) / 2 * kCells;
      const int ci = std::min(int(gx), kCells - 1), cj = std::min(int(gz), kCells - 1);
      const float dx = gx - float(ci), dz = gz - float(cj);
      if (std::abs(dx - dz) < 1e-4f) continue;  // on the diagonal: either triangle
      const uint32_t prim = uint32_t(2 * (cj * kCells + ci) + (dz > dx ? 1 : 0));
      const float pdf = light.pdfLi(ctx, s->wi, LightHit{s->pLight, s->nLight, prim});
      ASSERT_NEAR(pdf, s->pdf, 1e-4f * s->pdf) << "triangle " << prim;
      ++checked;
    }
    EXPECT_GT(checked, 15'000);
    // Drawn by area, 15 in 16 samples would land on black.
    EXPECT_LT(dark, samples / 50) << dark << " of " << samples << " samples were dark";

    // Irradiance against the glowing square integrated directly (midpoint rule): L cos² / d².
    double exact = 0;
    constexpr int kSteps = 400;
    const float x0 = 0.25f, z0 = -0.75f, side = 0.5f, dA = (side / kSteps) * (side / kSteps);
    for (int b = 0; b < kSteps; ++b)
      for (int a = 0; a < kSteps; ++a) {
        const Vec3f q{x0 + (float(a) + 0.5f) * side / kSteps, kHeight,
                      z0 + (float(b) + 0.5f) * side / kSteps};
        const float d2 = lengthSquared(q - ctx.p), cosine = kHeight / std::sqrt(d2);
        exact += double(kL * cosine * cosine / d2 * dA);
      }
    EXPECT_NEAR(irradiance(light, ctx, 200'000, 4), exact, 0.01 * exact);
  }
}

// Closed shapes under shear: next-event estimation's irradiance equals an estimator that
// never asks the light for a density, cosine-distributed rays traced against the placed shape
// (E = pi x the mean radiance they find). Checks the density's normalisation, which the
// chi-square test above (samples against pdfLi) cannot see.
TEST(AreaLights, ClosedShapeIrradianceMatchesTracedRays) {
  for (const LightCase& lc : lightCases()) {
    if (!lc.closed) continue;
    SCOPED_TRACE(lc.name);
    const LightSampleContext ctx = contextAt(lc);
    const float nee = irradiance(*lc.light, ctx, 400'000, 8);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> uni(0.0f, 0.999999f);
    constexpr int kRays = 400'000;
    const Frame frame = Frame::fromZ(ctx.n);
    int hits = 0;
    for (int i = 0; i < kRays; ++i) {
      const Vec3f w = frame.fromLocal(sampleCosineHemisphere({uni(rng), uni(rng)}));
      hits += trace(*lc.shape, ctx.p, w, lc.world).has_value();
    }
    const double traced = kPi * 1.0 * hits / kRays;  // radiance 1 in the x channel
    // Both have about 0.5% standard error here.
    EXPECT_GT(nee, 0);
    EXPECT_NEAR(nee, traced, 0.025 * traced);
  }
}

// Under a similarity, a placed sphere is the sphere of the scaled radius: same area, power and
// irradiance (its cone, sampled in object space, is the world cone).
TEST(AreaLights, PlacedSphereMatchesTheScaledSphere) {
  const Transform place = Transform::translate({0.5f, 3, 0}) * Transform::rotate(40, {0, 0, 1}) *
                          Transform::scale({0.7f, 0.7f, 0.7f});
  auto placed = makeShapeLight(std::make_unique<Sphere>(Vec3f{0, 0, 0}, 1.0f), place,
                               constant({2, 2, 2}, false));
  auto sphere = makeShapeLight(std::make_unique<Sphere>(Vec3f{0.5f, 3, 0}, 0.7f), {},
                               constant({2, 2, 2}, false));
  EXPECT_NEAR(placed->area(), sphere->area(), 1e-3f * sphere->area());
  EXPECT_NEAR(placed->phi().x, sphere->phi().x, 1e-3f * sphere->phi().x);
  LightSampleContext ctx;
  ctx.n = ctx.ns = {0, 1, 0};
  for (Vec2f u : {Vec2f{0.1f, 0.2f}, Vec2f{0.7f, 0.9f}}) {
    auto a = placed->sampleLi(ctx, u), b = sphere->sampleLi(ctx, u);
    ASSERT_TRUE(a && b);
    EXPECT_NEAR(a->pdf, b->pdf, 1e-3f * b->pdf);  // uniform in the same cone
  }
  const float a = irradiance(*placed, ctx, 100'000, 3), b = irradiance(*sphere, ctx, 100'000, 4);
  EXPECT_NEAR(a, b, 0.01f * b);
}

// Closed emitters glowing on both sides (as emitting materials do): no sample lands where the
// light's own shape hides it from the receiver. Before shapes sampled their visible part (area
// sampling of the whole surface), 53-67% of such samples were hidden (box, cylinder, cone,
// ellipsoid); only the sphere light's cone wasted none.
TEST(AreaLights, ClosedEmittersWasteNoSamplesOnTheirFarSide) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> uni(0.0f, 0.999999f);
  const Vec3f receivers[] = {{0, -3, 0}, {3, 0.2f, 0.5f}, {-2, 2.5f, 1}, {0.5f, 0.3f, -4}};
  for (const char* name : {"box", "cylinder", "cone", "ellipsoid"})
    for (const Transform& world : {Transform(), kSheared}) {
      SCOPED_TRACE(name);
      const std::unique_ptr<Shape> shape = closedShape(name);
      auto light = makeShapeLight(closedShape(name), world, constant({1, 1, 1}, true));
      const Transform objectFromWorld = world.inverse();
      int total = 0, hidden = 0;
      for (Vec3f r : receivers) {
        LightSampleContext ctx;
        ctx.p = world.point({0, 0, 0}) + r;
        for (int i = 0; i < 5000; ++i, ++total) {
          auto s = light->sampleLi(ctx, {uni(rng), uni(rng)});
          ASSERT_TRUE(s.has_value());
          // The shape's first hit along the way to the sample must be the sample itself.
          Ray ray{objectFromWorld.point(ctx.p), objectFromWorld.vector(s->pLight - ctx.p), 0,
                  kInfinity, 0};
          ShapeHit h;
          hidden += !shape->intersect(ray, &h) || h.t < 0.999f;
        }
      }
      std::printf("[ wasted   ] %-9s %-9s %d of %d samples hidden by the light itself\n", name,
                  world.isIdentity() ? "" : "(sheared)", hidden, total);
      EXPECT_LE(hidden, total / 500);  // silhouette rounding only
    }
}

TEST(AreaLights, OneSidedLightsAreDarkBehind) {
  auto quadShape = [] {  // normal -Y
    return std::make_unique<Quad>(Vec3f{0, 1, 0}, Vec3f{1, 0, 0}, Vec3f{0, 0, 1});
  };
  auto quad = makeShapeLight(quadShape(), {}, constant({1, 1, 1}, false));
  LightSampleContext below, above;
  below.p = {0.5f, 0, 0.5f};
  above.p = {0.5f, 2, 0.5f};
  EXPECT_TRUE(quad->sampleLi(below, {0.3f, 0.6f}).has_value());
  EXPECT_FALSE(quad->sampleLi(above, {0.3f, 0.6f}).has_value());
  auto both = makeShapeLight(quadShape(), {}, constant({1, 1, 1}, true));
  EXPECT_TRUE(both->sampleLi(above, {0.3f, 0.6f}).has_value());
  EXPECT_NEAR(luminance(both->phi()), 2 * luminance(quad->phi()), 1e-4f);
}

TEST(AreaLights, ZeroAreaLightsGiveNoSamples) {
  // A mesh of one degenerate triangle.
  AreaLight flat(EmissiveMesh{{{0, 1, 0}, {1, 1, 0}, {2, 1, 0}}, {0, 1, 2}, {}, {}},
                 constant({1, 1, 1}, true));
  LightSampleContext ctx;
  EXPECT_FALSE(flat.sampleLi(ctx, {0.5f, 0.5f}).has_value());
  EXPECT_FALSE(flat.sampleLe({0.5f, 0.5f}, {0.5f, 0.5f}, 0).has_value());
  EXPECT_EQ(luminance(flat.phi()), 0);
}

}  // namespace
}  // namespace glint

// --- Projective ----------------------------------------------------------------------------------

namespace glint {
namespace {

TEST(ProjectiveLight, IrradianceFollowsTheSlide) {
  // A 4 x 4 checker slide (black and white), the projector at the origin looking down -Y at
  // the plane y = -h: each point's irradiance is I * ((1 - a) + a * slide(uv)) cos / r^2,
  // with uv where the point projects onto the slide.
  TextureMapping mapping;
  mapping.scale = {4, 4, 1};
  CheckerTexture checker(mapping, {0, 0, 0}, {1, 1, 1}, false);
  const float h = 2, fov = kPi / 2, I = 5;  // tan(fov/2) = 1: the slide covers |x|, |z| <= h
  for (float a : {0.0f, 0.3f, 1.0f}) {
    SCOPED_TRACE(a);
    const Transform world = Transform::lookAt({0, 0, 0}, {0, -1, 0}, {0, 0, -1});
    ProjectiveLight light(world, {I, I, I}, fov, &checker, a, true);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> uni(-1.2f, 1.2f);
    int inside = 0;
    for (int i = 0; i < 500; ++i) {
      const Vec3f p{uni(rng) * h, -h, uni(rng) * h};
      LightSampleContext ctx;
      ctx.p = p;
      ctx.n = ctx.ns = {0, 1, 0};
      auto s = light.sampleLi(ctx, {0.5f, 0.5f});
      // The slide in light space: +X is world +X... found independently by projecting p.
      const Vec3f local = world.inverse().point(p);
      const float x = local.x / -local.z, y = local.y / -local.z;  // tan(fov/2) = 1
      if (std::abs(x) > 1 || std::abs(y) > 1) {
        EXPECT_FALSE(s.has_value()) << "lit outside the frustum";
        continue;
      }
      // Keep away from checker edges, where the test's rounding could pick the other cell.
      const float cu = (0.5f * x + 0.5f) * 4, cv = (0.5f * y + 0.5f) * 4;
      if (std::abs(cu - std::round(cu)) < 1e-3f || std::abs(cv - std::round(cv)) < 1e-3f) continue;
      ++inside;
      const float slide = ((int(std::floor(cu)) + int(std::floor(cv))) % 2 == 0) ? 0.0f : 1.0f;
      const float r2 = lengthSquared(p), cosTheta = h / std::sqrt(r2);
      const float expected = I * ((1 - a) + a * slide) * cosTheta / r2;
      const float got = s ? s->L.x * std::max(0.0f, dot(ctx.n, s->wi)) : 0.0f;
      EXPECT_NEAR(got, expected, 1e-4f * I) << "at " << p.x << ", " << p.z;
    }
    EXPECT_GT(inside, 250);
    // Power: half the slide is black, so phi lies between full and (1 - a) of the plain
    // frustum's; and light paths carry it.
    ProjectiveLight plain(world, {I, I, I}, fov, nullptr, a, true);
    constexpr int kN = 200'000;
    std::uniform_real_distribution<float> unit(0.0f, 0.999999f);
    double sum = 0;
    for (int i = 0; i < kN; ++i)
      if (auto le = light.sampleLe({0, 0}, {unit(rng), unit(rng)}, 0)) sum += le->beta().x;
    EXPECT_NEAR(sum / kN, light.phi().x, 0.01 * plain.phi().x);
    EXPECT_NEAR(light.phi().x, plain.phi().x * (1 - a / 2), 0.01f * plain.phi().x);
  }
}

}  // namespace
}  // namespace glint

// --- Environment ---------------------------------------------------------------------------------

namespace glint {
namespace {

// A small map: dim sky, a bright sun patch, a black band (where the density must be 0). The
// two rows at each pole are black too: there the solid-angle density has an (integrable)
// 1/sin singularity that the chi-square test's cubature cannot integrate accurately, and the
// density of a cell next to a lit row is not zero (it covers the bilinear lookup's reach).
ImageEnvironmentLight testEnvironment(float rotation) {
  const int w = 32, h = 16;
  std::vector<Rgb> pixels(size_t(w * h), Rgb{0.2f, 0.3f, 0.5f});
  for (int y : {0, 1, h - 2, h - 1})
    for (int x = 0; x < w; ++x) pixels[size_t(y * w + x)] = {0, 0, 0};
  for (int y = 3; y < 5; ++y)
    for (int x = 20; x < 23; ++x) pixels[size_t(y * w + x)] = {50, 40, 30};
  for (int x = 0; x < w; ++x) pixels[size_t(12 * w + x)] = {0, 0, 0};
  return ImageEnvironmentLight(w, h, std::move(pixels), 2.0f, rotation);
}

TEST(EnvironmentLight, Distribution2DMatchesItsPdf) {
  // Frequencies of cells against the normalised values.
  const int nu = 4, nv = 3;
  const std::vector<float> f = {1, 2, 0, 3, 0, 0, 0, 0, 5, 1, 1, 1};
  Distribution2D d(f, nu, nv);
  double total = 0;
  for (float v : f) total += v;
  std::vector<int> counts(f.size(), 0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> uni(0.0f, 0.999999f);
  constexpr int kN = 400'000;
  for (int i = 0; i < kN; ++i) {
    float pdf = 0;
    const Vec2f p = d.sample({uni(rng), uni(rng)}, &pdf);
    ASSERT_GE(p.x, 0);
    ASSERT_LT(p.x, 1);
    const int cell = std::min(int(p.y * nv), nv - 1) * nu + std::min(int(p.x * nu), nu - 1);
    ++counts[size_t(cell)];
    EXPECT_NEAR(pdf, d.pdf(p), 1e-5f * pdf);
    EXPECT_NEAR(pdf, f[size_t(cell)] / total * nu * nv, 1e-4f * pdf);
  }
  for (size_t i = 0; i < f.size(); ++i) {
    const double p = f[i] / total;
    EXPECT_NEAR(counts[i] / double(kN), p, 5 * std::sqrt(p * (1 - p) / kN) + 1e-9) << "cell " << i;
  }
}

TEST(EnvironmentLight, SampleLiMatchesPdfLiChi2) {
  for (float rotation : {0.0f, 1.0f}) {
    const ImageEnvironmentLight env = testEnvironment(rotation);
    LightSampleContext ctx;
    auto sample = [&](Vec2f u, float) -> std::optional<Vec3f> {
      auto s = env.sampleLi(ctx, u);
      if (!s) return std::nullopt;
      EXPECT_TRUE(s->infinite);
      EXPECT_NEAR(s->pdf, env.pdfLi(ctx, s->wi, {}), 1e-4f * s->pdf);
      EXPECT_EQ(s->L, env.Le(s->wi));
      return s->wi;
    };
    auto pdf = [&](Vec3f w) { return env.pdfLi(ctx, w, {}); };
    test::Chi2Options options;
    options.sampleCount = 300'000;
    options.testCount = 2;
    test::Chi2Result r = test::chi2Test(sample, pdf, options);
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 2e-3);
  }
}

TEST(EnvironmentLight, MappingRoundTripsAndRotates) {
  const ImageEnvironmentLight env = testEnvironment(0), turned = testEnvironment(kPi / 2);
  // The map's centre looks down -Z; its top is +Y.
  EXPECT_NEAR(env.uvOf({0, 0, -1}).x, 0.5f, 1e-6f);
  EXPECT_NEAR(env.uvOf({0, 1, 0}).y, 0.0f, 1e-6f);
  for (Vec2f uv : {Vec2f{0.1f, 0.3f}, Vec2f{0.7f, 0.8f}, Vec2f{0.5f, 0.5f}}) {
    const Vec2f back = turned.uvOf(turned.directionOf(uv));
    EXPECT_NEAR(back.x, uv.x, 1e-5f);
    EXPECT_NEAR(back.y, uv.y, 1e-5f);
    // Turning by 90 degrees about +Y moves the map a quarter turn.
    const Vec3f d = env.directionOf(uv), t = turned.directionOf(uv);
    EXPECT_NEAR(d.y, t.y, 1e-6f);
    EXPECT_NEAR(std::abs(dot(Vec3f{d.x, 0, d.z}, Vec3f{t.x, 0, t.z})), 0.0f, 1e-5f);
  }
}

TEST(EnvironmentLight, RadianceIsBilinearAndTheDensityCoversIt) {
  const ImageEnvironmentLight env = testEnvironment(0.3f);
  LightSampleContext ctx;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> uni(0.0f, 0.999999f);
  int lit = 0;
  for (int i = 0; i < 100'000; ++i) {
    const Vec3f d = sampleUniformSphere({uni(rng), uni(rng)});
    if (maxComponent(env.Le(d)) > 0) {
      ++lit;
      // Where the interpolated radiance reaches (the black band's and the poles' edges
      // included), sampleLi must be able to go: else the estimate loses that light.
      ASSERT_GT(env.pdfLi(ctx, d, {}), 0) << d.x << " " << d.y << " " << d.z;
    }
  }
  EXPECT_GT(lit, 50'000);
  // Bilinear: half-way between the centres of a dim sky pixel (row 5) and a sun pixel (row 4),
  // the mean of the two; no step at the pixel border.
  const float u = 21.5f / 32;
  const Rgb sky = Rgb{0.2f, 0.3f, 0.5f} * 2, sun = Rgb{50, 40, 30} * 2;
  const Rgb half = env.Le(env.directionOf({u, 5.0f / 16}));
  EXPECT_NEAR(half.x, 0.5f * (sky.x + sun.x), 1e-2f);
  const Rgb above = env.Le(env.directionOf({u, 5.0f / 16 - 1e-4f}));
  const Rgb below = env.Le(env.directionOf({u, 5.0f / 16 + 1e-4f}));
  EXPECT_NEAR(above.x, below.x, 1.0f);  // the slope over 2e-4 of v; nearest would jump by 100
}

TEST(EnvironmentLight, TheStudioIsGreyAndGivesIrradiancePiFromAbove) {
  constexpr int w = 512, h = 256;
  const ImageEnvironmentLight studio(w, h, studioEnvironment(w, h), 1, 0);
  // Irradiance of a surface facing +Y: cosine-weighted Monte Carlo over the upper hemisphere.
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> uni(0.0f, 0.999999f);
  constexpr int kN = 400'000;
  double sum = 0;
  for (int i = 0; i < kN; ++i) {
    const Vec3f l = sampleCosineHemisphere({uni(rng), uni(rng)});
    const Rgb L = studio.Le({l.x, l.z, -l.y});  // local +Z is world +Y
    EXPECT_EQ(L.x, L.y);
    EXPECT_EQ(L.y, L.z);
    sum += L.y;
  }
  // E = pi * mean(L) for cosine-weighted directions: E / pi = 1 (the bilinear lookup and the
  // midpoint rule the scale comes from agree to well under a percent at this resolution).
  EXPECT_NEAR(sum / kN, 1.0, 0.01);
  // The softbox (front left, up) outshines the sky; the floor is darker than the sky.
  const Rgb key = studio.Le(normalize(Vec3f{-0.55f, 0.65f, 0.5f}));
  const Rgb zenith = studio.Le({0, 1, 0}), floor = studio.Le({0, -1, 0});
  EXPECT_GT(key.y, 5 * zenith.y);
  EXPECT_LT(floor.y, zenith.y);
}

TEST(EnvironmentLight, LightPathPowerMatchesPhi) {
  ImageEnvironmentLight env = testEnvironment(0.4f);
  env.preprocess(Bounds3f{{-1, -2, -1}, {3, 1, 2}});
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> uni(0.0f, 0.999999f);
  constexpr int kN = 200'000;
  Rgb sum;
  for (int i = 0; i < kN; ++i)
    if (auto s = env.sampleLe({uni(rng), uni(rng)}, {uni(rng), uni(rng)}, 0)) sum += s->beta();
  const Rgb phi = env.phi();
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c] / kN, phi[c], 0.01f * phi[c]);
}

}  // namespace
}  // namespace glint
