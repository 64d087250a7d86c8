// The glTF metallic-roughness texture: metallic from its blue channel, roughness from green,
// read in one lookup, must shade exactly like the same constant factors.
#include <gtest/gtest.h>

#include "materials/basic_materials.h"
#include "materials/pbr.h"

namespace glint {
namespace {

SurfaceInteraction hitFacing(Vec3f wo) {
  SurfaceInteraction si;
  si.ng = si.ns = {0, 0, 1};
  si.wo = normalize(wo);
  si.dpdu = {1, 0, 0};
  si.dpdv = {0, 1, 0};
  return si;
}

TEST(PbrTextures, MetallicRoughnessChannelsMatchConstantFactors) {
  // A one-colour "texture": green 0.4 (roughness), blue 0.75 (metallic), scaled by factors.
  CheckerTexture mr(TextureMapping{}, {0.9f, 0.4f, 0.75f}, {0.9f, 0.4f, 0.75f}, false);
  PbrParams textured;
  textured.baseColor = {{0.8f, 0.6f, 0.3f}};
  textured.metallic = {1, &mr, 2};
  textured.roughness = {0.5f, &mr, 1};
  PbrParams constant = textured;
  constant.metallic = {0.75f};
  constant.roughness = {0.2f};
  PbrMaterial a(textured), b(constant);
  SurfaceInteraction si = hitFacing({0.3f, -0.2f, 1});
  for (Vec3f wi : {Vec3f{0, 0, 1}, Vec3f{-0.4f, 0.3f, 0.8f}, Vec3f{0.7f, 0.1f, 0.2f}}) {
    wi = normalize(wi);
    const Rgb fa = a.bsdf(si).f(wi), fb = b.bsdf(si).f(wi);
    EXPECT_NEAR(fa.x, fb.x, 1e-6f * std::max(1.0f, fb.x));
    EXPECT_NEAR(fa.y, fb.y, 1e-6f * std::max(1.0f, fb.y));
    EXPECT_GT(fa.x, 0);
    EXPECT_NEAR(a.bsdf(si).pdf(wi), b.bsdf(si).pdf(wi), 1e-6f * std::max(1.0f, b.bsdf(si).pdf(wi)));
  }
  EXPECT_TRUE(a.traits().procedural);
}

TEST(PbrTextures, SmoothnessIsDecidedPerHitFromTheRoughnessTexture) {
  // Roughness 0 in the texture: a mirror at that hit (the Whitted integrator follows delta
  // lobes only); roughness 0.5: no delta lobe there.
  CheckerTexture smooth(TextureMapping{}, {0, 0, 1}, {0, 0, 1}, false);
  CheckerTexture rough(TextureMapping{}, {0, 0.5f, 1}, {0, 0.5f, 1}, false);
  SurfaceInteraction si = hitFacing({0.3f, -0.2f, 1});
  for (const CheckerTexture* mr : {&smooth, &rough}) {
    PbrParams p;
    p.baseColor = {{0.9f, 0.7f, 0.3f}};
    p.metallic = {1, mr, 2};
    p.roughness = {1, mr, 1};
    PbrMaterial m(p);
    EXPECT_TRUE(m.flags() & kBsdfSpecular);
    EXPECT_TRUE(m.flags() & kBsdfGlossy);
    std::optional<BsdfSample> s =
        m.bsdf(si).sample({0.3f, 0.6f}, 0.1f, kBsdfReflection | kBsdfSpecular);
    if (mr == &smooth) {
      ASSERT_TRUE(s.has_value());
      EXPECT_TRUE(s->flags & kBsdfSpecular);
      EXPECT_NEAR(s->wi.x, -si.wo.x, 1e-6f);  // the mirror direction
      EXPECT_NEAR(s->wi.z, si.wo.z, 1e-6f);
    } else {
      EXPECT_FALSE(s.has_value());
    }
  }
}

// Counts its lookups (a constant colour otherwise).
class CountingTexture final : public Texture {
 public:
  explicit CountingTexture(Vec4f value) : value_(value) {}
  Vec4f evaluate(const TexturePoint&) const override {
    ++count;
    return value_;
  }
  TextureNeeds needs() const override { return {.uvs = true}; }
  mutable int count = 0;

 private:
  Vec4f value_;
};

// Per hit, every texture a material reads is looked up once through the hit's TextureLookups,
// whatever the integrator asks for (opacity, albedo AOV, BSDF, emission), and the BSDF reads
// none at all when it is evaluated, sampled or asked for its pdf, however often.
TEST(PbrTextures, EachTextureIsLookedUpOncePerHit) {
  CountingTexture base({0.8f, 0.5f, 0.3f, 0.7f}), mr({1, 0.5f, 0.25f, 1}),
      transmission({0.3f, 0.3f, 0.3f, 1}), emission({0.1f, 0.2f, 0.3f, 1});
  PbrParams p;
  p.baseColor = {{1, 1, 1}, &base};
  p.metallic = {1, &mr, 2};
  p.roughness = {1, &mr, 1};
  p.transmission = {1, &transmission, 0};
  p.emission = {{1, 1, 1}, &emission};
  PbrMaterial m(p);
  m.setAlpha(AlphaMode::Blend, 1, 0.5f, p.baseColor);  // glTF: alpha from the base colour
  SurfaceInteraction si = hitFacing({0.3f, -0.2f, 1});
  TextureLookups lookups(si);
  EXPECT_NEAR(m.opacity(si, lookups), 0.7f, 1e-6f);
  const Rgb albedo = m.albedo(si, lookups);
  const Bsdf bsdf = m.bsdf(si, lookups);
  const Rgb Le = m.emitted(si, lookups);
  EXPECT_EQ(albedo, (Rgb{0.8f, 0.5f, 0.3f}));
  EXPECT_EQ(Le, (Rgb{0.1f, 0.2f, 0.3f}));
  for (const CountingTexture* t : {&base, &mr, &transmission, &emission})
    EXPECT_EQ(t->count, 1) << "four distinct textures, four lookups";
  float sum = 0;
  for (int i = 0; i < 100; ++i) {
    const Vec3f wi = normalize(Vec3f{std::cos(0.1f * i), std::sin(0.1f * i), i % 2 ? 0.5f : -0.5f});
    sum += bsdf.f(wi).x + bsdf.pdf(wi);
    if (std::optional<BsdfSample> s = bsdf.sample({0.01f * i, 0.37f}, 0.0099f * i)) sum += s->pdf;
  }
  EXPECT_GT(sum, 0);
  for (const CountingTexture* t : {&base, &mr, &transmission, &emission})
    EXPECT_EQ(t->count, 1) << "the BSDF reads no texture";

  // Lambert and Phong read their diffuse texture once for albedo and BSDF together.
  CountingTexture diffuse({0.5f, 0.5f, 0.5f, 1});
  LambertMaterial lambert({{1, 1, 1}, &diffuse}, ColorParam{{0, 0, 0}});
  PhongMaterial phong({{0.6f, 0.6f, 0.6f}, &diffuse}, {0.3f, 0.3f, 0.3f}, 20,
                      ColorParam{{0, 0, 0}});
  for (const Material* mat :
       {static_cast<const Material*>(&lambert), static_cast<const Material*>(&phong)}) {
    diffuse.count = 0;
    TextureLookups l(si);
    (void)mat->albedo(si, l);
    const Bsdf b = mat->bsdf(si, l);
    (void)b.sample({0.5f, 0.5f}, 0.5f);
    (void)b.f({0, 0, 1});
    (void)b.pdf({0, 0, 1});
    EXPECT_EQ(diffuse.count, 1);
  }
}

}  // namespace
}  // namespace glint
