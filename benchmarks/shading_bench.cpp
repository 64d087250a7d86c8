// glint benchmark — shading cost per hit for every shader (one thread, no ray tracing), and the
// noise patterns as the procedural textures and bump maps see them.
//
// Per hit, each benchmark does what an integrator does once it has a SurfaceInteraction:
// perturbNormal (on a copy: it edits the hit), the material's BSDF (its parameters read once),
// f towards one light direction, pdf of that direction (the MIS weight of a light sample) and
// one sample() over all lobes. An unlit
// shader (eyelight) does what Whitted does for it instead: albedo x |cos|. The hits are a fixed
// pool of 1,024 SurfaceInteractions made once from fixed seeds (see makeHits), so the numbers
// exclude tracing and computing the interaction, and every run shades the same hits with the
// same random numbers. Items processed = hits, so items_per_second is hits per second and the
// per_hit counter its inverse; lookups_per_hit counts the texture evaluations a hit makes
// (measured on an untimed copy of the material whose textures count their calls).
//
// Besides the list, phong_image and pbr_textured (glTF's base colour plus
// metallicRoughness images) show what textures cost in shaders that read them more than once.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "image/oiio/plugin.h"
#include "materials/basic_materials.h"
#include "materials/bump.h"
#include "materials/image_texture.h"
#include "materials/pbr.h"
#include "materials/procedural.h"
#include "materials/specular.h"

namespace glint {
namespace {

// ---------------------------------------------------------------------------------------------
// The hits
// ---------------------------------------------------------------------------------------------

constexpr int kHits = 1024;
constexpr int kImageSize = 512;

// One shading point and the random numbers spent on it.
struct ShadingInput {
  SurfaceInteraction si;
  Vec3f wiLight;  // towards a light, in ng's hemisphere
  Vec2f u;        // sample(): direction
  float uLobe;    // sample(): lobe choice
};

// Hits on a unit-sized object: ng uniform over the sphere; ns within ~10 degrees of it
// (interpolated vertex normals); wo cosine-distributed about ng (how a camera sees a convex
// object's projected area); the light uniform over ng's hemisphere; p in [-1, 1]^3; uv in
// [0, 1)^2 with dp/du, dp/dv tangent to the surface (lengths 0.5 to 2, slightly skewed); a
// pixel footprint of 0.5 to 2 texels of a 512^2 image, dp/dx and dp/dy consistent with it;
// three hits in four on front faces (the rest: rays leaving glass).
std::vector<ShadingInput> makeHits() {
  std::mt19937 rng(20261122);
  std::uniform_real_distribution<float> u01(0, 1), u11(-1, 1);
  auto sphere = [&] {
    const float z = u11(rng), phi = 2 * kPi * u01(rng), r = std::sqrt(std::max(0.0f, 1 - z * z));
    return Vec3f{r * std::cos(phi), r * std::sin(phi), z};
  };
  auto ball = [&] {
    for (;;) {
      Vec3f v{u11(rng), u11(rng), u11(rng)};
      if (lengthSquared(v) <= 1) return v;
    }
  };
  auto hemisphere = [&](Vec3f n, bool cosine) {
    const float a = u01(rng), b = u01(rng);
    const float z = cosine ? std::sqrt(std::max(a, 1e-4f)) : std::max(a, 1e-4f);
    const float r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPi * b;
    return Frame::fromZ(n).fromLocal({r * std::cos(phi), r * std::sin(phi), z});
  };
  auto footprint = [&] {
    const float len = (0.5f + 1.5f * u01(rng)) / kImageSize, phi = 2 * kPi * u01(rng);
    return Vec2f{len * std::cos(phi), len * std::sin(phi)};
  };

  std::vector<ShadingInput> hits(kHits);
  for (ShadingInput& h : hits) {
    SurfaceInteraction& si = h.si;
    si.frontFace = u01(rng) < 0.75f;
    si.ng = sphere();
    si.ns = clampToHemisphere(normalize(si.ng + ball() * 0.17f), si.ng);
    si.wo = hemisphere(si.ng, true);
    si.p = Vec3f{u11(rng), u11(rng), u11(rng)};
    si.uv = Vec2f{u01(rng), u01(rng)};
    // Tangents around the outward normal (ng faces the ray, so it is inward on back faces).
    const Vec3f outward = si.frontFace ? si.ng : -si.ng;
    const Frame f = Frame::fromZ(outward);
    const float phi = 2 * kPi * u01(rng);
    const Vec3f t = f.s * std::cos(phi) + f.t * std::sin(phi);
    const Vec3f b = normalize(cross(outward, t) + t * (0.3f * u11(rng)));
    si.dpdu = t * (0.5f + 1.5f * u01(rng));
    si.dpdv = b * (0.5f + 1.5f * u01(rng));
    si.duvdx = footprint();
    si.duvdy = footprint();
    si.dpdx = si.dpdu * si.duvdx.x + si.dpdv * si.duvdx.y;
    si.dpdy = si.dpdu * si.duvdy.x + si.dpdv * si.duvdy.y;
    si.instance = 0;
    si.prim = uint32_t(rng() % 100000);
    h.wiLight = hemisphere(si.ng, false);
    h.u = Vec2f{u01(rng), u01(rng)};
    h.uLobe = u01(rng);
  }
  return hits;
}

// ---------------------------------------------------------------------------------------------
// The images (in memory, 512 x 512, smooth content; lookup cost does not depend on it)
// ---------------------------------------------------------------------------------------------

std::vector<float> colorImage() {  // RGBA, sRGB-encoded, like a glTF base colour
  std::vector<float> px(size_t(kImageSize) * kImageSize * 4);
  for (int y = 0; y < kImageSize; ++y)
    for (int x = 0; x < kImageSize; ++x) {
      float* c = &px[(size_t(y) * kImageSize + x) * 4];
      const float s = float(x) / kImageSize, t = float(y) / kImageSize;
      c[0] = 0.5f + 0.5f * std::sin(2 * kPi * 5 * s);
      c[1] = 0.5f + 0.5f * std::sin(2 * kPi * 7 * t);
      c[2] = 0.5f + 0.5f * std::sin(2 * kPi * 3 * (s + t));
      c[3] = 1;
    }
  return px;
}

// Height h(s, t) = a sum of sines, 16 periods across; the normal map is its slope.
float heightAt(float s, float t) {
  return 0.5f + 0.25f * std::sin(2 * kPi * 16 * s) + 0.25f * std::sin(2 * kPi * 16 * t);
}

std::vector<float> heightImage() {  // one linear channel
  std::vector<float> px(size_t(kImageSize) * kImageSize);
  for (int y = 0; y < kImageSize; ++y)
    for (int x = 0; x < kImageSize; ++x)
      px[size_t(y) * kImageSize + x] = heightAt(float(x) / kImageSize, float(y) / kImageSize);
  return px;
}

std::vector<float> normalImage() {  // RGB, linear, tangent space encoded as n * 0.5 + 0.5
  std::vector<float> px(size_t(kImageSize) * kImageSize * 3);
  for (int y = 0; y < kImageSize; ++y)
    for (int x = 0; x < kImageSize; ++x) {
      const float s = float(x) / kImageSize, t = float(y) / kImageSize;
      const float k = 0.2f;  // slope scale
      Vec3f n =
          normalize(Vec3f{-k * std::cos(2 * kPi * 16 * s), -k * std::cos(2 * kPi * 16 * t), 1});
      float* c = &px[(size_t(y) * kImageSize + x) * 3];
      c[0] = 0.5f * n.x + 0.5f, c[1] = 0.5f * n.y + 0.5f, c[2] = 0.5f * n.z + 0.5f;
    }
  return px;
}

std::vector<float> metallicRoughnessImage() {  // RGB, linear: G roughness, B metallic (glTF)
  std::vector<float> px(size_t(kImageSize) * kImageSize * 3);
  for (int y = 0; y < kImageSize; ++y)
    for (int x = 0; x < kImageSize; ++x) {
      float* c = &px[(size_t(y) * kImageSize + x) * 3];
      c[0] = 1;
      c[1] = 0.3f + 0.4f * heightAt(float(x) / kImageSize, float(y) / kImageSize);
      c[2] = ((x / 64 + y / 64) & 1) ? 1.0f : 0.0f;  // metal and dielectric patches
    }
  return px;
}

// ---------------------------------------------------------------------------------------------
// The shaders
// ---------------------------------------------------------------------------------------------

enum class Shader {
  Eyelight,
  Lambert,
  Phong,
  BlinnPhong,
  Mirror,
  Glass,
  PbrDielectricRough,
  PbrMetalRough,
  PbrSmooth,
  PbrTransmission,
  RoughGlass,
  LambertImage,
  PhongImage,
  PbrTextured,
  LambertMarble,
  LambertBumpProcedural,
  LambertBumpImage,
  NormalMapped,
  Snow,
};

// Counts the texture evaluations a material makes (evaluate, scalar, and scalarGradient when
// it answers), for the lookups-per-hit column; only in an untimed copy of the setup.
class CountingTexture final : public Texture {
 public:
  CountingTexture(std::unique_ptr<Texture> t, int64_t* count) : t_(std::move(t)), count_(count) {}
  Vec4f evaluate(const TexturePoint& tp) const override {
    ++*count_;
    return t_->evaluate(tp);
  }
  bool scalarGradient(const TexturePoint& tp, Vec3f* g) const override {
    const bool known = t_->scalarGradient(tp, g);
    if (known) ++*count_;
    return known;
  }
  TextureNeeds needs() const override { return t_->needs(); }
  Rgb upperBound() const override { return t_->upperBound(); }
  bool isImage() const override { return t_->isImage(); }

 private:
  std::unique_ptr<Texture> t_;
  int64_t* count_;
};

// A material with the textures it reads (which must outlive it).
struct ShaderSetup {
  TextureImages images{&oiio::imageDecoder};
  std::vector<std::unique_ptr<Texture>> textures;
  std::unique_ptr<Material> material;
  int64_t* lookups = nullptr;  // non-null: wrap every texture in a CountingTexture

  const Texture* add(std::unique_ptr<Texture> t) {
    if (lookups) t = std::make_unique<CountingTexture>(std::move(t), lookups);
    textures.push_back(std::move(t));
    return textures.back().get();
  }
  const Texture* image(const char* name, int channels, const std::vector<float>& px,
                       ColorEncoding enc) {
    auto h = images.addPixels(name, kImageSize, kImageSize, channels, px, enc);
    return add(std::make_unique<ImageTexture>(images, h, TextureMapping{}, TextureWrap::Repeat,
                                              TextureWrap::Repeat, TextureFilter::Mipmap));
  }
  const Texture* noise(NoisePattern pattern, int octaves) {
    TextureMapping m;
    m.space = TextureMapping::Space::World;
    m.scale = {2, 2, 2};
    NoiseParams np;
    np.pattern = pattern;
    np.seed = 7;
    np.octaves = octaves;
    np.colorA = {0.9f, 0.88f, 0.85f};
    np.colorB = {0.15f, 0.15f, 0.2f};
    return add(std::make_unique<NoiseTexture>(m, np));
  }
};

std::unique_ptr<ShaderSetup> makeSetup(Shader shader, int64_t* lookups = nullptr) {
  auto s = std::make_unique<ShaderSetup>();
  s->lookups = lookups;
  const ColorParam black{{0, 0, 0}}, grey{{0.8f, 0.6f, 0.4f}};
  auto lambert = [&](ColorParam c) { return std::make_unique<LambertMaterial>(c, black); };
  auto pbr = [&](float metallic, float roughness, float transmission) {
    PbrParams p;
    p.baseColor = ColorParam{{0.9f, 0.7f, 0.5f}};
    p.metallic = FloatParam{metallic};
    p.roughness = FloatParam{roughness};
    p.transmission = FloatParam{transmission};
    return std::make_unique<PbrMaterial>(p);
  };
  switch (shader) {
    case Shader::Eyelight:
      s->material = std::make_unique<EyelightMaterial>(grey);
      break;
    case Shader::Lambert:
      s->material = lambert(grey);
      break;
    case Shader::Phong:
    case Shader::BlinnPhong:
      s->material =
          std::make_unique<PhongMaterial>(ColorParam{{0.5f, 0.3f, 0.2f}}, Rgb{0.4f, 0.4f, 0.4f},
                                          50.0f, black, shader == Shader::BlinnPhong);
      break;
    case Shader::Mirror:
      s->material = std::make_unique<MirrorMaterial>(ColorParam{{0.9f, 0.9f, 0.9f}});
      break;
    case Shader::Glass:
      s->material = std::make_unique<GlassMaterial>(1.5f, ColorParam{{1, 1, 1}});
      break;
    case Shader::PbrDielectricRough:
      s->material = pbr(0, 0.5f, 0);
      break;
    case Shader::PbrMetalRough:
      s->material = pbr(1, 0.3f, 0);
      break;
    case Shader::PbrSmooth:  // roughness 0: delta reflection plus the diffuse lobe
      s->material = pbr(0, 0, 0);
      break;
    case Shader::PbrTransmission:  // KHR_materials_transmission, smooth: clear glass from glTF
      s->material = pbr(0, 0, 1);
      break;
    case Shader::RoughGlass:  // the same, roughness 0.3: GGX reflection and refraction
      s->material = pbr(0, 0.3f, 1);
      break;
    case Shader::LambertImage:
      s->material =
          lambert(ColorParam{{1, 1, 1}, s->image("color", 4, colorImage(), ColorEncoding::Srgb)});
      break;
    case Shader::PhongImage:
      s->material = std::make_unique<PhongMaterial>(
          ColorParam{{0.6f, 0.6f, 0.6f}, s->image("color", 4, colorImage(), ColorEncoding::Srgb)},
          Rgb{0.4f, 0.4f, 0.4f}, 50.0f, black);
      break;
    case Shader::PbrTextured: {  // glTF's usual pair: base colour and metallicRoughness images
      PbrParams p;
      p.baseColor = ColorParam{{1, 1, 1}, s->image("color", 4, colorImage(), ColorEncoding::Srgb)};
      const Texture* mr = s->image("mr", 3, metallicRoughnessImage(), ColorEncoding::Linear);
      p.metallic = FloatParam{1, mr, 2};
      p.roughness = FloatParam{1, mr, 1};
      s->material = std::make_unique<PbrMaterial>(p);
      break;
    }
    case Shader::LambertMarble:
      s->material = lambert(ColorParam{{1, 1, 1}, s->noise(NoisePattern::Marble, 5)});
      break;
    case Shader::LambertBumpProcedural:  // 5-octave fBm height, exact gradient
      s->material = lambert(grey);
      s->material->setNormalModifier(
          std::make_unique<BumpMap>(s->noise(NoisePattern::Fbm, 5), 0.02f));
      break;
    case Shader::LambertBumpImage:  // finite differences: four lookups
      s->material = lambert(grey);
      s->material->setNormalModifier(std::make_unique<BumpMap>(
          s->image("height", 1, heightImage(), ColorEncoding::Linear), 0.005f));
      break;
    case Shader::NormalMapped:
      s->material = lambert(grey);
      s->material->setNormalModifier(std::make_unique<NormalMap>(
          s->image("normal", 3, normalImage(), ColorEncoding::Linear), 1.0f));
      break;
    case Shader::Snow:
      s->material = lambert(ColorParam{{0.95f, 0.95f, 0.95f}});
      s->material->setNormalModifier(std::make_unique<SnowPerturbation>(0.3f, 0.01f, 7));
      break;
  }
  return s;
}

// What the integrator does at one hit; returns a value that depends on all of it.
inline float shade(const Material& m, bool unlit, const ShadingInput& in) {
  SurfaceInteraction si = in.si;
  m.perturbNormal(si);
  TextureLookups lookups(si);
  if (unlit) return m.albedo(si, lookups).x * std::abs(dot(si.ns, si.wo));
  const Bsdf bsdf = m.bsdf(si, lookups);
  // f and pdf towards the light in one evaluation, as next-event estimation with MIS asks.
  float lightPdf = 0;
  const Rgb f = bsdf.evaluate(in.wiLight, &lightPdf);
  float v = f.x + lightPdf;
  if (BsdfSample s; bsdf.sample(in.u, in.uLobe, &s)) v += s.f.x + s.pdf + s.wi.x;
  return v;
}

void BM_Shade(benchmark::State& state, Shader shader) {
  const std::vector<ShadingInput> hits = makeHits();
  const std::unique_ptr<ShaderSetup> scene = makeSetup(shader);
  const Material& m = *scene->material;
  const bool unlit = (m.flags() & kBsdfUnlit) != 0;
  float sink = 0;
  for (int pass = 0; pass < 2; ++pass)  // load every image tile and MIP level the hits touch
    for (const ShadingInput& h : hits) sink += shade(m, unlit, h);
  for (auto _ : state) {
    for (const ShadingInput& h : hits) sink += shade(m, unlit, h);
    benchmark::DoNotOptimize(sink);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * kHits);
  state.counters["per_hit"] = benchmark::Counter(
      kHits, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);

  // The same hits once more, untimed, through counting textures.
  int64_t lookups = 0;
  const std::unique_ptr<ShaderSetup> counted = makeSetup(shader, &lookups);
  for (const ShadingInput& h : hits) sink += shade(*counted->material, unlit, h);
  benchmark::DoNotOptimize(sink);
  state.counters["lookups_per_hit"] = double(lookups) / kHits;
}

// The floor: copying the hit and reading it, without a material.
void BM_Shade_overhead(benchmark::State& state) {
  const std::vector<ShadingInput> hits = makeHits();
  float sink = 0;
  for (auto _ : state) {
    for (const ShadingInput& h : hits) {
      SurfaceInteraction si = h.si;
      benchmark::DoNotOptimize(si);
      sink += si.ns.x + h.wiLight.x + h.u.x + h.uLobe;
    }
    benchmark::DoNotOptimize(sink);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * kHits);
  state.counters["per_hit"] = benchmark::Counter(
      kHits, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

BENCHMARK(BM_Shade_overhead);
BENCHMARK_CAPTURE(BM_Shade, eyelight, Shader::Eyelight);
BENCHMARK_CAPTURE(BM_Shade, lambert, Shader::Lambert);
BENCHMARK_CAPTURE(BM_Shade, phong, Shader::Phong);
BENCHMARK_CAPTURE(BM_Shade, blinn_phong, Shader::BlinnPhong);
BENCHMARK_CAPTURE(BM_Shade, mirror, Shader::Mirror);
BENCHMARK_CAPTURE(BM_Shade, glass, Shader::Glass);
BENCHMARK_CAPTURE(BM_Shade, pbr_dielectric_rough, Shader::PbrDielectricRough);
BENCHMARK_CAPTURE(BM_Shade, pbr_metal_rough, Shader::PbrMetalRough);
BENCHMARK_CAPTURE(BM_Shade, pbr_smooth, Shader::PbrSmooth);
BENCHMARK_CAPTURE(BM_Shade, pbr_transmission, Shader::PbrTransmission);
BENCHMARK_CAPTURE(BM_Shade, rough_glass, Shader::RoughGlass);
BENCHMARK_CAPTURE(BM_Shade, lambert_image, Shader::LambertImage);
BENCHMARK_CAPTURE(BM_Shade, phong_image, Shader::PhongImage);
BENCHMARK_CAPTURE(BM_Shade, pbr_textured, Shader::PbrTextured);
BENCHMARK_CAPTURE(BM_Shade, lambert_marble, Shader::LambertMarble);
BENCHMARK_CAPTURE(BM_Shade, lambert_bump_procedural, Shader::LambertBumpProcedural);
BENCHMARK_CAPTURE(BM_Shade, lambert_bump_image, Shader::LambertBumpImage);
BENCHMARK_CAPTURE(BM_Shade, normal_map, Shader::NormalMapped);
BENCHMARK_CAPTURE(BM_Shade, snow, Shader::Snow);

// ---------------------------------------------------------------------------------------------
// Noise patterns through NoiseTexture (the mapping, the pattern and the colour mix; the
// gradient is what procedural bump maps use), at the pool's hit points
// ---------------------------------------------------------------------------------------------

void BM_Pattern(benchmark::State& state, NoisePattern pattern, bool gradient) {
  const std::vector<ShadingInput> hits = makeHits();
  ShaderSetup scene;
  const Texture& t = *scene.noise(pattern, pattern == NoisePattern::Clouds ? 6 : 5);
  std::vector<TexturePoint> points;
  for (const ShadingInput& h : hits) points.emplace_back(h.si);
  float sink = 0;
  for (auto _ : state) {
    for (const TexturePoint& tp : points) {
      if (gradient) {
        Vec3f g;
        t.scalarGradient(tp, &g);
        sink += g.x;
      } else {
        sink += t.evaluate(tp).x;
      }
    }
    benchmark::DoNotOptimize(sink);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(points.size()));
}

BENCHMARK_CAPTURE(BM_Pattern, noise_evaluate, NoisePattern::Noise, false);
BENCHMARK_CAPTURE(BM_Pattern, noise_gradient, NoisePattern::Noise, true);
BENCHMARK_CAPTURE(BM_Pattern, fbm5_evaluate, NoisePattern::Fbm, false);
BENCHMARK_CAPTURE(BM_Pattern, fbm5_gradient, NoisePattern::Fbm, true);
BENCHMARK_CAPTURE(BM_Pattern, marble_evaluate, NoisePattern::Marble, false);
BENCHMARK_CAPTURE(BM_Pattern, marble_gradient, NoisePattern::Marble, true);
BENCHMARK_CAPTURE(BM_Pattern, wood_evaluate, NoisePattern::Wood, false);
BENCHMARK_CAPTURE(BM_Pattern, wood_gradient, NoisePattern::Wood, true);
BENCHMARK_CAPTURE(BM_Pattern, clouds6_evaluate, NoisePattern::Clouds, false);
BENCHMARK_CAPTURE(BM_Pattern, clouds6_gradient, NoisePattern::Clouds, true);

}  // namespace
}  // namespace glint

BENCHMARK_MAIN();
