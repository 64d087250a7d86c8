// The glTF metallic-roughness texture: metallic from its blue channel, roughness from green,
// read in one lookup, must shade exactly like the same constant factors.
#include <gtest/gtest.h>

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
    const Rgb fa = a.eval(si, wi), fb = b.eval(si, wi);
    EXPECT_NEAR(fa.x, fb.x, 1e-6f * std::max(1.0f, fb.x));
    EXPECT_NEAR(fa.y, fb.y, 1e-6f * std::max(1.0f, fb.y));
    EXPECT_GT(fa.x, 0);
    EXPECT_NEAR(a.pdf(si, wi), b.pdf(si, wi), 1e-6f * std::max(1.0f, b.pdf(si, wi)));
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
    std::optional<BsdfSample> s = m.sample(si, {0.3f, 0.6f}, 0.1f, kBsdfReflection | kBsdfSpecular);
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

}  // namespace
}  // namespace glint
