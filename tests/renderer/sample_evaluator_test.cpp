// Tests for the render loop's inner parts: a pixel's sums (renderer/pixel_sums.h) give the film
// pixel and come back from it, and the sample evaluator (renderer/sample_evaluator.h) gives a
// pixel the same sums however its samples are cut into batches, with a lens and motion too,
// and puts a centre look through the middle of the pixel.
#include "renderer/sample_evaluator.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "scenes/build.h"
#include "scenes/sidecar.h"
#include "test_support.h"

namespace glint {
namespace {

PathAovs hitAt(Rgb albedo, Vec3f normal, float depth) {
  PathAovs a;
  a.wanted = true;
  a.hit = true;
  a.albedo = albedo, a.normal = normal, a.depth = depth;
  return a;
}

TEST(PixelSums, TheFilmPixelIsTheirMeanAndGivesThemBack) {
  PixelSums sums;
  sums.add(Rgb{1, 2, 3}, hitAt({0.5f, 0.5f, 0.5f}, {0, 1, 0}, 2));
  sums.add(Rgb{3, 2, 1}, PathAovs{});  // escaped: no hit, no AOVs
  sums.add(Rgb{2, 2, 2}, hitAt({0.3f, 0.1f, 0.5f}, {0, 0, 1}, 4));
  EXPECT_EQ(sums.taken, 3u);
  EXPECT_EQ(sums.hits, 2u);
  Film film(2, 1, true);
  sums.writeTo(film, 1);
  EXPECT_EQ(film.samples[1], 3u);
  EXPECT_FLOAT_EQ(film.color[1][0], 2);
  EXPECT_FLOAT_EQ(film.variance[1][0], 1.0f / 3);  // sample variance 1, over 3 samples
  EXPECT_FLOAT_EQ(film.variance[1][1], 0);
  EXPECT_FLOAT_EQ(film.alpha[1], 2.0f / 3);
  EXPECT_FLOAT_EQ(film.albedo[1][0], 0.8f / 3);
  EXPECT_FLOAT_EQ(film.normal[1][2], 1.0f / 3);
  EXPECT_FLOAT_EQ(film.depth[1], 3);  // over the hits only
  const PixelSums back = PixelSums::readFrom(film, 1);
  EXPECT_EQ(back.taken, 3u);
  EXPECT_EQ(back.hits, 2u);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(back.moments.sum[c], sums.moments.sum[c], 1e-5);
    EXPECT_NEAR(back.moments.sumSq[c], sums.moments.sumSq[c], 1e-5);
    EXPECT_NEAR(back.albedo[c], sums.albedo[c], 1e-6);
  }
  EXPECT_NEAR(back.depth, 6, 1e-6);
  // A pixel without samples is black and transparent, and gives empty sums.
  PixelSums{}.writeTo(film, 0);
  EXPECT_EQ(film.color[0], Rgb{});
  EXPECT_EQ(film.alpha[0], 0);
  EXPECT_EQ(PixelSums::readFrom(film, 0).moments.sumSq[0], 0);
}

TEST(PixelSumsGrid, KeepsAovSumsOnlyWhenAsked) {
  PixelSums sums;
  sums.add(Rgb{1, 1, 1}, hitAt({0.5f, 0.5f, 0.5f}, {0, 1, 0}, 2));
  PixelSumsGrid with, without;
  with.allocate(4, true);
  without.allocate(4, false);
  with.store(2, sums);
  without.store(2, sums);
  EXPECT_EQ(with.load(2).depth, 2);
  EXPECT_EQ(without.load(2).depth, 0);
  EXPECT_EQ(without.load(2).hits, 1u);
  EXPECT_EQ(without.taken(2), 1u);
  EXPECT_EQ(with.load(1).taken, 0u);
}

struct Stage {
  SceneDescription desc;
  RenderScene scene;
  std::unique_ptr<Integrator> integrator;
};

std::unique_ptr<Stage> stage(const std::string& json) {
  auto s = std::make_unique<Stage>();
  s->desc.file = "sample_evaluator_test (in code)";
  applySceneJsonText(json, s->desc.file, SceneJsonKind::Scene, &s->desc);
  s->desc.render.seed = 5;
  s->desc.render.aovs = true;
  s->scene = buildRenderScene(s->desc);
  s->integrator = makeIntegrator(s->scene, s->desc.render);
  return s;
}

// Samples 0..15 of pixel (x, y) in batches of the given sizes.
PixelSums evaluateInBatches(const Stage& s, int x, int y, std::initializer_list<uint32_t> sizes) {
  const SampleEvaluator evaluator(s.scene, *s.integrator, s.desc.render);
  SampleEvaluator::Batch batch;
  SampleTally tally;
  PixelSums sums;
  const PixelKeys keys = evaluator.keys(x, y);
  for (uint32_t n : sizes) evaluator.evaluate(keys, n, false, batch, sums, tally);
  EXPECT_EQ(tally.rays.camera, 16u);
  return sums;
}

void expectSameSums(const PixelSums& a, const PixelSums& b) {
  EXPECT_EQ(a.taken, b.taken);
  EXPECT_EQ(a.hits, b.hits);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(a.moments.sum[c], b.moments.sum[c]);
    EXPECT_EQ(a.moments.sumSq[c], b.moments.sumSq[c]);
    EXPECT_EQ(a.albedo[c], b.albedo[c]);
    EXPECT_EQ(a.normal[c], b.normal[c]);
  }
  EXPECT_EQ(a.depth, b.depth);
}

TEST(SampleEvaluator, BatchesOfAnySizeGiveTheSameSums) {
  // The ball's top edge at (10, 3) of the 20 x 18 image: its samples both hit and miss it.
  const auto pinhole = stage(test::litBallJson(20, 18));
  const PixelSums whole = evaluateInBatches(*pinhole, 10, 3, {16});
  EXPECT_GT(whole.hits, 0u);
  EXPECT_LT(whole.hits, 16u);
  expectSameSums(whole, evaluateInBatches(*pinhole, 10, 3, {1, 1, 2, 4, 8}));
  expectSameSums(whole, evaluateInBatches(*pinhole, 10, 3, {3, 13}));
  // A thin lens and a moving ball: the lens points and shutter times are drawn per sample.
  std::string moving = test::litBallJson(20, 18);
  moving.replace(
      moving.find("\"yfov_degrees\": 30"), 18,
      R"("yfov_degrees": 30, "aperture": 0.1, "focus_distance": 4, "shutter": [0, 0.5])");
  moving.replace(
      moving.find("\"material\": \"clay\"}"), 19,
      R"("material": "clay", "animation": {"translation": {"keys": [[0, [0, 0, 0]], [1, [0.3, 0, 0]]]}}})");
  const auto blurred = stage(moving);
  ASSERT_TRUE(blurred->scene.camera().hasLens());
  ASSERT_TRUE(blurred->scene.features().has(Feature::MotionBlur));
  const PixelSums blur = evaluateInBatches(*blurred, 10, 3, {16});
  expectSameSums(blur, evaluateInBatches(*blurred, 10, 3, {1, 1, 2, 4, 8}));
  EXPECT_NE(blur.moments.sum[0], whole.moments.sum[0]);
}

TEST(SampleEvaluator, TheCentreLookGoesThroughTheMiddleOfThePixel) {
  const auto s = stage(test::litBallJson(20, 18));
  const SampleEvaluator evaluator(s->scene, *s->integrator, s->desc.render);
  SampleEvaluator::Batch batch;
  SampleTally tally;
  PixelSums sums;
  evaluator.evaluate(evaluator.keys(7, 3), 1, true, batch, sums, tally);
  const Ray expected = s->scene.camera().generateRay(Vec2f{7.5f, 3.5f}, 0);
  EXPECT_EQ(batch.rays[0].o, expected.o);
  EXPECT_EQ(batch.rays[0].d, expected.d);
  EXPECT_EQ(sums.taken, 1u);
  // A sample placed by the filter is elsewhere in the pixel.
  PixelSums other;
  evaluator.evaluate(evaluator.keys(7, 3), 1, false, batch, other, tally);
  EXPECT_NE(batch.rays[0].d, expected.d);
}

}  // namespace
}  // namespace glint
