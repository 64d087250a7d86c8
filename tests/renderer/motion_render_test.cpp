// Motion blur in the rendered image: a moving sphere's blurred render equals the average of
// static renders over the shutter, up to sampling noise; a scene that does not move renders
// as before.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/shapes/sphere.h"
#include "renderer/render.h"
#include "scenes/build.h"
#include "scenes/load.h"
#include "test_support.h"

namespace glint {
namespace {

// An orthographic camera 5 in front of `centre` (along +z) seeing xmag x ymag half-extents,
// its shutter open from 0 to `shutterClose`.
CameraDesc frontCamera(float xmag, float ymag, Vec3f centre, float shutterClose) {
  CameraDesc cam;
  cam.name = "front";
  cam.type = CameraType::Orthographic;
  cam.xmag = xmag;
  cam.ymag = ymag;
  cam.worldFromCamera = Transform::lookAt(centre + Vec3f{0, 0, 5}, centre, {0, 1, 0});
  cam.shutterClose = shutterClose;
  return cam;
}

// An eyelight sphere (radius 0.5) moving from x = -1 to x = 1 over one second, seen head-on by
// an orthographic camera covering [-2, 2] x [-1, 1].
SceneDescription movingBall(float shutterClose, double time, bool textured = false) {
  SceneDescription d;
  d.file = "moving ball (in code)";
  MaterialDesc white;
  white.name = "white";
  white.type = MaterialType::Eyelight;
  if (textured) {
    // Checkers fixed to the ball (object space): they must travel with it.
    TextureDesc checks;
    checks.name = "checks";
    checks.kind = TextureKind::Checker;
    checks.solid = true;
    checks.mapping.space = MappingDesc::Space::Object;
    checks.mapping.scale = {4, 4, 4};
    checks.colorA = {0.1f, 0.1f, 0.1f};
    d.textures.push_back(checks);
    white.baseColorTexture = 0;
  }
  d.materials.push_back(white);
  NodeDesc node;
  node.translationTrack.times = {0, 1};
  node.translationTrack.values = {{-1, 0, 0}, {1, 0, 0}};
  d.nodes.push_back(node);
  ObjectDesc ball;
  ball.kind = ObjectKind::Shape;
  ball.shape = std::make_shared<Sphere>(Vec3f{0, 0, 0}, 0.5f);
  ball.material = 0;
  ball.transformNode = 0;
  d.objects.push_back(ball);
  d.cameras.push_back(frontCamera(2, 1, {0, 0, 0}, shutterClose));
  d.render.width = 64;
  d.render.height = 32;
  d.render.time = time;
  return d;
}

Film renderIt(const SceneDescription& d, int spp, int threads = 2) {
  SceneDescription copy = d;
  copy.render.spp = spp;
  RenderScene scene = buildRenderScene(copy);
  auto integrator = makeIntegrator(scene, copy.render);
  RenderOptions options;
  options.threads = threads;
  RenderStats stats;
  return render(scene, *integrator, copy.render, options, &stats);
}

double meanAbsDifference(const Film& a, const Film& b) {
  double sum = 0;
  for (size_t i = 0; i < a.color.size(); ++i)
    sum += std::abs(luminance(a.color[i]) - luminance(b.color[i]));
  return sum / double(a.color.size());
}

class MotionRender : public testing::TestWithParam<bool> {};

// Untextured, and with object-space checkers that must move with the ball (its texture frame
// is the object's at each ray's time).
TEST_P(MotionRender, BlurEqualsTheAverageOfStaticFrames) {
  const bool textured = GetParam();
  const Film blurred = renderIt(movingBall(1, 0, textured), 256);
  // The box-filtered time average: 32 static frames at the midpoints of equal time slices.
  constexpr int kSlices = 32;
  Film average = renderIt(movingBall(0, 0.5 / kSlices, textured), 8);
  for (Rgb& c : average.color) c = {};
  for (int k = 0; k < kSlices; ++k) {
    Film frame = renderIt(movingBall(0, (k + 0.5) / kSlices, textured), 8);
    for (size_t i = 0; i < frame.color.size(); ++i)
      average.color[i] += frame.color[i] / float(kSlices);
  }
  const Film still = renderIt(movingBall(0, 0.5, textured), 8);
  double blurError = meanAbsDifference(blurred, average);
  double stillError = meanAbsDifference(still, average);
  // The blurred streak covers x in [-1.5, 1.5] with a ramp; a still ball is a disc. Their
  // difference is large, while the blur agrees with the average up to noise and the
  // 1/32-second discretisation of the average.
  EXPECT_LT(blurError, 0.01) << "blurred render differs from the time average";
  EXPECT_GT(stillError, 10 * blurError) << "the test cannot tell blur from no blur";
}

INSTANTIATE_TEST_SUITE_P(Materials, MotionRender, testing::Values(false, true),
                         [](const testing::TestParamInfo<bool>& p) {
                           return p.param ? "ObjectSpaceTexture" : "Plain";
                         });

// Deformation blur: the skinned triangle of tests/data/gltf/skin_morph.gltf, whose joint turns
// it through 90 degrees over a second, blurred over that second equals the average of still
// frames, as a moving object does.
SceneDescription turningTriangle(float shutterClose, double time) {
  SceneDescription d = loadScene(test::dataDir() + "/gltf/skin_morph.gltf");
  d.instances.erase(d.instances.begin(), d.instances.begin() + 3);  // the skinned one alone
  MaterialDesc white;
  white.name = "white";
  white.type = MaterialType::Eyelight;
  d.materials.push_back(white);
  d.instances[0].material = int(d.materials.size()) - 1;
  d.cameras = {frontCamera(1.25f, 1.25f, {0.5f, 1, 0}, shutterClose)};
  d.render.camera.clear();
  d.render.width = 40;
  d.render.height = 40;
  d.render.time = time;
  // The triangle's silhouette against a grey background is what the renders differ by (its
  // eyelight shading is dark here); a scene of eyelight surfaces gets no default light.
  d.render.background = {0.5f, 0.5f, 0.5f};
  return d;
}

TEST(DeformationRender, BlurEqualsTheAverageOfStaticFrames) {
  const Film blurred = renderIt(turningTriangle(1, 0), 256);
  constexpr int kSlices = 32;
  Film average = renderIt(turningTriangle(0, 0.5 / kSlices), 8);
  for (Rgb& c : average.color) c = {};
  for (int k = 0; k < kSlices; ++k) {
    Film frame = renderIt(turningTriangle(0, (k + 0.5) / kSlices), 8);
    for (size_t i = 0; i < frame.color.size(); ++i)
      average.color[i] += frame.color[i] / float(kSlices);
  }
  const Film still = renderIt(turningTriangle(0, 0.5), 8);
  const double blurError = meanAbsDifference(blurred, average);
  const double stillError = meanAbsDifference(still, average);
  EXPECT_LT(blurError, 0.01) << "blurred render differs from the time average";
  EXPECT_GT(stillError, 5 * blurError) << "the test cannot tell blur from no blur";
}

TEST(MotionRenderThreads, SameImageForAnyThreadCount) {
  const SceneDescription d = movingBall(1, 0, true);
  Film one = renderIt(d, 16, 1), two = renderIt(d, 16, 2);
  ASSERT_EQ(one.color.size(), two.color.size());
  for (size_t i = 0; i < one.color.size(); ++i) ASSERT_EQ(one.color[i], two.color[i]) << i;
}

}  // namespace
}  // namespace glint
