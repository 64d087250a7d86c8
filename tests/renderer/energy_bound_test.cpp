// The energy bound (issue 49, item 4): under a uniform sky of radiance 1 and nothing else, no
// single sample of a surface that does not emit may be brighter than the sky by more than its
// BSDF's sampling allows. A mean or a FLIP average hides a seam of fireflies; the brightest
// sample does not (RenderStats::brightestSample). Every material kind, with and without bump
// and normal maps, on a curved and a creased solid, seen straight on and at grazing angles.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "renderer/render.h"
#include "test_support.h"

namespace glint {
namespace {

// A sphere and a box of material `m`, under a white sky of radiance 1, seen from `camera`
// (the box's edges and the sphere's limb are the grazing views).
std::string skyScene(const std::string& material, const std::string& camera, int depth) {
  return R"({
    "render": {"width": 40, "height": 30, "spp": 16, "camera": "c", "seed": 5,
               "integrator": {"type": "path", "max_depth": )" +
         std::to_string(depth) + R"(}},
    "environment": {"color": [1, 1, 1]},
    "cameras": [)" +
         camera + R"(],
    "textures": [{"name": "bumps", "type": "noise", "seed": 3, "mapping": {"space": "object", "scale": [9, 9, 9]}},
                 {"name": "tilts", "type": "marble", "seed": 4, "colors": [[0.2, 0.3, 1], [0.85, 0.7, 1]],
                  "mapping": {"space": "object", "scale": [6, 6, 6]}}],
    "materials": [)" +
         material + R"(],
    "objects": [{"type": "sphere", "center": [-0.7, 0.6, 0], "radius": 0.6, "material": "m"},
                {"type": "box", "min": [0.2, 0, -0.5], "max": [1.2, 1, 0.5], "material": "m",
                 "transform": [{"rotate": {"axis": [0, 1, 0], "degrees": 35}}]}]})";
}

const std::vector<std::string> kMaterials = {
    R"({"name": "m", "type": "lambert", "diffuse": [0.9, 0.2, 0.1]})",
    R"({"name": "m", "type": "phong", "diffuse": [0.7, 0.1, 0.08], "specular": [0.28, 0.28, 0.28], "shininess": 40})",
    R"({"name": "m", "type": "blinn_phong", "diffuse": [0.1, 0.2, 0.6], "specular": [0.3, 0.3, 0.3], "shininess": 200})",
    R"({"name": "m", "type": "mirror", "color": [0.95, 0.6, 0.3]})",
    R"({"name": "m", "type": "glass", "ior": 1.5})",
    R"({"name": "m", "type": "glass", "ior": 1.5, "roughness": 0.2})",
    R"({"name": "m", "type": "pbr", "base_color": [0.36, 0.05, 0.016], "metallic": 1, "roughness": 0})",
    R"({"name": "m", "type": "pbr", "base_color": [0.8, 0.8, 0.85], "metallic": 1, "roughness": 0.13})",
    R"({"name": "m", "type": "pbr", "base_color": [0.9, 0.5, 0.2], "metallic": 1, "roughness": 0.5})",
    R"({"name": "m", "type": "pbr", "base_color": [0.9, 0.1, 0.1], "metallic": 0, "roughness": 0.3})",
    R"({"name": "m", "type": "pbr", "base_color": [0.8, 0.8, 0.8], "metallic": 0.5, "roughness": 0.05,
        "clearcoat": {"factor": 1, "roughness": 0.1}, "sheen": {"color": [0.5, 0.2, 0.8], "roughness": 0.5}})",
    R"({"name": "m", "type": "pbr", "base_color": [0.9, 0.9, 0.9], "metallic": 0, "roughness": 0.2,
        "transmission": 1})",
    R"({"name": "m", "type": "pbr", "base_color": [0.7, 0.7, 0.7], "metallic": 1, "roughness": 0.3,
        "anisotropy": {"strength": 0.8, "rotation": 0.5}})",
};

// Straight on, and nearly along the box's top face and the sphere's limb.
const std::vector<std::string> kCameras = {
    R"({"name": "c", "position": [0, 1.2, 4], "look_at": [0, 0.5, 0], "yfov_degrees": 40})",
    R"({"name": "c", "position": [4, 1.05, 0.4], "look_at": [0, 0.95, 0], "yfov_degrees": 30})",
};

// One bounce: a sample is what next-event estimation and the BSDF sample each bring from the
// sky's 1. The lobes are chosen by their largest channel and each lobe is sampled by its own
// density, so a BSDF sample's weight stays below the sum of the lobe weights at wo (under 1.5
// for every glTF surface, PbrSampling.NoSampleWeighsMoreThanTheLobesTogether); the power
// heuristic gives the light sample at most half of that. Over eight bounces a sample is the
// sum of what each vertex adds, and Russian roulette scales a surviving path's throughput back
// up towards 1, so each vertex may add up to the one-bounce bound. Measured (16 spp, 40 x 30,
// both views, bare, bumped and normal-mapped): after one bounce at most 1.96 (the sheen and
// coat), after eight 3.19 (Phong; a Lambert crevice 3.11, rough glass 1.50, a transmitting
// glTF surface 1.46, where choosing reflection or refraction at the macro normal gave 27.5,
// and the sheen's cosine sampling 2.33 after one bounce). DamagedHelmet's seam had samples of
// 93 after one bounce and weights of 1,393 (issue 49).
constexpr float kOneBounce = 1.5f * 1.5f, kEightBounces = 8 * kOneBounce;

TEST(EnergyBound, NoSampleUnderAWhiteSkyIsBrighterThanTheBsdfAllows) {
  for (const std::string& modifier :
       {std::string(), std::string(R"(, "bump": {"texture": "bumps", "strength": 0.05})"),
        std::string(R"(, "normal_map": {"texture": "tilts", "scale": 1})")})
    for (std::string material : kMaterials) {
      material.insert(material.size() - 1, modifier);
      for (const std::string& camera : kCameras)
        for (int depth : {1, 8}) {
          const test::Rendered r = test::renderJson(skyScene(material, camera, depth));
          const float bound = depth == 1 ? kOneBounce : kEightBounces;
          EXPECT_LE(r.stats.brightestSample, bound) << material << "\n"
                                                    << camera << "\ndepth " << depth;
          EXPECT_EQ(r.stats.nonfiniteSamples, 0u) << material;
          // The sky itself is seen: the check is not vacuous.
          EXPECT_GE(r.stats.brightestSample, 0.99f) << material;
        }
    }
}

// The negative control: the same check catches an emitter of radiance 3 (a sample of 3 in a
// scene whose one-bounce bound is 2.25), so it would catch a BSDF sample that heavy.
TEST(EnergyBound, TheCheckSeesASampleThreeTimesTheSky) {
  const test::Rendered r = test::renderJson(skyScene(
      R"({"name": "m", "type": "lambert", "diffuse": [0.5, 0.5, 0.5], "emissive": [3, 3, 3]})",
      kCameras[0], 1));
  EXPECT_GT(r.stats.brightestSample, kOneBounce);
}

}  // namespace
}  // namespace glint
