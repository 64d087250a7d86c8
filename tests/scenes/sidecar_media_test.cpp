// glint tests — the sidecar's "media": regions, coefficients, density fields, .vol grids, and
// the errors for bad ones, each naming its JSON pointer.
#include <gtest/gtest.h>

#include <filesystem>

#include "geometry/shapes/cylinder.h"
#include "scene_error_support.h"
#include "scenes/build.h"
#include "scenes/sidecar.h"
#include "scenes/vol_file.h"
#include "test_support.h"

namespace glint {
namespace {

using test::errorFrom;

constexpr const char* kFile = "media.json";
const std::string kObjects =
    R"("objects": [{"name": "ball", "type": "sphere", "radius": 2},
                   {"name": "floor", "type": "plane"}])";

SceneDescription applyMedia(const std::string& media, const std::string& file = kFile) {
  SceneDescription scene;
  applySceneJsonText("{" + kObjects + ", \"media\": " + media + "}", file, SceneJsonKind::Scene,
                     &scene);
  return scene;
}

SceneError applyError(const std::string& media, const std::string& file = kFile) {
  return errorFrom([&] { applyMedia(media, file); });
}

TEST(SidecarMedia, ReadsRegionsCoefficientsAndDensities) {
  SceneDescription s = applyMedia(R"([
    {"name": "fog", "sigma_a": 0.1, "sigma_s": [0.2, 0.3, 0.4], "g": 0.5,
     "density": {"type": "exponential", "falloff": 2, "height": 1, "up": [0, 0, 3]}},
    {"region": {"type": "box", "min": [0, 0, 0], "max": [1, 2, 3],
                "transform": [{"translate": [1, 0, 0]}]},
     "emission": [1, 2, 3], "density": {"type": "noise", "scale": 3, "octaves": 2,
                                        "threshold": 0.4, "seed": 9,
                                        "offset": [0.5, 1, 2]}},
    {"object": "ball", "sigma_a": {"keys": [[0, 1], [1, 3]]},
     "density": {"type": "grid", "resolution": [2, 1, 1], "values": [0, 2]}},
    {"region": {"type": "cylinder", "radius": 1, "height": 2}, "sigma_s": 1,
     "density": {"type": "constant", "value": 0.5}}
  ])");
  ASSERT_EQ(s.media.size(), 4u);
  const MediumDesc& fog = s.media[0];
  EXPECT_EQ(fog.name, "fog");
  EXPECT_EQ(fog.region, MediumDesc::Region::Scene);
  EXPECT_EQ(fog.sigmaA, (Rgb{0.1f, 0.1f, 0.1f}));
  EXPECT_EQ(fog.sigmaS, (Rgb{0.2f, 0.3f, 0.4f}));
  EXPECT_EQ(fog.g, 0.5f);
  EXPECT_EQ(fog.density, DensityType::Exponential);
  EXPECT_EQ(fog.up, (Vec3f{0, 0, 1}));
  EXPECT_EQ(fog.falloff, 2.0f);
  EXPECT_EQ(fog.h0, 1.0f);
  EXPECT_EQ(fog.where.pointer, "/media/0");
  EXPECT_EQ(s.media[1].region, MediumDesc::Region::Shape);
  EXPECT_STREQ(s.media[1].shape->typeName(), "box");
  EXPECT_EQ(s.media[1].worldFromRegion.point({0, 0, 0}), (Vec3f{1, 0, 0}));
  EXPECT_EQ(s.media[1].emission, (Rgb{1, 2, 3}));
  EXPECT_EQ(s.media[1].noiseOctaves, 2);
  EXPECT_EQ(s.media[1].noiseThreshold, 0.4f);
  EXPECT_EQ(s.media[1].noiseSeed, 9u);
  EXPECT_EQ(s.media[1].noiseOffset, (Vec3f{0.5f, 1, 2}));
  EXPECT_EQ(s.media[0].noiseOffset, (Vec3f{0, 0, 0}));  // the default
  EXPECT_EQ(s.media[2].region, MediumDesc::Region::Object);
  EXPECT_EQ(s.media[2].object, 0);
  EXPECT_EQ(s.media[2].sigmaA.x, 1.0f);  // keyframes at the scene time 0
  EXPECT_EQ(s.media[2].gridValues, (std::vector<float>{0, 2}));
  EXPECT_EQ(s.media[3].value, 0.5f);
  EXPECT_TRUE(test::shapeAs<Cylinder>(s.media[3].shape).capped());
}

TEST(SidecarMedia, BuildsMediaAndSetsTheFeature) {
  SceneDescription s = applyMedia(R"([{"object": "ball", "sigma_a": 1},
                                      {"sigma_s": 0.1}])");
  RenderScene scene = buildRenderScene(s);
  ASSERT_NE(scene.media(), nullptr);
  EXPECT_TRUE(scene.features().has(Feature::Volumes));
  EXPECT_EQ(scene.media()->regionCount(), 2u);
  // The ball region (radius 2 at the origin) is crossed over 4 units by a ray through it.
  const Ray ray{{-10, 0, 0}, {1, 0, 0}};
  std::vector<MediaScene::Interval> iv;
  scene.media()->intervals(ray, kInfinity, &iv);
  ASSERT_EQ(iv.size(), 2u);
  const auto& ball = iv[0].region == 0 ? iv[0] : iv[1];
  EXPECT_NEAR(ball.t1 - ball.t0, 4, 1e-4f);
  // Without media: no feature, no media object.
  SceneDescription none = applyMedia("[]");
  RenderScene plain = buildRenderScene(none);
  EXPECT_EQ(plain.media(), nullptr);
  EXPECT_FALSE(plain.features().has(Feature::Volumes));
}

TEST(SidecarMedia, ReadsVolFiles) {
  const std::string dir = test::scratchDir("SidecarMedia.ReadsVolFiles");
  VolumeGrid grid;
  grid.nx = 2, grid.ny = 3, grid.nz = 1;
  grid.values = {0, 1, 2, 3, 4, 5};
  grid.bounds = {{0, 0, 0}, {1, 1, 1}};
  writeVolFile(dir + "/smoke.vol", grid);
  const std::string file = dir + "/scene.json";
  SceneDescription s = applyMedia(
      R"([{"region": {"type": "sphere", "radius": 1}, "sigma_s": 1,
           "density": {"type": "grid", "file": "smoke.vol"}}])",
      file);
  ASSERT_EQ(s.media.size(), 1u);
  EXPECT_EQ(s.media[0].gridRes[0], 2);
  EXPECT_EQ(s.media[0].gridRes[1], 3);
  EXPECT_EQ(s.media[0].gridValues, grid.values);

  // A file that is not a grid: the error is at the sidecar's key and names the .vol file too
  // (the reader's own errors: tests/scenes/vol_file_test.cpp).
  {
    std::FILE* f = std::fopen((dir + "/bad.vol").c_str(), "wb");
    std::fputs("VOX nonsense", f);
    std::fclose(f);
  }
  EXPECT_SCENE_ERROR(applyError(R"([{"density": {"type": "grid", "file": "bad.vol"}}])", file),
                     file, "/media/0/density/file", "bad.vol: not a .vol grid");
  EXPECT_SCENE_ERROR(applyError(R"([{"density": {"type": "grid", "file": "missing.vol"}}])", file),
                     file, "/media/0/density/file", "file not found");
}

TEST(SidecarMedia, RejectsBadInput) {
  EXPECT_SCENE_ERROR(applyError(R"([{"sigma_a": -1}])"), kFile, "/media/0/sigma_a", ">= 0");
  EXPECT_SCENE_ERROR(applyError(R"([{"sigma_s": [0.1, -0.2, 0]}])"), kFile, "/media/0/sigma_s/1",
                     ">= 0");
  EXPECT_SCENE_ERROR(applyError(R"([{"emission": [1, 2]}])"), kFile, "/media/0/emission", "");
  EXPECT_SCENE_ERROR(applyError(R"([{"g": 1}])"), kFile, "/media/0/g", "< 1");
  EXPECT_SCENE_ERROR(applyError(R"([{"g": -1.5}])"), kFile, "/media/0/g", "> -1");
  EXPECT_SCENE_ERROR(applyError(R"([{"sigma_t": 1}])"), kFile, "/media/0/sigma_t", "unknown key");
  EXPECT_SCENE_ERROR(applyError(R"([{"density": {"type": "fractal"}}])"), kFile,
                     "/media/0/density/type", "");
  EXPECT_SCENE_ERROR(applyError(R"([{"density": {"type": "constant", "valeu": 2}}])"), kFile,
                     "/media/0/density/valeu", "unknown key");
  EXPECT_SCENE_ERROR(applyError(R"([{"density": {"type": "noise", "threshold": 1}}])"), kFile,
                     "/media/0/density/threshold", "< 1");
  EXPECT_SCENE_ERROR(applyError(R"([{"density": {"type": "exponential", "up": [0, 0, 0]}}])"),
                     kFile, "/media/0/density/up", "must not be zero");
  EXPECT_SCENE_ERROR(
      applyError(R"([{"density": {"type": "grid", "resolution": [2, 2, 2], "values": [1]}}])"),
      kFile, "/media/0/density/values", "expected 8 values");
  EXPECT_SCENE_ERROR(
      applyError(R"([{"density": {"type": "grid", "resolution": [1, 1, 1], "values": [-1]}}])"),
      kFile, "/media/0/density/values/0", ">= 0");
  EXPECT_SCENE_ERROR(applyError(R"([{"density": {"type": "grid"}}])"), kFile, "/media/0/density",
                     "either 'file'");
  EXPECT_SCENE_ERROR(applyError(R"([{"region": {"type": "disk", "radius": 1}}])"), kFile,
                     "/media/0/region/type", "");
  EXPECT_SCENE_ERROR(
      applyError(R"([{"region": {"type": "cone", "radius": 1, "height": 1, "capped": false}}])"),
      kFile, "/media/0/region", "closed solid");
  EXPECT_SCENE_ERROR(applyError(R"([{"region": {"type": "sphere", "radius": 0}}])"), kFile,
                     "/media/0/region/radius", "> 0");
  EXPECT_SCENE_ERROR(applyError(R"([{"object": "bal"}])"), kFile, "/media/0/object",
                     "did you mean 'ball'");
  EXPECT_SCENE_ERROR(applyError(R"([{"object": "floor"}])"), kFile, "/media/0/object",
                     "not a bounded convex solid");
  EXPECT_SCENE_ERROR(applyError(R"([{"object": "ball", "region": {"type": "sphere",
                                      "radius": 1}}])"),
                     kFile, "/media/0", "not both");
}

}  // namespace
}  // namespace glint
