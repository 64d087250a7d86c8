// Shading-normal modifiers: bump maps against the normal of the displaced surface computed
// by finite differences, object-space mapping, the hemisphere clamp, normal maps, snow and the
// shadow-terminator term.
#include "materials/bump.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "materials/procedural.h"

namespace glint {
namespace {

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

struct Vec3d {
  double x = 0, y = 0, z = 0;
};
Vec3d toD(Vec3f v) { return {v.x, v.y, v.z}; }
Vec3d operator+(Vec3d a, Vec3d b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3d operator-(Vec3d a, Vec3d b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3d operator*(Vec3d a, double s) { return {a.x * s, a.y * s, a.z * s}; }
Vec3d crossD(Vec3d a, Vec3d b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double dotD(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3d normalizeD(Vec3d a) { return a * (1 / std::sqrt(dotD(a, a))); }
Vec3f toF(Vec3d v) { return {float(v.x), float(v.y), float(v.z)}; }

float uniformFloat(std::mt19937_64& rng) { return float(rng() >> 40) * 0x1p-24f; }
Vec3f randomPoint(std::mt19937_64& rng, float extent) {
  return {extent * (2 * uniformFloat(rng) - 1), extent * (2 * uniformFloat(rng) - 1),
          extent * (2 * uniformFloat(rng) - 1)};
}
Vec3f randomUnit(std::mt19937_64& rng) {
  const float z = 1 - 2 * uniformFloat(rng), phi = 2 * kPi * uniformFloat(rng);
  const float r = std::sqrt(std::max(0.0f, 1 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// A hit on the plane through p with normal +Z, dp/du = (L, 0, 0), dp/dv = (0, L, 0).
SurfaceInteraction planeHit(Vec3f p, float L) {
  SurfaceInteraction si;
  si.p = p;
  si.ng = si.ns = {0, 0, 1};
  si.wo = normalize(Vec3f{0.2f, 0.1f, 1});
  si.dpdu = {L, 0, 0};
  si.dpdv = {0, L, 0};
  si.uv = {0.5f, 0.5f};
  return si;
}

// An fBm height field in world (or the given) space.
NoiseTexture fbmTexture(TextureMapping::Space space = TextureMapping::Space::World,
                        Rgb a = {0, 0, 0}, Rgb b = {1, 1, 1}, uint64_t seed = 7) {
  TextureMapping mapping;
  mapping.space = space;
  NoiseParams params;
  params.pattern = NoisePattern::Fbm;
  params.seed = seed;
  params.colorA = a;
  params.colorB = b;
  return NoiseTexture(mapping, params);
}

// The same texture without its exact gradient: BumpMap then takes finite differences.
class WithoutGradient final : public Texture {
 public:
  explicit WithoutGradient(const Texture& t) : t_(t) {}
  Vec4f evaluate(const TexturePoint& tp) const override { return t_.evaluate(tp); }
  TextureNeeds needs() const override { return t_.needs(); }

 private:
  const Texture& t_;
};

// The normal of the displaced surface P(u, v) = p(u, v) + strength h(p(u, v)) n(u, v) at
// (u0, v0), by central differences with uv step `step`, oriented to n(u0, v0). `surface`
// gives p and the unit normal at (u, v) in double; stepU and stepV are the uv steps.
template <typename Surface>
Vec3d displacedNormal(const Texture& height, float strength, const Surface& surface,
                      const TexturePoint& base, double u0, double v0, double stepU, double stepV) {
  auto P = [&](double u, double v) {
    Vec3d p, n;
    surface(u, v, &p, &n);
    TexturePoint tp = base;
    tp.p = toF(p);
    return p + n * (double(strength) * height.scalar(tp));
  };
  const Vec3d pu = (P(u0 + stepU, v0) - P(u0 - stepU, v0)) * (1 / (2 * stepU));
  const Vec3d pv = (P(u0, v0 + stepV) - P(u0, v0 - stepV)) * (1 / (2 * stepV));
  Vec3d n = normalizeD(crossD(pu, pv));
  Vec3d p0, n0;
  surface(u0, v0, &p0, &n0);
  if (dotD(n, n0) < 0) n = n * -1;
  return n;
}

void expectNear(Vec3f actual, Vec3d expected, double tolerance, const std::string& what) {
  EXPECT_NEAR(actual.x, expected.x, tolerance) << what;
  EXPECT_NEAR(actual.y, expected.y, tolerance) << what;
  EXPECT_NEAR(actual.z, expected.z, tolerance) << what;
}

// Tolerance of the finite-difference references: steps of 2^-11 world units leave a truncation
// error of ~3e-5 (the top fBm octave has frequency 16) and a rounding error of ~1e-4 (float
// heights differenced over 1e-3) in the height gradient; 1e-3 in the normal's components is
// an order of magnitude above both and far below what a wrong sign, a missing dp/du length
// or a wrong chain rule would give (O(strength x gradient) ~ 0.1 to 1).
constexpr double kNormalTolerance = 1e-3;

// ---------------------------------------------------------------------------------------------
// Bump maps
// ---------------------------------------------------------------------------------------------

// A plane with dp/du = L x, dp/dv = L y for L from 1/256 to 256 (the normal depends on the
// world-space surface only, not on its parameterisation's scale), at random points, through
// the exact gradient and through BumpMap's own finite differences (heightDerivatives with
// forceFiniteDifferences, and apply() on a texture that does not know its gradient). The
// finite-difference path steps half a pixel footprint, here set to 2^-10 world units.
TEST(BumpMap, PlaneNormalMatchesDisplacedSurface) {
  const NoiseTexture height = fbmTexture();
  const WithoutGradient heightFd(height);
  std::mt19937_64 rng(11);
  for (float L : {1.0f / 256, 1.0f, 256.0f})
    for (float strength : {0.02f, 0.1f, 0.4f}) {
      const BumpMap bump(&height, strength);
      const BumpMap bumpFd(&heightFd, strength);
      for (int i = 0; i < 40; ++i) {
        const Vec3f p0 = randomPoint(rng, 3);
        SurfaceInteraction si = planeHit(p0, L);
        si.duvdx = {0x1p-10f / L, 0};
        si.duvdy = {0, 0x1p-10f / L};
        const double step = 0x1p-11 / L;  // 2^-11 world units
        auto plane = [&](double u, double v, Vec3d* p, Vec3d* n) {
          *p = toD(p0) + Vec3d{L * (u - 0.5), L * (v - 0.5), 0};
          *n = {0, 0, 1};
        };
        const Vec3d expected =
            displacedNormal(height, strength, plane, TexturePoint(si), 0.5, 0.5, step, step);
        const std::string what = "L " + std::to_string(L) + " strength " +
                                 std::to_string(strength) + " point " + std::to_string(i);
        SurfaceInteraction analytic = si;
        bump.apply(analytic);
        expectNear(analytic.ns, expected, kNormalTolerance, what + " (exact gradient)");
        SurfaceInteraction fd = si;
        bumpFd.apply(fd);
        expectNear(fd.ns, expected, kNormalTolerance, what + " (finite differences)");
        const Vec2f dExact = bump.heightDerivatives(si, false);
        const Vec2f dFd = bump.heightDerivatives(si, true);
        // dh/du scales with L; compare per world unit (error ~2.5e-4 x strength, see above).
        EXPECT_NEAR(dFd.x / L, dExact.x / L, 2e-3 * strength) << what;
        EXPECT_NEAR(dFd.y / L, dExact.y / L, 2e-3 * strength) << what;
        EXPECT_NEAR(length(analytic.ns), 1, 1e-6f);
      }
    }
}

// The bump is real: at strength 0.4 the normal tilts by a clear angle on average (otherwise
// the comparison above would test nothing).
TEST(BumpMap, TiltsTheNormalVisibly) {
  const NoiseTexture height = fbmTexture();
  const BumpMap bump(&height, 0.4f);
  std::mt19937_64 rng(5);
  double tilt = 0;
  for (int i = 0; i < 200; ++i) {
    SurfaceInteraction si = planeHit(randomPoint(rng, 3), 1);
    bump.apply(si);
    tilt += std::acos(std::clamp(double(si.ns.z), -1.0, 1.0));
  }
  EXPECT_GT(tilt / 200, 0.1);
}

// A sphere of radius 1.3 (phi = 2 pi u around +Z, theta = pi v), so that dn/du != 0. Blinn's
// normal drops the strength h dn/du term of the displaced surface's derivative; with a height
// shifted to be 0 at the shading point (colours -w0 and 1 - w0: scalar w - w0) that term
// vanishes there and the comparison is exact.
TEST(BumpMap, CurvedPatchNormalMatchesDisplacedSurface) {
  const NoiseTexture plain = fbmTexture();
  std::mt19937_64 rng(17);
  const Vec3d centre{0.2, -0.1, 0.3};
  constexpr double kRadius = 1.3;
  auto sphere = [&](double u, double v, Vec3d* p, Vec3d* n) {
    const double phi = 2 * M_PI * u, theta = M_PI * v;
    *n = {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
    *p = centre + *n * kRadius;
  };
  for (int i = 0; i < 60; ++i) {
    const double u0 = uniformFloat(rng), v0 = 0.15 + 0.7 * uniformFloat(rng);
    Vec3d p, n;
    sphere(u0, v0, &p, &n);
    const double phi = 2 * M_PI * u0, theta = M_PI * v0;
    SurfaceInteraction si;
    si.p = toF(p);
    si.ng = si.ns = toF(n);
    si.wo = si.ns;
    si.uv = {float(u0), float(v0)};
    si.dpdu = toF(Vec3d{-std::sin(theta) * std::sin(phi), std::sin(theta) * std::cos(phi), 0} *
                  (2 * M_PI * kRadius));
    si.dpdv = toF(
        Vec3d{std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi), -std::sin(theta)} *
        (M_PI * kRadius));
    const float w0 = plain.weight(si.p, nullptr);
    const NoiseTexture height =
        fbmTexture(TextureMapping::Space::World, Rgb{1, 1, 1} * -w0, Rgb{1, 1, 1} * (1 - w0));
    const WithoutGradient heightFd(height);
    si.duvdx = {float(0x1p-10 / (2 * M_PI * kRadius)), 0};
    si.duvdy = {0, float(0x1p-10 / (M_PI * kRadius))};
    for (float strength : {0.05f, 0.3f}) {
      const BumpMap bump(&height, strength), bumpFd(&heightFd, strength);
      // Steps of 2^-11 world units along u and v.
      const double stepU = 0x1p-11 / (2 * M_PI * kRadius * std::sin(theta));
      const double stepV = 0x1p-11 / (M_PI * kRadius);
      const Vec3d expected =
          displacedNormal(height, strength, sphere, TexturePoint(si), u0, v0, stepU, stepV);
      const std::string what =
          "point " + std::to_string(i) + " strength " + std::to_string(strength);
      SurfaceInteraction a = si, f = si;
      bump.apply(a);
      bumpFd.apply(f);
      expectNear(a.ns, expected, kNormalTolerance, what + " (exact gradient)");
      expectNear(f.ns, expected, kNormalTolerance, what + " (finite differences)");
    }
  }
}

// Object-space mapping: the texture reads objectFromWorld(p), so (a) its value at p is the
// world-mapped texture's at objectFromWorld(p), exactly; (b) the bumped normal under a
// rotated, non-uniformly scaled and translated objectFromWorld matches the displaced
// surface's (the gradient goes through the transposed linear part); (c) under a rigid motion
// M the whole configuration moves along: bumping the plane M^-1(S) with object mapping gives
// M^-1 of the normal from bumping S with world mapping.
TEST(BumpMap, ObjectSpaceMappingFollowsTheObject) {
  const NoiseTexture world = fbmTexture(TextureMapping::Space::World);
  const NoiseTexture object = fbmTexture(TextureMapping::Space::Object);
  const Transform skewed = Transform::translate({0.3f, -1.2f, 0.7f}) *
                           Transform::rotate(37, {1, 2, 0.5f}) *
                           Transform::scale({0.5f, 2.0f, 1.3f});
  const Transform rigid =
      Transform::translate({-0.4f, 0.9f, 2.1f}) * Transform::rotate(71, {-0.3f, 1, 0.6f});
  std::mt19937_64 rng(23);
  for (int i = 0; i < 50; ++i) {
    const Vec3f p0 = randomPoint(rng, 2);
    // (a)
    TexturePoint tp;
    tp.p = p0;
    tp.objectFromWorld = &skewed;
    TexturePoint tw;
    tw.p = skewed.point(p0);
    EXPECT_EQ(object.scalar(tp), world.scalar(tw));
    // (b)
    for (float strength : {0.05f, 0.2f}) {
      const BumpMap bump(&object, strength);
      SurfaceInteraction si = planeHit(p0, 1);
      si.objectFromWorld = &skewed;
      auto plane = [&](double u, double v, Vec3d* p, Vec3d* n) {
        *p = toD(p0) + Vec3d{u - 0.5, v - 0.5, 0};
        *n = {0, 0, 1};
      };
      const Vec3d expected =
          displacedNormal(object, strength, plane, TexturePoint(si), 0.5, 0.5, 0x1p-12, 0x1p-12);
      bump.apply(si);
      // The scale 2 along one axis doubles the top octave's frequency: twice the tolerance.
      expectNear(si.ns, expected, 2 * kNormalTolerance,
                 "skewed object space, point " + std::to_string(i));
    }
    // (c)
    const Transform worldFromObject = rigid.inverse();
    const BumpMap bumpWorld(&world, 0.3f), bumpObject(&object, 0.3f);
    SurfaceInteraction inObject;
    inObject.p = p0;
    inObject.ng = inObject.ns = normalize(Vec3f{0.3f, 0.4f, 0.8f});
    inObject.dpdu = Frame::fromZ(inObject.ns).s * 0.7f;
    inObject.dpdv = Frame::fromZ(inObject.ns).t * 1.9f;
    SurfaceInteraction placed = inObject;
    placed.p = worldFromObject.point(p0);
    placed.ng = placed.ns = normalize(worldFromObject.vector(inObject.ns));
    placed.dpdu = worldFromObject.vector(inObject.dpdu);
    placed.dpdv = worldFromObject.vector(inObject.dpdv);
    placed.objectFromWorld = &rigid;
    bumpWorld.apply(inObject);
    bumpObject.apply(placed);
    const Vec3f expected = worldFromObject.vector(inObject.ns);
    EXPECT_NEAR(placed.ns.x, expected.x, 2e-5f) << i;
    EXPECT_NEAR(placed.ns.y, expected.y, 2e-5f) << i;
    EXPECT_NEAR(placed.ns.z, expected.z, 2e-5f) << i;
  }
}

// A constant height changes nothing: not on a flat plane and not on a smooth-shaded triangle,
// whose shading normal differs from the face normal cross(dp/du, dp/dv) (interpolated vertex
// normals). A bump map must perturb ns, not replace it by the face normal.
TEST(BumpMap, ConstantHeightKeepsTheShadingNormal) {
  const NoiseTexture flat =
      fbmTexture(TextureMapping::Space::World, Rgb{0.3f, 0.3f, 0.3f}, Rgb{0.3f, 0.3f, 0.3f});
  const BumpMap bump(&flat, 5);
  std::mt19937_64 rng(29);
  for (int i = 0; i < 100; ++i) {
    SurfaceInteraction si = planeHit(randomPoint(rng, 3), 2);
    bump.apply(si);
    EXPECT_EQ(si.ns, (Vec3f{0, 0, 1}));
    // Smooth shading: ns tilted up to ~25 degrees from the face normal +Z.
    SurfaceInteraction smooth = planeHit(randomPoint(rng, 3), 0.5f);
    smooth.ns =
        normalize(Vec3f{0.4f * uniformFloat(rng) - 0.2f, 0.4f * uniformFloat(rng) - 0.2f, 1});
    const Vec3f before = smooth.ns;
    bump.apply(smooth);
    EXPECT_NEAR(smooth.ns.x, before.x, 1e-6f) << i;
    EXPECT_NEAR(smooth.ns.y, before.y, 1e-6f) << i;
    EXPECT_NEAR(smooth.ns.z, before.z, 1e-6f) << i;
  }
}

// On a smooth-shaded triangle a bump perturbs the interpolated normal: the bumped normal is
// that of the shading surface (tangent plane perpendicular to ns: the face's dp/du and dp/dv
// projected onto it) displaced along ns by the height, whose derivatives are taken along the
// true surface (the face).
TEST(BumpMap, SmoothShadedSurfaceIsBumpedAroundItsShadingNormal) {
  const NoiseTexture height = fbmTexture();
  const BumpMap bump(&height, 0.1f);
  std::mt19937_64 rng(31);
  for (int i = 0; i < 100; ++i) {
    const Vec3f p = randomPoint(rng, 3);
    const Vec3f ns =
        normalize(Vec3f{0.4f * uniformFloat(rng) - 0.2f, 0.4f * uniformFloat(rng) - 0.2f, 1});
    // The triangle's face: normal +Z, dp/du = x, dp/dv = y.
    const SurfaceInteraction face = planeHit(p, 1);
    SurfaceInteraction smooth = face;
    smooth.ns = ns;
    bump.apply(smooth);
    const Vec2f dh = bump.heightDerivatives(face, false);
    const Vec3f tu = face.dpdu - ns * dot(ns, face.dpdu), tv = face.dpdv - ns * dot(ns, face.dpdv);
    const Vec3f expected = normalize(cross(tu + ns * dh.x, tv + ns * dh.y));
    EXPECT_NEAR(smooth.ns.x, expected.x, 1e-5f) << i;
    EXPECT_NEAR(smooth.ns.y, expected.y, 1e-5f) << i;
    EXPECT_NEAR(smooth.ns.z, expected.z, 1e-5f) << i;
  }
}

// Whatever the strength (up to 1e4), the bumped normal is a finite unit vector in ng's
// hemisphere, at least ~1 degree above the surface (clampToHemisphere's cos >= 0.02).
TEST(BumpMap, HugeStrengthsStayInTheHemisphere) {
  const NoiseTexture height = fbmTexture();
  std::mt19937_64 rng(37);
  for (int i = 0; i < 2000; ++i) {
    const float strength =
        std::pow(10.0f, 4 * uniformFloat(rng)) * (uniformFloat(rng) < 0.5f ? -1 : 1);
    const BumpMap bump(&height, strength);
    const Vec3f n = randomUnit(rng);
    SurfaceInteraction si;
    si.p = randomPoint(rng, 3);
    si.ng = si.ns = n;
    si.dpdu = Frame::fromZ(n).s * (0.1f + uniformFloat(rng));
    si.dpdv = Frame::fromZ(n).t * (0.1f + uniformFloat(rng));
    bump.apply(si);
    ASSERT_TRUE(isFinite(si.ns)) << strength;
    EXPECT_NEAR(length(si.ns), 1, 1e-5f);
    EXPECT_GE(dot(si.ns, si.ng), 0.02f - 1e-5f) << strength;
  }
}

// ---------------------------------------------------------------------------------------------
// Normal maps
// ---------------------------------------------------------------------------------------------

// A constant texel (a checkerboard of one colour).
CheckerTexture constantTexel(Rgb c) { return CheckerTexture(TextureMapping{}, c, c, false); }

TEST(NormalMap, FlatTexelKeepsTheNormal) {
  const CheckerTexture flat = constantTexel({0.5f, 0.5f, 1});
  const NormalMap map(&flat, 1);
  std::mt19937_64 rng(41);
  for (int i = 0; i < 100; ++i) {
    const Vec3f n = randomUnit(rng);
    for (bool front : {true, false}) {
      SurfaceInteraction si;
      si.ng = si.ns = front ? n : -n;
      si.frontFace = front;
      si.dpdu = Frame::fromZ(n).s + n * 0.3f;  // not orthogonal to n
      si.dpdv = Frame::fromZ(n).t;
      const Vec3f before = si.ns;
      map.apply(si);
      EXPECT_NEAR(si.ns.x, before.x, 1e-6f);
      EXPECT_NEAR(si.ns.y, before.y, 1e-6f);
      EXPECT_NEAR(si.ns.z, before.z, 1e-6f);
    }
  }
}

// Red > 0.5 tilts the normal towards +dp/du (the tangent), green > 0.5 towards the image's up,
// -dp/dv (glTF's v runs down the image), by the texel's angle: (0.75, 0.5, 1) is (0.5, 0, 1)
// in tangent space, atan(0.5) = 26.6 degrees, scaled in x and y by `scale`. For a layout as
// drawn, -dp/dv is n x dp/du; for a mirrored one (dp/dv along n x dp/du) green still goes to
// -dp/dv, which is then -(n x dp/du) (the Khronos viewer's cross(n, t) alone showed mirrored
// halves inverted). Seen from the back (frontFace false, ns = -outward) the relief is the same
// surface: the result is exactly the front's, negated.
TEST(NormalMap, TiltedTexelTiltsTowardsTheTangentAndMirrorsOnBackFaces) {
  const CheckerTexture red = constantTexel({0.75f, 0.5f, 1});
  const CheckerTexture green = constantTexel({0.5f, 0.75f, 1});
  std::mt19937_64 rng(43);
  for (int i = 0; i < 50; ++i) {
    const Vec3f n = randomUnit(rng);
    const Frame f = Frame::fromZ(n);
    for (float scale : {1.0f, 0.5f, -0.5f}) {  // the last: a mirrored layout, half strength
      const bool mirrored = scale < 0;
      scale = std::abs(scale);
      SurfaceInteraction front;
      front.ng = front.ns = n;
      front.dpdu = f.s * 2.0f;
      front.dpdv = f.t * (mirrored ? 3.0f : -3.0f);  // f.t = n x f.s
      SurfaceInteraction back = front;
      back.ng = back.ns = -n;
      back.frontFace = false;
      SurfaceInteraction frontGreen = front;
      const NormalMap mapRed(&red, scale), mapGreen(&green, scale);
      mapRed.apply(front);
      mapRed.apply(back);
      mapGreen.apply(frontGreen);
      const float expectedAngle = std::atan(0.5f * scale);
      EXPECT_NEAR(std::acos(std::clamp(dot(front.ns, n), -1.0f, 1.0f)), expectedAngle, 1e-4f);
      EXPECT_NEAR(dot(front.ns, f.s), std::sin(expectedAngle), 1e-5f);  // towards +dp/du
      EXPECT_NEAR(dot(front.ns, f.t), 0, 1e-5f);
      EXPECT_NEAR(dot(frontGreen.ns, -normalize(front.dpdv)), std::sin(expectedAngle), 1e-5f);
      EXPECT_NEAR(back.ns.x, -front.ns.x, 1e-6f);
      EXPECT_NEAR(back.ns.y, -front.ns.y, 1e-6f);
      EXPECT_NEAR(back.ns.z, -front.ns.z, 1e-6f);
      EXPECT_GT(dot(back.ns, back.ng), 0);
    }
  }
}

// A normal map on TEXCOORD_1 tilts along that set's dp/du1, not set 0's dp/du: with the second
// set turned a quarter turn from the first (u1 = -v, v1 = u), dp/du1 = -dp/dv. Without a
// second set (the identity map) both agree.
TEST(NormalMap, SecondUvSetUsesItsOwnTangent) {
  struct SecondSetTexel final : Texture {
    Vec4f texel{0.75f, 0.5f, 1, 1};  // tilted towards +tangent
    Vec4f evaluate(const TexturePoint&) const override { return texel; }
    TextureNeeds needs() const override { return {}; }
    int uvSet() const override { return 1; }
  } second;
  SurfaceInteraction si;
  si.ng = si.ns = {0, 0, 1};
  si.dpdu = {1, 0, 0};
  si.dpdv = {0, 1, 0};
  si.duv1du = {0, 1};   // d(u1, v1) / du
  si.duv1dv = {-1, 0};  // d(u1, v1) / dv
  Vec3f t, b;
  ASSERT_TRUE(tangentFrame(si, si.ns, &t, &b, 1));
  EXPECT_NEAR(t.y, -1, 1e-6f);
  ASSERT_TRUE(tangentFrame(si, si.ns, &t, &b, 0));
  EXPECT_NEAR(t.x, 1, 1e-6f);
  SurfaceInteraction mapped = si;
  NormalMap(&second, 1).apply(mapped);
  EXPECT_NEAR(mapped.ns.y, -std::sin(std::atan(0.5f)), 1e-5f);
  EXPECT_NEAR(mapped.ns.x, 0, 1e-5f);
  SurfaceInteraction identity = si;
  identity.duv1du = {1, 0};
  identity.duv1dv = {0, 1};
  NormalMap(&second, 1).apply(identity);
  EXPECT_NEAR(identity.ns.x, std::sin(std::atan(0.5f)), 1e-5f);
}

// ---------------------------------------------------------------------------------------------
// Snow
// ---------------------------------------------------------------------------------------------

SurfaceInteraction snowHit(Vec3f p, Vec3f n) {
  SurfaceInteraction si;
  si.p = p;
  si.ng = si.ns = n;
  si.dpdu = Frame::fromZ(n).s;
  si.dpdv = Frame::fromZ(n).t;
  return si;
}

// Deterministic, constant within a grain cell, different across cells and seeds, and always
// a unit vector in the hemisphere (also for amounts far above 1).
TEST(Snow, GrainsAreDeterministicCellsInTheHemisphere) {
  constexpr float kGrain = 0.25f;
  const SnowPerturbation snow(0.3f, kGrain, 1), otherSeed(0.3f, kGrain, 2), wild(50, kGrain, 3);
  std::mt19937_64 rng(47);
  int sameAcrossCells = 0, sameAcrossSeeds = 0;
  constexpr int kPoints = 1000;
  for (int i = 0; i < kPoints; ++i) {
    const Vec3f n = randomUnit(rng);
    // A point well inside a cell, another in the same cell, and one in the next cell along x.
    const Vec3f cell{std::floor(10 * (2 * uniformFloat(rng) - 1)),
                     std::floor(10 * (2 * uniformFloat(rng) - 1)),
                     std::floor(10 * (2 * uniformFloat(rng) - 1))};
    const Vec3f a = (cell + Vec3f{0.2f, 0.3f, 0.4f}) * kGrain;
    const Vec3f b = (cell + Vec3f{0.8f, 0.7f, 0.6f}) * kGrain;
    const Vec3f c = (cell + Vec3f{1.2f, 0.3f, 0.4f}) * kGrain;
    SurfaceInteraction sa = snowHit(a, n), sa2 = snowHit(a, n), sb = snowHit(b, n),
                       sc = snowHit(c, n), sd = snowHit(a, n), sw = snowHit(a, n);
    snow.apply(sa);
    snow.apply(sa2);
    snow.apply(sb);
    snow.apply(sc);
    otherSeed.apply(sd);
    wild.apply(sw);
    EXPECT_EQ(sa.ns, sa2.ns);
    EXPECT_EQ(sa.ns, sb.ns);
    if (sa.ns == sc.ns) ++sameAcrossCells;
    if (sa.ns == sd.ns) ++sameAcrossSeeds;
    for (const SurfaceInteraction* s : {&sa, &sc, &sd, &sw}) {
      ASSERT_TRUE(isFinite(s->ns));
      EXPECT_NEAR(length(s->ns), 1, 1e-5f);
      EXPECT_GE(dot(s->ns, n), 0.02f - 1e-5f);
    }
    // Object space: a translated object carries its grains along.
    const Transform objectFromWorld = Transform::translate({-3, 1, 2});
    SurfaceInteraction moved = snowHit(a - Vec3f{-3, 1, 2}, n);
    moved.objectFromWorld = &objectFromWorld;
    snow.apply(moved);
    EXPECT_NEAR(moved.ns.x, sa.ns.x, 1e-6f);
    EXPECT_NEAR(moved.ns.y, sa.ns.y, 1e-6f);
    EXPECT_NEAR(moved.ns.z, sa.ns.z, 1e-6f);
  }
  // A 64-bit hash makes repeats across cells or seeds practically impossible.
  EXPECT_LE(sameAcrossCells, 1);
  EXPECT_LE(sameAcrossSeeds, 1);
}

// ---------------------------------------------------------------------------------------------
// The shadow-terminator term
// ---------------------------------------------------------------------------------------------

// 1 when ns == ng, 0 below the geometric horizon, in [0, 1] everywhere, and continuous: along
// a fine sweep of wi across the hemisphere, consecutive values (3e-4 rad apart) differ by
// less than 0.01 (the smooth cubic's slope is bounded away from the horizon of ng).
TEST(TerminatorShadowing, IsOneWithoutPerturbationAndSmoothInTheUnitInterval) {
  std::mt19937_64 rng(53);
  for (int i = 0; i < 10000; ++i) {
    const Vec3f ng = randomUnit(rng), wi = randomUnit(rng);
    const float t = terminatorShadowing(ng, ng, wi);
    EXPECT_NEAR(t, dot(wi, ng) > 0 ? 1.0f : 0.0f, 1e-6f);
    // A shading normal tilted up to ~60 degrees.
    Vec3f ns = normalize(ng + randomUnit(rng) * (1.5f * uniformFloat(rng)));
    if (dot(ns, ng) <= 0.05f) continue;
    const float s = terminatorShadowing(ng, ns, wi);
    EXPECT_GE(s, 0);
    EXPECT_LE(s, 1);
    if (dot(wi, ng) <= 0) {
      EXPECT_EQ(s, 0);
    }
  }
  const Vec3f ng{0, 0, 1};
  for (float tiltDegrees : {10.0f, 30.0f, 60.0f}) {
    const float tilt = tiltDegrees * kPi / 180;
    const Vec3f ns{std::sin(tilt), 0, std::cos(tilt)};
    float previous = -1, maxJump = 0;
    constexpr int kSteps = 10'000;
    // wi in the xz plane from the +x horizon over the top to 5 degrees above the -x horizon.
    for (int k = 0; k <= kSteps; ++k) {
      const float a = 0.01f + (kPi - 0.1f) * k / kSteps;
      const float v = terminatorShadowing(ng, ns, {std::cos(a), 0, std::sin(a)});
      if (previous >= 0) maxJump = std::max(maxJump, std::abs(v - previous));
      previous = v;
    }
    EXPECT_LT(maxJump, 0.01f) << tiltDegrees;
    // Light along ng is not shadowed; grazing light on the side ns tilts towards is darkened
    // (there ns promises more light than the geometry receives).
    EXPECT_EQ(terminatorShadowing(ng, ns, ng), 1);
    EXPECT_LT(terminatorShadowing(ng, ns, normalize(Vec3f{1, 0, 0.2f})), 0.9f);
  }
}

// ---------------------------------------------------------------------------------------------
// A shading normal that reflects above the surface
// ---------------------------------------------------------------------------------------------

// reflectionSafeNormal: unchanged where the mirror direction of wo is already above the
// geometric plane by the threshold; elsewhere tilted towards ng, in the plane of ng and ns,
// just far enough (the threshold reached within rounding), never past ng. Then wo . n is at
// least half of wo . ng, which bounds every lobe's 1 / (wo . n).
TEST(ReflectionSafeNormal, TiltsJustFarEnoughTowardsTheGeometricNormal) {
  std::mt19937_64 rng(59);
  std::uniform_real_distribution<float> u(0, 1);
  int changed = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3f ng = randomUnit(rng);
    Vec3f ns = randomUnit(rng);
    if (dot(ns, ng) < 0) ns = -ns;
    ns = clampToHemisphere(ns, ng);
    Vec3f wo = randomUnit(rng);
    if (dot(wo, ng) < 0) wo = -wo;
    const float z = dot(wo, ng), q = std::min(0.9f * z, 0.01f);
    auto height = [&](Vec3f n) { return dot(2 * dot(wo, n) * n - wo, ng); };
    const Vec3f n = reflectionSafeNormal(ns, ng, wo);
    EXPECT_NEAR(length(n), 1, 1e-5f);
    if (height(ns) >= q) {
      EXPECT_EQ(n, ns) << i;
      continue;
    }
    ++changed;
    EXPECT_NEAR(height(n), q, 2e-4f) << i;
    EXPECT_GE(dot(wo, n), 0.5f * z - 1e-4f) << i;
    // In the plane of ng and ns, between them.
    EXPECT_NEAR(dot(n, cross(ng, ns)), 0, 1e-4f) << i;
    EXPECT_GE(dot(n, ng), dot(ns, ng) - 1e-5f) << i;
  }
  EXPECT_GT(changed, 1000);
}

}  // namespace
}  // namespace glint
