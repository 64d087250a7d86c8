// Render tests for the thin lens and the shutter: an aperture of 0 is the pinhole, the focus
// plane stays sharp, defocus blurs by the thin-lens circle of confusion, time is sampled only
// for motion blur and moves the camera, and all of it is independent of threads and tiles.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <vector>

#include "renderer/render.h"
#include "scenes/build.h"

namespace glint {
namespace {

// ---- scenes ----------------------------------------------------------------------------------

// An axis-aligned rectangle [x0, x1] x [y0, y1] facing +Z at z = -depth.
void addRect(SceneDescription* d, float x0, float x1, float y0, float y1, float depth,
             int material) {
  MeshDesc m;
  m.positions = {{x0, y0, -depth}, {x1, y0, -depth}, {x1, y1, -depth}, {x0, y1, -depth}};
  m.normals.assign(4, {0, 0, 1});
  m.indices = {0, 1, 2, 0, 2, 3};
  m.material = material;
  d->meshes.push_back(m);
  d->instances.push_back({int(d->meshes.size() - 1), Transform(), "rect", {}});
}

// A camera at the origin looking down -Z (tan(yfov/2) = 1/2: the film is as high as it is far
// away) at a vertical edge on x = 0, `depth` away: black on the left, white on the right. Both
// halves only emit (black Lambert under the default studio light), so a sample's value does not
// depend on the ray's direction, and lens and pinhole rays that hit the same side give the same
// value.
SceneDescription edgeScene(float depth, int width, int height, int spp) {
  SceneDescription d;
  d.file = "edge (in code)";
  MaterialDesc black;
  black.name = "Black";
  black.type = MaterialType::Lambert;
  black.baseColor = {0, 0, 0};
  MaterialDesc white = black;
  white.name = "White";
  white.emissive = {1, 1, 1};
  d.materials = {black, white};
  const float half = 3 * depth + 3;  // beyond the view and every lens ray
  addRect(&d, -half, 0, -half, half, depth, 0);
  addRect(&d, 0, half, -half, half, depth, 1);
  CameraDesc cam;
  cam.name = "Front";
  cam.yfov = 2 * std::atan(0.5f);
  cam.worldFromCamera = Transform();
  d.cameras.push_back(cam);
  d.render.width = width;
  d.render.height = height;
  d.render.spp = spp;
  return d;
}

Film renderScene(const RenderScene& scene, const SceneDescription& d, int threads = 2,
                 int tileSize = 16) {
  auto integrator = makeIntegrator(scene, d.render);
  RenderOptions options;
  options.threads = threads;
  options.tileSize = tileSize;
  RenderStats stats;
  return render(scene, *integrator, d.render, options, &stats);
}

// Records every camera ray and the path's first integrator sample; returns (sample, time,
// origin x). Run with one thread, it sees the pixels' samples in order, spp at a time.
class ProbeIntegrator final : public Integrator {
 public:
  using Integrator::Integrator;
  Rgb LiFromHit(const Ray& ray, const Hit*, Sampler& sampler, RayCounters&,
                PathAovs& aovs) const override {
    aovs.hit = true;
    const float u = sampler.get1D();
    std::lock_guard<std::mutex> lock(mutex_);
    rays.push_back(ray);
    samples.push_back(u);
    return {u, ray.time, ray.o.x};
  }
  mutable std::vector<Ray> rays;
  mutable std::vector<float> samples;

 private:
  mutable std::mutex mutex_;
};

struct Probe {
  std::vector<Ray> rays;
  std::vector<float> samples;
};

Probe probe(const RenderScene& scene, const SceneDescription& d) {
  ProbeIntegrator integrator(scene);
  RenderOptions options;
  options.threads = 1;
  RenderStats stats;
  render(scene, integrator, d.render, options, &stats);
  return {integrator.rays, integrator.samples};
}

// The scene's camera given `lens` (the scene detects the lens feature again).
void withLens(RenderScene* scene, const ThinLens& lens) {
  Camera camera = scene->camera();
  camera.setLens(lens);
  scene->setCamera(camera, scene->cameraName());
}

// ---- aperture 0 ------------------------------------------------------------------------------

TEST(Lens, ApertureZeroRendersThePinholeImage) {
  SceneDescription d = edgeScene(5, 48, 32, 16);
  RenderScene pinhole = buildRenderScene(d);
  RenderScene zero = buildRenderScene(d);
  withLens(&zero, {0.0f, 5.0f, 6, 0.3f});
  zero.setFeature(Feature::Lens);  // even when told there is a lens
  Film a = renderScene(pinhole, d), b = renderScene(zero, d);
  for (size_t i = 0; i < a.color.size(); ++i) {
    ASSERT_EQ(a.color[i], b.color[i]) << "pixel " << i;
    ASSERT_EQ(a.variance[i], b.variance[i]) << "pixel " << i;
  }
  // Same camera rays, same integrator samples.
  Probe pa = probe(pinhole, d), pb = probe(zero, d);
  ASSERT_EQ(pa.rays.size(), pb.rays.size());
  for (size_t i = 0; i < pa.rays.size(); ++i) {
    ASSERT_EQ(pa.rays[i].o, pb.rays[i].o) << i;
    ASSERT_EQ(pa.rays[i].d, pb.rays[i].d) << i;
    ASSERT_EQ(pa.samples[i], pb.samples[i]) << i;
  }
  // A real aperture moves the rays but leaves the integrator's samples where they were.
  RenderScene open = buildRenderScene(d);
  withLens(&open, {0.2f, 3.0f});
  Probe pc = probe(open, d);
  ASSERT_EQ(pa.samples, pc.samples);
  size_t moved = 0;
  for (size_t i = 0; i < pa.rays.size(); ++i) moved += !(pa.rays[i].o == pc.rays[i].o);
  EXPECT_EQ(moved, pa.rays.size());
}

// ---- focus -----------------------------------------------------------------------------------

// Columns whose filter support (box, half-width 0.5) reaches the edge: only the two beside it.
bool isEdgeColumn(int x, int width) { return x == width / 2 - 1 || x == width / 2; }

TEST(Lens, FocusPlaneStaysSharp) {
  const float f = 5;
  const int width = 64, height = 32, spp = 64;
  SceneDescription d = edgeScene(f, width, height, spp);
  d.render.filter = {"box", 0.5f};
  RenderScene pinhole = buildRenderScene(d);
  RenderScene lens = buildRenderScene(d);
  withLens(&lens, {0.5f, f});
  Film a = renderScene(pinhole, d), b = renderScene(lens, d);
  // The image does hold a hard edge.
  EXPECT_EQ(a.color[a.index(width / 2 - 2, 5)].y, 0.0f);
  EXPECT_EQ(a.color[a.index(width / 2 + 1, 5)].y, 1.0f);
  // Every lens ray of a sample meets the pinhole ray on the focus plane up to float rounding
  // (~1e-6 of the distance), so only a sample within that of the edge can change sides: the
  // pixels away from the edge are identical, and the edge pixels differ by at most 2 of their
  // 64 samples (none in practice).
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float pa = a.color[a.index(x, y)].y, pb = b.color[b.index(x, y)].y;
      if (isEdgeColumn(x, width))
        EXPECT_NEAR(pa, pb, 2.0f / spp) << x << "," << y;
      else
        EXPECT_EQ(pa, pb) << x << "," << y;
    }
  // Focused twice as far, the same aperture blurs the edge over a 3.2-pixel circle: the edge
  // columns go grey (about 0.3 and 0.7), far beyond the tolerance above.
  RenderScene defocused = buildRenderScene(d);
  withLens(&defocused, {0.5f, 2 * f});
  Film c = renderScene(defocused, d);
  for (int y = 0; y < height; ++y) {
    EXPECT_GT(c.color[c.index(width / 2 - 1, y)].y, 0.2f) << y;
    EXPECT_LT(c.color[c.index(width / 2, y)].y, 0.8f) << y;
  }
}

// ---- defocus ---------------------------------------------------------------------------------

// The 10-90% width of a step seen through a uniform disk of diameter D: the disk's white
// fraction at offset h from the edge is 1/2 + (u sqrt(1 - u^2) + asin u) / pi, u = h / (D/2).
double diskEdgeWidth1090(double diameter) {
  double lo = 0, hi = 1;
  for (int i = 0; i < 60; ++i) {
    double u = (lo + hi) / 2;
    double white = 0.5 + (u * std::sqrt(1 - u * u) + std::asin(u)) / kPi;
    (white < 0.9 ? lo : hi) = u;
  }
  return 2 * lo * diameter / 2;
}

// The 10-90% width of an edge's profile (columns averaged over all rows, white = 1), by linear
// interpolation between pixel centres; and the profile's midpoint.
void measureEdge(const Film& film, double* width1090, double* middle) {
  std::vector<double> profile(size_t(film.width), 0);
  for (int x = 0; x < film.width; ++x) {
    for (int y = 0; y < film.height; ++y) profile[size_t(x)] += film.color[film.index(x, y)].y;
    profile[size_t(x)] /= film.height;
  }
  auto crossing = [&](double level) {
    for (int x = 0; x + 1 < film.width; ++x) {
      double a = profile[size_t(x)], b = profile[size_t(x + 1)];
      if (a < level && b >= level) return x + 0.5 + (level - a) / (b - a);
    }
    return -1.0;
  };
  double x10 = crossing(0.1), x90 = crossing(0.9);
  *width1090 = x90 - x10;
  *middle = (x10 + x90) / 2;
}

TEST(Lens, DefocusBlurMatchesTheCircleOfConfusion) {
  const int width = 128, height = 48, spp = 64;
  struct Case {
    float depth, focus, radius;
  };
  for (Case c : {Case{8, 4, 1}, Case{3, 4, 1.2f}, Case{10, 6, 0.6f}}) {
    SceneDescription d = edgeScene(c.depth, width, height, spp);
    d.render.filter = {"box", 0.5f};
    RenderScene scene = buildRenderScene(d);
    withLens(&scene, {c.radius, c.focus});
    Film film = renderScene(scene, d);
    // Thin lens: a point at depth d spreads over a disk of diameter 2 A |d - f| / d on the
    // focus plane, whose film is 2 f tan(yfov/2) = f high, i.e. `height` pixels.
    const double coc = 2.0 * c.radius * std::abs(c.depth - c.focus) / c.depth;
    const double cocPixels = coc * height / c.focus;
    const double predicted = diskEdgeWidth1090(cocPixels);
    double measured, middle;
    measureEdge(film, &measured, &middle);
    // Tolerance: the 1-pixel box filter widens the 10-90% width by ~0.02 px here, linear
    // interpolation between pixel centres errs by < 0.1 px, the noise of 48 x 64 samples per
    // column by ~0.05 px: 0.25 px + 2%.
    EXPECT_NEAR(measured, predicted, 0.25 + 0.02 * predicted)
        << "depth " << c.depth << ", focus " << c.focus << ", radius " << c.radius
        << ": circle of confusion " << cocPixels << " px";
    EXPECT_NEAR(middle, width / 2.0, 0.25);
  }
  // The pinhole image of the same edge is sharp: the measure does not invent a blur.
  SceneDescription d = edgeScene(8, width, height, spp);
  d.render.filter = {"box", 0.5f};
  double measured, middle;
  measureEdge(renderScene(buildRenderScene(d), d), &measured, &middle);
  EXPECT_LT(measured, 1.0);
}

// ---- shutter time ----------------------------------------------------------------------------

TEST(MotionBlur, TimeIsSampledOnlyWithTheFeatureAndMovesTheCamera) {
  const int spp = 16;
  SceneDescription d = edgeScene(5, 12, 8, spp);
  AnimatedTransform slide({Transform::translate({0, 0, 0}), Transform::translate({1, 0, 0})});
  RenderScene scene = buildRenderScene(d);
  scene.setCamera(Camera::perspective(slide, d.cameras[0].yfov, 12, 8, 0, kInfinity), "slide");
  ASSERT_TRUE(scene.camera().isMoving());

  // Without the feature: time 0, the camera at its first key.
  scene.setFeature(Feature::MotionBlur, false);
  Probe still = probe(scene, d);
  for (const Ray& r : still.rays) {
    ASSERT_EQ(r.time, 0.0f);
    ASSERT_EQ(r.o.x, 0.0f);
  }

  scene.setFeature(Feature::MotionBlur);
  Probe moving = probe(scene, d);
  ASSERT_EQ(moving.rays.size(), size_t(12 * 8 * spp));
  // The integrator's samples do not move when time is drawn.
  EXPECT_EQ(moving.samples, still.samples);
  for (size_t first = 0; first < moving.rays.size(); first += spp) {
    std::vector<int> strata(spp, 0);
    for (size_t i = first; i < first + spp; ++i) {
      const Ray& r = moving.rays[i];
      ASSERT_GE(r.time, 0.0f);
      ASSERT_LE(r.time, 1.0f);
      // The camera slides from x = 0 to x = 1 over the shutter.
      ASSERT_NEAR(r.o.x, r.time, 1e-6f);
      strata[std::min(int(r.time * spp), spp - 1)]++;
    }
    // One sample per 1/spp of the shutter in every pixel.
    for (int s = 0; s < spp; ++s) ASSERT_EQ(strata[s], 1) << "pixel " << first / spp;
  }
}

TEST(MotionBlur, LensAndMotionImagesAreIdenticalForAnyThreadsAndTiles) {
  SceneDescription d = edgeScene(6, 40, 24, 8);
  d.render.aovs = true;
  RenderScene scene = buildRenderScene(d);
  AnimatedTransform turn({Transform::rotate(-5, {0, 1, 0}), Transform::rotate(5, {0, 1, 0})});
  Camera turning = Camera::perspective(turn, d.cameras[0].yfov, 40, 24, 0, kInfinity);
  turning.setLens({0.4f, 3, 7, 0.1f});
  scene.setCamera(turning, "turning");
  ASSERT_TRUE(scene.features().has(Feature::Lens));
  ASSERT_TRUE(scene.features().has(Feature::MotionBlur));
  Film a = renderScene(scene, d, 1, 16), b = renderScene(scene, d, 2, 5);
  for (size_t i = 0; i < a.color.size(); ++i) {
    ASSERT_EQ(a.color[i], b.color[i]) << "pixel " << i;
    ASSERT_EQ(a.variance[i], b.variance[i]) << "pixel " << i;
    ASSERT_EQ(a.depth[i], b.depth[i]) << "pixel " << i;
  }
  // The motion and the lens did blur: the columns beside the edge are neither black nor white.
  float beside = a.color[a.index(19, 12)].y;
  EXPECT_GT(beside, 0.05f);
  EXPECT_LT(beside, 0.95f);
}

}  // namespace
}  // namespace glint
