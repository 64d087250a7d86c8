// Procedural textures: pattern weights in [0, 1] and colours between colorA and colorB, exact
// gradients against finite differences (world and object mapping), determinism, random
// colours, checkerboards and the texture mapping.
#include "materials/procedural.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace glint {
namespace {

float uniformFloat(std::mt19937_64& rng) { return float(rng() >> 40) * 0x1p-24f; }
Vec3f randomPoint(std::mt19937_64& rng, float extent) {
  return {extent * (2 * uniformFloat(rng) - 1), extent * (2 * uniformFloat(rng) - 1),
          extent * (2 * uniformFloat(rng) - 1)};
}

const std::vector<NoisePattern> kPatterns = {NoisePattern::Noise,      NoisePattern::Fbm,
                                             NoisePattern::Turbulence, NoisePattern::Marble,
                                             NoisePattern::Wood,       NoisePattern::Clouds};
const char* name(NoisePattern p) {
  switch (p) {
    case NoisePattern::Noise:
      return "noise";
    case NoisePattern::Fbm:
      return "fbm";
    case NoisePattern::Turbulence:
      return "turbulence";
    case NoisePattern::Marble:
      return "marble";
    case NoisePattern::Wood:
      return "wood";
    case NoisePattern::Clouds:
      return "clouds";
  }
  return "?";
}

TextureMapping worldMapping(Vec3f scale = {1, 1, 1}, Vec3f offset = {0, 0, 0}) {
  TextureMapping m;
  m.space = TextureMapping::Space::World;
  m.scale = scale;
  m.offset = offset;
  return m;
}

NoiseParams patternParams(NoisePattern pattern, uint64_t seed = 3, Rgb a = {0, 0, 0},
                          Rgb b = {1, 1, 1}) {
  NoiseParams p;
  p.pattern = pattern;
  p.seed = seed;
  p.colorA = a;
  p.colorB = b;
  return p;
}

TexturePoint pointAt(Vec3f p, const Transform* objectFromWorld = nullptr) {
  TexturePoint tp;
  tp.p = p;
  tp.objectFromWorld = objectFromWorld;
  return tp;
}

// ---------------------------------------------------------------------------------------------
// Noise patterns
// ---------------------------------------------------------------------------------------------

// Every pattern's weight stays in [0, 1] at 1e5 random points over +-20 units (thousands of
// lattice cells), and its colour is lerp(colorA, colorB, weight) with alpha 1.
TEST(NoiseTexture, WeightsStayInTheUnitIntervalAndColoursLerp) {
  const Rgb a{0.9f, 0.2f, 0.1f}, b{0.1f, 0.5f, 1.0f};
  for (NoisePattern pattern : kPatterns) {
    const NoiseTexture tex(worldMapping(), patternParams(pattern, 3, a, b));
    std::mt19937_64 rng(uint64_t(pattern) + 1);
    float lo = 1, hi = 0;
    for (int i = 0; i < 100'000; ++i) {
      const Vec3f p = randomPoint(rng, 20);
      const float w = tex.weight(p, nullptr);
      ASSERT_GE(w, 0) << name(pattern) << " at " << p.x << " " << p.y << " " << p.z;
      ASSERT_LE(w, 1) << name(pattern) << " at " << p.x << " " << p.y << " " << p.z;
      lo = std::min(lo, w), hi = std::max(hi, w);
      if (i % 10 == 0) {
        const Vec4f c = tex.evaluate(pointAt(p));
        const Rgb expected = lerp(w, a, b);
        EXPECT_NEAR(c.x, expected.x, 1e-6f);
        EXPECT_NEAR(c.y, expected.y, 1e-6f);
        EXPECT_NEAR(c.z, expected.z, 1e-6f);
        EXPECT_EQ(c.w, 1);
        // Between the two colours, channel by channel.
        for (int k = 0; k < 3; ++k) {
          EXPECT_GE(c[k], std::min(a[k], b[k]) - 1e-6f);
          EXPECT_LE(c[k], std::max(a[k], b[k]) + 1e-6f);
        }
      }
    }
    // The pattern uses a good part of the range (not stuck at a constant). Turbulence, a sum
    // of |noise| normalised by the bound of its amplitudes, stays below ~0.6 in practice.
    EXPECT_LT(lo, 0.3f) << name(pattern);
    EXPECT_GT(hi, pattern == NoisePattern::Turbulence ? 0.45f : 0.7f) << name(pattern);
  }
}

// Compares scalarGradient with central differences of scalar() along the world axes, with
// steps of 2^-10, 2^-12 and 2^-14 world units until one agrees (marble's veins are steep: the
// truncation error h^2/6 f''' needs the small steps there, float rounding the large ones).
// Tolerance: 2e-3 + 2e-3 |g| plus 4e-6 / (2h) for the rounding of the values: ~2e-7 for
// noise, but marble's phase (up to ~20 radians, in float after the object transform) is off
// by up to ~1e-5, i.e. ~2e-6 in the value.
// A difference straddling a jump (wood's ring edges: the value changes by more than 0.5 over
// the step) is skipped, and so is one straddling a kink (|noise| in turbulence and marble,
// the clamp of clouds), recognised by forward and backward differences at the smallest step
// that disagree by more than twice the tolerance; a wrong gradient shows at smooth points,
// where both one-sided differences agree with each other but not with it.
struct GradientCheck {
  int compared = 0, skipped = 0, failed = 0;
  std::string firstFailure;
};

void checkGradient(const Texture& tex, Vec3f p, const Transform* objectFromWorld,
                   GradientCheck* check) {
  Vec3f g;
  ASSERT_TRUE(tex.scalarGradient(pointAt(p, objectFromWorld), &g));
  const float f0 = tex.scalar(pointAt(p, objectFromWorld));
  for (int axis = 0; axis < 3; ++axis) {
    bool ok = false, skip = false;
    double fd = 0;
    for (float h : {0x1p-10f, 0x1p-12f, 0x1p-14f}) {
      Vec3f plus = p, minus = p;
      plus[axis] += h;
      minus[axis] -= h;
      const float fPlus = tex.scalar(pointAt(plus, objectFromWorld));
      const float fMinus = tex.scalar(pointAt(minus, objectFromWorld));
      if (std::abs(fPlus - fMinus) > 0.5f) {
        skip = true;  // a jump
        break;
      }
      const double step = double(plus[axis]) - double(minus[axis]);
      fd = (double(fPlus) - double(fMinus)) / step;
      const double tolerance = 2e-3 + 2e-3 * std::abs(g[axis]) + 4e-6 / step;
      if (std::abs(fd - g[axis]) <= tolerance) {
        ok = true;
        break;
      }
      if (h == 0x1p-14f) {
        const double forward = (double(fPlus) - f0) / (double(plus[axis]) - p[axis]);
        const double backward = (f0 - double(fMinus)) / (double(p[axis]) - minus[axis]);
        skip = std::abs(forward - backward) > 2 * tolerance;  // a kink
      }
    }
    if (skip) {
      ++check->skipped;
      continue;
    }
    ++check->compared;
    if (!ok && check->failed++ == 0)
      check->firstFailure = "axis " + std::to_string(axis) + " at (" + std::to_string(p.x) + ", " +
                            std::to_string(p.y) + ", " + std::to_string(p.z) + "): exact " +
                            std::to_string(g[axis]) + ", differences " + std::to_string(fd);
  }
}

void expectGradientsMatch(const GradientCheck& c, const std::string& what) {
  EXPECT_GT(c.compared, 0) << what;
  EXPECT_LE(c.failed, c.compared / 1000)
      << what << ": " << c.failed << " of " << c.compared << " differ, e.g. " << c.firstFailure;
  EXPECT_LE(c.skipped, (c.compared + c.skipped) / 20) << what << ": too many jumps";
}

TEST(NoiseTexture, ExactGradientMatchesFiniteDifferencesInWorldSpace) {
  for (NoisePattern pattern : kPatterns)
    for (auto [scale, offset] : {std::pair{Vec3f{1, 1, 1}, Vec3f{0, 0, 0}},
                                 std::pair{Vec3f{0.5f, 2.0f, 1.5f}, Vec3f{0.3f, -2.0f, 7.0f}}}) {
      // Colours with different luminances and a reversed order: the gradient scales with
      // lum(B) - lum(A).
      const NoiseTexture tex(worldMapping(scale, offset),
                             patternParams(pattern, 11, {0.8f, 0.7f, 0.9f}, {0.1f, 0.3f, 0.0f}));
      std::mt19937_64 rng(101 + uint64_t(pattern));
      GradientCheck check;
      for (int i = 0; i < 2000; ++i) checkGradient(tex, randomPoint(rng, 4), nullptr, &check);
      expectGradientsMatch(check,
                           std::string(name(pattern)) + " scale.y " + std::to_string(scale.y));
    }
}

TEST(NoiseTexture, ExactGradientMatchesFiniteDifferencesInObjectSpace) {
  const Transform objectFromWorld = Transform::translate({1.5f, -0.5f, 2}) *
                                    Transform::rotate(50, {0.2f, 1, -0.4f}) *
                                    Transform::scale({1.7f, 0.6f, 1.1f});
  TextureMapping mapping;
  mapping.space = TextureMapping::Space::Object;
  mapping.scale = {1.2f, 1, 0.8f};
  for (NoisePattern pattern : kPatterns) {
    const NoiseTexture tex(mapping, patternParams(pattern, 13));
    std::mt19937_64 rng(201 + uint64_t(pattern));
    GradientCheck check;
    for (int i = 0; i < 2000; ++i)
      checkGradient(tex, randomPoint(rng, 3), &objectFromWorld, &check);
    expectGradientsMatch(check, std::string(name(pattern)) + " in object space");
    // Without an object transform, object space is world space.
    const NoiseTexture world(worldMapping(mapping.scale), patternParams(pattern, 13));
    for (int i = 0; i < 100; ++i) {
      const Vec3f p = randomPoint(rng, 3);
      EXPECT_EQ(tex.scalar(pointAt(p)), world.scalar(pointAt(p)));
    }
  }
}

// uv-mapped patterns have no world-space gradient: bump mapping takes differences instead.
TEST(NoiseTexture, UvMappingHasNoExactGradient) {
  const NoiseTexture tex(TextureMapping{}, patternParams(NoisePattern::Fbm));
  Vec3f g;
  EXPECT_FALSE(tex.scalarGradient(pointAt({0.3f, 0.2f, 0.1f}), &g));
}

// The same seed gives bit-identical values (the lattice is shuffled by glint's own generator);
// another seed gives another pattern (values differ at almost every point).
TEST(NoiseTexture, SeedsAreDeterministic) {
  for (NoisePattern pattern : kPatterns) {
    const NoiseTexture a(worldMapping(), patternParams(pattern, 42));
    const NoiseTexture b(worldMapping(), patternParams(pattern, 42));
    const NoiseTexture c(worldMapping(), patternParams(pattern, 43));
    std::mt19937_64 rng(7);
    int different = 0;
    constexpr int kPoints = 1000;
    for (int i = 0; i < kPoints; ++i) {
      const Vec3f p = randomPoint(rng, 10);
      EXPECT_EQ(a.scalar(pointAt(p)), b.scalar(pointAt(p))) << name(pattern);
      if (std::abs(a.scalar(pointAt(p)) - c.scalar(pointAt(p))) > 1e-4f) ++different;
    }
    EXPECT_GE(different, kPoints * 9 / 10) << name(pattern);
  }
}

// ---------------------------------------------------------------------------------------------
// Random colours
// ---------------------------------------------------------------------------------------------

std::tuple<float, float, float> key(Vec4f c) { return {c.x, c.y, c.z}; }

TEST(RandomColorTexture, ObjectsPrimitivesAndHitsGetTheirOwnColours) {
  const RandomColorTexture perObject(RandomColorTexture::Mode::Object, 5);
  const RandomColorTexture perPrim(RandomColorTexture::Mode::Primitive, 5);
  const RandomColorTexture perHit(RandomColorTexture::Mode::Hit, 5);
  const RandomColorTexture otherSeed(RandomColorTexture::Mode::Object, 6);
  std::mt19937_64 rng(3);
  std::set<std::tuple<float, float, float>> objectColours, primColours, hitColours;
  int sameAcrossSeeds = 0;
  for (uint32_t instance = 0; instance < 1000; ++instance) {
    TexturePoint tp = pointAt(randomPoint(rng, 5));
    tp.instance = instance;
    tp.prim = uint32_t(rng() % 100);
    const Vec4f c = perObject.evaluate(tp);
    // Same object, another primitive and point: the same colour.
    TexturePoint elsewhere = pointAt(randomPoint(rng, 5));
    elsewhere.instance = instance;
    elsewhere.prim = tp.prim + 7;
    EXPECT_EQ(key(perObject.evaluate(elsewhere)), key(c));
    EXPECT_EQ(key(perObject.evaluate(tp)), key(c));  // deterministic
    objectColours.insert(key(c));
    if (key(otherSeed.evaluate(tp)) == key(c)) ++sameAcrossSeeds;
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(c[k], 0);
      EXPECT_LT(c[k], 1);
    }
    EXPECT_EQ(c.w, 1);
    // Per primitive: the same primitive keeps its colour at another point; each of an
    // object's primitives differs.
    TexturePoint samePrim = elsewhere;
    samePrim.prim = tp.prim;
    EXPECT_EQ(key(perPrim.evaluate(samePrim)), key(perPrim.evaluate(tp)));
    if (instance < 10)
      for (uint32_t prim = 0; prim < 100; ++prim) {
        TexturePoint q = tp;
        q.prim = prim;
        const Vec4f pc = perPrim.evaluate(q);
        for (int k = 0; k < 3; ++k) EXPECT_TRUE(pc[k] >= 0 && pc[k] < 1);
        primColours.insert(key(pc));
      }
    // Per hit: depends on the point.
    hitColours.insert(key(perHit.evaluate(tp)));
    hitColours.insert(key(perHit.evaluate(samePrim)));
  }
  EXPECT_EQ(objectColours.size(), 1000u);
  EXPECT_EQ(primColours.size(), 1000u);
  EXPECT_EQ(hitColours.size(), 2000u);
  EXPECT_EQ(sameAcrossSeeds, 0);
}

// ---------------------------------------------------------------------------------------------
// Checkerboards and mapping
// ---------------------------------------------------------------------------------------------

const Rgb kA{1, 0, 0}, kB{0, 0, 1};
bool isA(Vec4f c) { return c.x == 1 && c.z == 0; }
bool isB(Vec4f c) { return c.x == 0 && c.z == 1; }

// Unit squares in uv alternate (including across 0, where floor turns negative), and
// scale/offset move the squares: with scale (4, 2) and offset (0.5, 0.25), the square
// boundaries are at u = (k - 0.5) / 4 and v = (k - 0.25) / 2.
TEST(CheckerTexture, SquaresAlternateInUv) {
  const CheckerTexture plain(TextureMapping{}, kA, kB, false);
  for (int i = -4; i <= 4; ++i)
    for (int j = -4; j <= 4; ++j) {
      TexturePoint tp;
      tp.uv = {i + 0.5f, j + 0.5f};
      const Vec4f c = plain.evaluate(tp);
      EXPECT_TRUE(((i + j) & 1) == 0 ? isA(c) : isB(c)) << i << " " << j;
      // Moving by one square flips the colour.
      tp.uv.x += 1;
      EXPECT_NE(isA(plain.evaluate(tp)), isA(c));
    }
  TextureMapping scaled;
  scaled.scale = {4, 2, 1};
  scaled.offset = {0.5f, 0.25f, 0};
  const CheckerTexture moved(scaled, kA, kB, false);
  std::mt19937_64 rng(9);
  for (int n = 0; n < 1000; ++n) {
    TexturePoint tp;
    tp.uv = {4 * uniformFloat(rng) - 2, 4 * uniformFloat(rng) - 2};
    const int i = int(std::floor(tp.uv.x * 4 + 0.5f)), j = int(std::floor(tp.uv.y * 2 + 0.25f));
    EXPECT_EQ(isA(moved.evaluate(tp)), ((i + j) & 1) == 0) << tp.uv.x << " " << tp.uv.y;
  }
}

// Solid checkers: unit cubes alternate in all three directions; 2D checkers from world space
// read the chosen plane and ignore the third axis.
TEST(CheckerTexture, CubesAndPlanesAlternateInSpace) {
  const CheckerTexture solid(worldMapping(), kA, kB, true);
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j)
      for (int k = -3; k <= 3; ++k) {
        const Vec4f c = solid.evaluate(pointAt({i + 0.5f, j + 0.5f, k + 0.5f}));
        EXPECT_TRUE(((i + j + k) & 1) == 0 ? isA(c) : isB(c)) << i << " " << j << " " << k;
      }
  using Plane = TextureMapping::Plane;
  for (Plane plane : {Plane::Xy, Plane::Xz, Plane::Yz}) {
    TextureMapping m = worldMapping();
    m.plane = plane;
    const CheckerTexture flat(m, kA, kB, false);
    for (int i = -3; i <= 3; ++i)
      for (int j = -3; j <= 3; ++j)
        for (float other : {-2.5f, 0.5f, 7.5f}) {
          Vec3f p;
          if (plane == Plane::Xy) p = {i + 0.5f, j + 0.5f, other};
          if (plane == Plane::Xz) p = {i + 0.5f, other, j + 0.5f};
          if (plane == Plane::Yz) p = {other, i + 0.5f, j + 0.5f};
          const Vec4f c = flat.evaluate(pointAt(p));
          EXPECT_TRUE(((i + j) & 1) == 0 ? isA(c) : isB(c))
              << "plane " << int(plane) << " " << i << " " << j << " " << other;
        }
  }
}

TEST(TextureMapping, RotatesUvsAsKhrTextureTransform) {
  // The extension's GLSL: uv' = T R S uv with column-major mat3s, R's columns (cos, sin) and
  // (-sin, cos). Scale (2, 3), rotation 90 degrees, offset (0.5, 0.25): (1, 0) -> S (2, 0) ->
  // R (0, 2) -> (0.5, 2.25); (0, 1) -> (0, 3) -> (-3, 0) -> (-2.5, 0.25).
  TextureMapping m;
  m.scale = {2, 3, 1};
  m.offset = {0.5f, 0.25f, 0};
  m.setUvRotation(kPi / 2);
  TexturePoint tp;
  tp.uv = {1, 0};
  tp.duvdx = {0.01f, 0};
  TexCoord2 c = m.map2D(tp);
  EXPECT_NEAR(c.st.x, 0.5f, 1e-6f);
  EXPECT_NEAR(c.st.y, 2.25f, 1e-6f);
  // Footprints turn with the coordinates (no offset).
  EXPECT_NEAR(c.dstdx.x, 0, 1e-7f);
  EXPECT_NEAR(c.dstdx.y, 0.02f, 1e-7f);
  tp.uv = {0, 1};
  c = m.map2D(tp);
  EXPECT_NEAR(c.st.x, -2.5f, 1e-6f);
  EXPECT_NEAR(c.st.y, 0.25f, 1e-6f);
  // The same in 3D lookups over uv.
  const Vec3f p = m.map3D(tp);
  EXPECT_NEAR(p.x, -2.5f, 1e-6f);
  EXPECT_NEAR(p.y, 0.25f, 1e-6f);
}

TEST(TextureMapping, ScalesOffsetsAndProjects) {
  TextureMapping m;
  m.scale = {2, 3, 4};
  m.offset = {0.5f, -1, 0.25f};
  TexturePoint tp;
  tp.uv = {0.25f, 0.5f};
  tp.duvdx = {0.01f, 0};
  tp.duvdy = {0, 0.02f};
  tp.p = {1, 2, 3};
  tp.dpdx = {0.1f, 0, 0};
  tp.dpdy = {0, 0, 0.2f};
  // uv space: (u, v) * scale.xy + offset.xy, and (u, v, 0) * scale + offset in 3D.
  TexCoord2 c = m.map2D(tp);
  EXPECT_EQ(c.st, (Vec2f{1.0f, 0.5f}));
  EXPECT_NEAR(c.dstdx.x, 0.02f, 1e-8f);
  EXPECT_EQ(c.dstdx.y, 0);
  EXPECT_EQ(c.dstdy.x, 0);
  EXPECT_NEAR(c.dstdy.y, 0.06f, 1e-8f);
  EXPECT_EQ(m.map3D(tp), (Vec3f{1.0f, 0.5f, 0.25f}));
  EXPECT_EQ(m.map3DVector(tp, {1, 1, 1}), (Vec3f{}));
  EXPECT_TRUE(m.usesUvs());
  // World space: p * scale + offset; 2D projects onto the plane.
  m.space = TextureMapping::Space::World;
  EXPECT_EQ(m.map3D(tp), (Vec3f{2.5f, 5, 12.25f}));
  EXPECT_EQ(m.map3DVector(tp, {1, 1, 1}), (Vec3f{2, 3, 4}));
  m.plane = TextureMapping::Plane::Xz;
  c = m.map2D(tp);
  EXPECT_EQ(c.st, (Vec2f{2.5f, 12.25f}));
  EXPECT_NEAR(c.dstdx.x, 0.2f, 1e-7f);
  EXPECT_NEAR(c.dstdy.y, 0.8f, 1e-7f);
  m.plane = TextureMapping::Plane::Yz;
  EXPECT_EQ(m.map2D(tp).st, (Vec2f{5, 12.25f}));
  m.plane = TextureMapping::Plane::Xy;
  EXPECT_EQ(m.map2D(tp).st, (Vec2f{2.5f, 5}));
  // Object space: the point goes through objectFromWorld, vectors without its translation.
  const Transform objectFromWorld =
      Transform::translate({10, 20, 30}) * Transform::scale({2, 2, 2});
  tp.objectFromWorld = &objectFromWorld;
  m.space = TextureMapping::Space::Object;
  EXPECT_TRUE(m.usesObjectSpace());
  EXPECT_EQ(m.map3D(tp), (Vec3f{(10 + 2) * 2 + 0.5f, (20 + 4) * 3 - 1.0f, (30 + 6) * 4 + 0.25f}));
  EXPECT_EQ(m.map3DVector(tp, {1, 1, 1}), (Vec3f{4, 6, 8}));
}

}  // namespace
}  // namespace glint
