// glint tests — VDB media: files written here with libopenvdb (no binaries in the tree), read
// through the sidecar, checked against closed forms and the existing media: a sphere of fog
// against exp(-sigma_t chord) per pixel, a constant box against the homogeneous medium, the
// majorant grid against the single majorant (same image, fewer collisions), temperature and
// flame grids against the emission integral, frame sequences, and every kind of bad input
// with its file and JSON pointer.
#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/ChangeBackground.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "image/output.h"
#include "image/statistical.h"
#include "materials/blackbody.h"
#include "materials/vdb_volume.h"
#include "media_scene.h"
#include "renderer/integrator.h"
#include "renderer/render.h"
#include "renderer/volume.h"
#include "scene_error_support.h"
#include "scenes/build.h"
#include "scenes/load.h"
#include "scenes/sidecar.h"
#include "scenes/vdb_file.h"
#include "test_support.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Writing VDB files
// ---------------------------------------------------------------------------------------------

// A float grid `name` of voxel size `voxel` (voxel (i, j, k) centred at (i, j, k) x voxel)
// holding f(i, j, k) over the index box [lo, hi]; voxels where f is 0 stay inactive unless
// `keepZeros`.
template <class F>
openvdb::FloatGrid::Ptr makeGrid(const std::string& name, float voxel, openvdb::Coord lo,
                                 openvdb::Coord hi, F f, bool keepZeros = false) {
  openvdb::initialize();
  openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
  g->setName(name);
  g->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
  auto acc = g->getAccessor();
  for (int k = lo.z(); k <= hi.z(); ++k)
    for (int j = lo.y(); j <= hi.y(); ++j)
      for (int i = lo.x(); i <= hi.x(); ++i) {
        const float v = f(i, j, k);
        if (v != 0 || keepZeros) acc.setValueOn(openvdb::Coord(i, j, k), v);
      }
  return g;
}

void writeVdb(const std::string& path, const openvdb::GridPtrVec& grids) {
  openvdb::initialize();
  openvdb::io::File file(path);
  file.write(grids);
  file.close();
}

// A constant cube of n^3 voxels, indices [0, n-1].
openvdb::FloatGrid::Ptr cube(const std::string& name, float voxel, int n, float value) {
  return makeGrid(name, voxel, {0, 0, 0}, {n - 1, n - 1, n - 1},
                  [&](int, int, int) { return value; });
}

// ---------------------------------------------------------------------------------------------
// Scenes
// ---------------------------------------------------------------------------------------------

// The media tests' scene (tests/media_scene.h) seeing [-half, half]^2, with the media of
// `mediaJson` (the sidecar's "media" array), read as if from `file`.
SceneDescription mediaScene(const std::string& file, const std::string& mediaJson, int size,
                            int spp, float half, const std::string& integrator = "path") {
  SceneDescription d = test::orthographicMediaScene(size, spp, half, integrator, 16);
  d.file = file;
  applySceneJsonText("{\"media\": " + mediaJson + "}", file, SceneJsonKind::Sidecar, &d);
  return d;
}

Film renderScene(const RenderScene& scene, const RenderSettings& settings) {
  auto integrator = makeIntegrator(scene, settings);
  RenderOptions options;
  options.threads = 2;
  RenderStats stats;
  Film film = render(scene, *integrator, settings, options, &stats);
  EXPECT_EQ(stats.nonfiniteSamples, 0u);
  return film;
}

// World position of pixel centre (x, y) on the plane z = 0 for a camera seeing [-half, half]^2.
Vec2f pixelCentre(const Film& film, int x, int y, float half) {
  return {-half + 2 * half * (float(x) + 0.5f) / float(film.width),
          half - 2 * half * (float(y) + 0.5f) / float(film.height)};
}

// ---------------------------------------------------------------------------------------------
// Reading
// ---------------------------------------------------------------------------------------------

// Every cell of `cells` bounds `value` inside it (up to a relative `slack`), at 20,000 random
// points of `box`.
template <class F>
void expectCellsBound(const MajorantGrid& cells, const Bounds3f& box, uint32_t seed, float slack,
                      F value) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 1);
  const Bounds3f& g = cells.bounds();
  for (int n = 0; n < 20000; ++n) {
    const Vec3f p = box.lower + box.diagonal() * Vec3f{u(rng), u(rng), u(rng)};
    int c[3];
    for (int a = 0; a < 3; ++a)
      c[a] = std::min(cells.res(a) - 1,
                      int((p[a] - g.lower[a]) / g.diagonal()[a] * float(cells.res(a))));
    ASSERT_GE(cells.at(c[0], c[1], c[2]) * (1 + slack), value(p))
        << p.x << " " << p.y << " " << p.z;
  }
}

TEST(VdbFile, ReadsGridsBoundsAndListsThem) {
  const std::string dir = test::scratchDir("VdbFile.ReadsGridsBoundsAndListsThem");
  const float voxel = 0.25f;
  auto density = makeGrid("density", voxel, {2, 3, 4}, {5, 6, 7},
                          [](int i, int, int) { return 0.5f * float(i); });
  auto temperature = cube("temperature", voxel, 4, 1500);
  writeVdb(dir + "/smoke.vdb", {density, temperature});

  const std::vector<VdbGridInfo> grids = listVdbGrids(dir + "/smoke.vdb");
  ASSERT_EQ(grids.size(), 2u);
  EXPECT_EQ(grids[0].name, "density");
  EXPECT_EQ(grids[0].type, "float");
  EXPECT_EQ(grids[0].voxelSize, (Vec3f{voxel, voxel, voxel}));
  EXPECT_EQ(grids[0].activeVoxels, 4u * 4u * 4u);
  // Voxel (i, j, k) spans (i -+ 0.5) x voxel.
  EXPECT_NEAR(grids[0].worldBounds.lower.x, 1.5f * voxel, 1e-6f);
  EXPECT_NEAR(grids[0].worldBounds.upper.z, 7.5f * voxel, 1e-6f);
  EXPECT_GT(grids[0].memoryBytes, 0u);
  EXPECT_EQ(grids[1].name, "temperature");

  VdbRequest request;
  request.where = {"scene.json", "/media/0/density/file"};
  request.density = {"density", {"scene.json", "/media/0/density/grid"}};
  request.temperature = VdbGridRequest{"temperature", {"scene.json", "/x"}};
  const std::shared_ptr<VdbVolume> v = readVdbFile(dir + "/smoke.vdb", request);
  EXPECT_EQ(v->maxDensity, 2.5f);
  // The box where lookups can be non-zero: one voxel beyond the outermost active centres, of
  // both grids.
  EXPECT_NEAR(v->bounds.lower.x, -1 * voxel, 1e-6f);
  EXPECT_NEAR(v->bounds.upper.x, 6 * voxel, 1e-6f);
  EXPECT_NEAR(v->bounds.upper.z, 8 * voxel, 1e-6f);
  EXPECT_NEAR(v->density.sample(Vec3f{3, 4, 5} * voxel), 1.5f, 1e-6f);
  EXPECT_NEAR(v->density.sample(Vec3f{3.5f, 4, 5} * voxel), 1.75f, 1e-6f);  // trilinear
  EXPECT_EQ(v->density.sample(Vec3f{20, 20, 20}), 0.0f);
  ASSERT_TRUE(v->temperature);
  EXPECT_NEAR(v->temperature->sample(Vec3f{1, 1, 1} * voxel), 1500.0f, 1e-3f);
  // Every cell of the majorant grid bounds the density inside it.
  ASSERT_TRUE(v->majorants);
  const MajorantGrid& m = *v->majorants;
  EXPECT_EQ(m.maxValue(), 2.5f);
  expectCellsBound(m, v->bounds, 3, 0, [&](Vec3f p) { return v->density.sample(p); });
  EXPECT_GT(m.emptyFraction(), 0.0f);
}

// The temperature grid becomes kelvin voxel by voxel (scale x value + offset, 0 K at or below
// the cutoff) before it is interpolated, as Blender maps its fluid domains' flame grid: half a
// voxel beyond a flame's last voxel the temperature is half that voxel's (the interpolation of
// kelvin), not the map of half its value. Without a cutoff the offset holds everywhere, the
// background too (an ambient temperature); the emission bound follows the kelvin.
TEST(VdbFile, TemperatureMapsVoxelsToKelvinBeforeInterpolating) {
  const std::string dir = test::scratchDir("VdbFile.TemperatureMapsVoxelsToKelvin");
  const float voxel = 0.25f;
  writeVdb(dir + "/fire.vdb", {cube("density", voxel, 4, 1), cube("flame", voxel, 4, 2)});
  struct Case {
    VdbTemperatureMap map;
    float inside, halfVoxelOut, far;
  };
  const Case cases[] = {
      // Blender's defaults (ignition 1.5, max 3, Temperature 1000), flame > 0.01 burning.
      {{1500, 1500, 1515}, 4500, 2250, 0},
      {{2, 100, 0}, 104, 102, 100},  // offset everywhere
      {{1, 0, 0}, 2, 1, 0},          // the grid as it is
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.map.offset);
    VdbRequest request;
    request.where = {"scene.json", "/media/0/density/file"};
    request.density = {"density", {"scene.json", "/media/0/density/grid"}};
    request.temperature = VdbGridRequest{"flame", {"scene.json", "/x"}};
    request.kelvin = c.map;
    const std::shared_ptr<VdbVolume> v = readVdbFile(dir + "/fire.vdb", request);
    ASSERT_TRUE(v->temperature);
    EXPECT_NEAR(v->temperature->sample(Vec3f{1, 2, 1} * voxel), c.inside, 1e-3f * c.inside);
    EXPECT_NEAR(v->temperature->sample(Vec3f{3.5f, 2, 1} * voxel), c.halfVoxelOut,
                1e-3f * c.inside);
    EXPECT_EQ(v->temperature->sample(Vec3f{20, 20, 20}), c.far);
    ASSERT_TRUE(v->temperatureMaxima);
    EXPECT_NEAR(v->temperatureMaxima->maxValue(), c.inside, 1e-3f * c.inside);
  }
  // A signed grid (a simulation's heat, below its ambient here) is a temperature through the
  // map; kelvin at or below the cutoff, or below 0, are 0 K. A NaN is still refused.
  writeVdb(dir + "/heat.vdb",
           {cube("density", voxel, 4, 1), makeGrid("heat", voxel, {0, 0, 0}, {3, 3, 3},
                                                   [](int i, int, int) { return i - 2.0f; })});
  VdbRequest request;
  request.where = {"scene.json", "/media/0/density/file"};
  request.density = {"density", {"scene.json", "/media/0/density/grid"}};
  request.temperature = VdbGridRequest{"heat", {"scene.json", "/x"}};
  request.kelvin = {1000, 1500, 600};
  const std::shared_ptr<VdbVolume> v = readVdbFile(dir + "/heat.vdb", request);
  EXPECT_NEAR(v->temperature->sample(Vec3f{0, 1, 1} * voxel), 0.0f, 1e-3f);     // -500 K
  EXPECT_NEAR(v->temperature->sample(Vec3f{1, 1, 1} * voxel), 0.0f, 1e-3f);     // 500 K
  EXPECT_NEAR(v->temperature->sample(Vec3f{2, 1, 1} * voxel), 1500.0f, 1e-3f);  // 0: ambient
  EXPECT_NEAR(v->temperature->sample(Vec3f{3, 1, 1} * voxel), 2500.0f, 1e-3f);
  writeVdb(dir + "/nan_heat.vdb",
           {cube("density", voxel, 4, 1),
            makeGrid("heat", voxel, {0, 0, 0}, {3, 3, 3},
                     [](int i, int, int) { return i == 1 ? std::nanf("") : -1.0f; })});
  const std::string error =
      test::errorFrom([&] { readVdbFile(dir + "/nan_heat.vdb", request); }).message();
  EXPECT_NE(error.find("grid 'heat' has at voxel [1, 0, 0] the value nan (values must be "
                       "finite)"),
            std::string::npos)
      << error;
}

// The majorant grid is built a leaf at a time where the file's transform is axis-aligned; it
// must be cell for cell what raising every active voxel's and tile's trilinear reach (its index
// box -+ 1, in world space as the reader computes it) to its value gives. A sparse grid of
// random voxels over several leaves, a tile, a scale that differs per axis and an offset; and
// a rotated transform (each voxel on its own) still bounding the density.
TEST(VdbFile, MajorantGridIsEveryVoxelsReach) {
  const std::string dir = test::scratchDir("VdbFile.MajorantGridIsEveryVoxelsReach");
  openvdb::initialize();
  for (bool rotated : {false, true}) {
    SCOPED_TRACE(rotated);
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
    g->setName("density");
    openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
    m.preScale(openvdb::Vec3d(0.25, 0.5, 0.125));
    if (rotated) m.postRotate(openvdb::math::Z_AXIS, 0.3);
    m.postTranslate(openvdb::Vec3d(0.3, -1.7, 2.1));
    g->setTransform(openvdb::math::Transform::createLinearTransform(m));
    std::mt19937 rng(11);
    std::uniform_int_distribution<int> coord(-20, 40);
    std::uniform_real_distribution<float> value(0.1f, 3.0f);
    auto acc = g->getAccessor();
    for (int i = 0; i < 3000; ++i)
      acc.setValueOn(openvdb::Coord(coord(rng), coord(rng), coord(rng)), value(rng));
    g->tree().addTile(1, openvdb::Coord(64, 0, 0), 4.0f, true);  // a 16^3 tile of 4
    writeVdb(dir + "/sparse.vdb", {g});

    VdbRequest request;
    request.where = {"scene.json", "/media/0/density/file"};
    request.density = {"density", {"scene.json", "/media/0/density/grid"}};
    const std::shared_ptr<VdbVolume> v = readVdbFile(dir + "/sparse.vdb", request);
    ASSERT_TRUE(v->majorants);
    const MajorantGrid& got = *v->majorants;
    EXPECT_EQ(got.maxValue(), 4.0f);
    expectCellsBound(got, v->bounds, 4, 0, [&](Vec3f p) { return v->density.sample(p); });
    if (rotated) continue;
    // The reference: the reader's float affine map, one include per active value.
    const openvdb::Vec3d o = g->transform().indexToWorld(openvdb::Vec3d(0, 0, 0));
    const Vec3f origin{float(o.x()), float(o.y()), float(o.z())};
    Vec3f axis[3];
    for (int a = 0; a < 3; ++a) {
      openvdb::Vec3d e(0, 0, 0);
      e[a] = 1;
      const openvdb::Vec3d w = g->transform().indexToWorld(e) - o;
      axis[a] = {float(w.x()), float(w.y()), float(w.z())};
    }
    MajorantGrid want(got.bounds(), got.res(0), got.res(1), got.res(2));
    openvdb::CoordBBox box;
    for (auto it = g->cbeginValueOn(); it; ++it) {
      it.getBoundingBox(box);
      const Vec3f lo =
          Vec3f{float(box.min().x()), float(box.min().y()), float(box.min().z())} - Vec3f{1, 1, 1};
      const Vec3f hi =
          Vec3f{float(box.max().x()), float(box.max().y()), float(box.max().z())} + Vec3f{1, 1, 1};
      const Vec3f c = (lo + hi) * 0.5f, h = (hi - lo) * 0.5f;
      const Vec3f centre = origin + axis[0] * c.x + axis[1] * c.y + axis[2] * c.z;
      Vec3f half;
      for (int a = 0; a < 3; ++a)
        half[a] =
            std::abs(axis[0][a]) * h.x + std::abs(axis[1][a]) * h.y + std::abs(axis[2][a]) * h.z;
      want.include({centre - half, centre + half}, *it);
    }
    int differ = 0;
    for (int z = 0; z < got.res(2); ++z)
      for (int y = 0; y < got.res(1); ++y)
        for (int x = 0; x < got.res(0); ++x) differ += got.at(x, y, z) != want.at(x, y, z);
    EXPECT_EQ(differ, 0);
    EXPECT_GT(got.emptyFraction(), 0.0f);
  }
}

// A file shaped as Blender's fluid caches are (scenes/README, "Blender's fluid caches"): 16-bit
// floats, Blosc, grids counted from the domain's corner, a `shadow` grid of -1 and a vec3
// `velocity` beside the float grids, read with the sidecar entry the README gives: the grid
// stretched over the domain box with Blender's axes turned, and the flame grid as Blender's
// temperature (ignition 1.5, maximum 3: 1,500 K + flame x 1,500 K above a flame of 0.01).
TEST(VdbFile, ReadsABlenderFluidCacheWithTheReadmesEntry) {
  const std::string dir = test::scratchDir("VdbFile.ReadsABlenderFluidCache");
  openvdb::initialize();
  const float v = 0.0625f;  // a 2.1 x 1.9 x 3 domain at resolution 48: 34 x 30 x 48 voxels
  auto grid = [&](const std::string& name, auto f) {
    openvdb::FloatGrid::Ptr g = makeGrid(name, v, {0, 0, 0}, {33, 29, 47}, f);
    g->setSaveFloatAsHalf(true);
    return g;
  };
  auto density = grid("density", [](int i, int j, int k) {
    return i >= 10 && i <= 20 && j >= 8 && j <= 18 && k <= 30 ? 0.5f : 0.0f;
  });
  auto flame = grid("flame", [](int i, int j, int k) {
    return i == 15 && j == 12 && k == 4 ? 0.5f : i == 16 && j == 12 && k == 4 ? 0.005f : 0.0f;
  });
  auto heat = grid("temperature", [](int i, int, int) { return i == 15 ? 2.0f : 0.0f; });
  auto shadow = grid("shadow", [](int, int, int) { return -1.0f; });
  openvdb::Vec3SGrid::Ptr velocity = openvdb::Vec3SGrid::create();
  velocity->setName("velocity");
  velocity->setTransform(openvdb::math::Transform::createLinearTransform(v));
  velocity->getAccessor().setValueOn({15, 12, 4}, openvdb::Vec3s(0, 0, 1));
  {
    openvdb::io::File file(dir + "/fluid_data_0030.vdb");
    file.setCompression(openvdb::io::COMPRESS_BLOSC);
    file.write({density, flame, heat, shadow, velocity});
    file.close();
  }
  // The domain: lowest corner (-0.75, -1.15, 0), sides 2.1 x 1.9 x 3 (Blender's axes).
  const float sx = 2.1f / (34 * v), sy = 1.9f / (30 * v), sz = 3.0f / (48 * v);
  SceneDescription d;
  d.file = dir + "/scene.json";
  applySceneJsonText(R"({"media": [{"sigma_a": 2, "sigma_s": 6, "transform": [
      {"translate": [0.03125, 0.03125, 0.03125]},
      {"scale": [)" + std::to_string(sx) +
                         ", " + std::to_string(sy) + ", " + std::to_string(sz) + R"(]},
      {"translate": [-0.75, -1.15, 0]}, {"rotate": {"axis": [1, 0, 0], "degrees": -90}}],
    "density": {"type": "vdb", "file": "fluid_data_####.vdb", "frame_offset": 30,
      "temperature_grid": "flame", "temperature_scale": 1500, "temperature_offset": 1500,
      "temperature_cutoff": 1515}}]})",
                     d.file, SceneJsonKind::Sidecar, &d);
  ASSERT_EQ(d.media.size(), 1u);
  const MediumDesc& m = d.media[0];
  const VdbVolume& vol = *m.vdb;
  // The flame voxel's temperature (0.5 is exact in 16 bits), none below the cutoff, none
  // outside the flame.
  EXPECT_NEAR(vol.temperature->sample(Vec3f{15, 12, 4} * v), 2250.0f, 0.5f);
  EXPECT_EQ(vol.temperature->sample(Vec3f{17, 12, 4} * v), 0.0f);
  EXPECT_EQ(vol.temperature->sample(Vec3f{5, 5, 20} * v), 0.0f);
  EXPECT_NEAR(vol.density.sample(Vec3f{12, 10, 20} * v), 0.5f, 1e-6f);
  // Voxel (i, j, k) spans [i - 0.5, i + 0.5] x v in the file; the entry puts voxel 0's lower
  // corner at the domain's lowest corner and voxel (33, 29, 47)'s upper one at its highest,
  // in glint's axes: Blender's (x, y, z) is glint's (x, z, -y).
  const Vec3f lo = m.worldFromRegion.point(Vec3f{-0.5f, -0.5f, -0.5f} * v);
  const Vec3f hi = m.worldFromRegion.point(Vec3f{33.5f, 29.5f, 47.5f} * v);
  EXPECT_NEAR(lo.x, -0.75f, 1e-5f);
  EXPECT_NEAR(lo.y, 0.0f, 1e-5f);
  EXPECT_NEAR(lo.z, 1.15f, 1e-5f);
  EXPECT_NEAR(hi.x, 1.35f, 1e-5f);
  EXPECT_NEAR(hi.y, 3.0f, 1e-5f);
  EXPECT_NEAR(hi.z, -0.75f, 1e-5f);
}

// Blender's coloured smoke: its cache keeps the colour as three float grids (color_r,
// color_g, color_b; a channel the flow never emits is an empty grid), each holding colour x
// density, which Blender renders as it stands. glint joins the three into one colour grid.
TEST(VdbFile, ReadsThreeFloatGridsAsTheColour) {
  const std::string dir = test::scratchDir("VdbFile.ReadsThreeFloatGridsAsTheColour");
  const float v = 0.0625f;
  // Two voxels along x: density 0.5 of colour (1, 0.25, 0), density 0.25 of (0.5, 0.5, 0).
  const float d[2] = {0.5f, 0.25f};
  const Rgb c[2] = {{1, 0.25f, 0}, {0.5f, 0.5f, 0}};
  auto voxels = [&](const std::string& name, auto f) {
    openvdb::FloatGrid::Ptr g =
        makeGrid(name, v, {4, 4, 4}, {5, 4, 4}, [&](int i, int, int) { return f(i - 4); });
    g->setSaveFloatAsHalf(true);
    return g;
  };
  auto density = voxels("density", [&](int i) { return d[i]; });
  auto red = voxels("color_r", [&](int i) { return c[i].x * d[i]; });
  auto green = voxels("color_g", [&](int i) { return c[i].y * d[i]; });
  auto blue = voxels("color_b", [&](int) { return 0.0f; });  // no active voxels
  writeVdb(dir + "/smoke.vdb", {density, red, green, blue});
  SceneDescription s;
  applySceneJsonText(R"({"media": [{"sigma_s": 1, "density": {"type": "vdb",
      "file": "smoke.vdb", "color_grid": ["color_r", "color_g", "color_b"],
      "color_mode": "albedo"}}]})",
                     dir + "/scene.json", SceneJsonKind::Sidecar, &s);
  ASSERT_EQ(s.media.size(), 1u);
  EXPECT_TRUE(s.media[0].colorTintsAlbedo);
  const auto volume = s.media[0].vdb;
  ASSERT_TRUE(volume->color);
  const VdbColor color(volume, 1.0f);
  // Each voxel's three values (exact in 16 bits), and halfway their mean.
  for (int i = 0; i < 2; ++i) {
    const Rgb at = color.color(Vec3f{float(4 + i), 4, 4} * v, 1.0f);
    EXPECT_EQ(at.x, c[i].x * d[i]);
    EXPECT_EQ(at.y, c[i].y * d[i]);
    EXPECT_EQ(at.z, 0.0f);
  }
  const Rgb half = color.color(Vec3f{4.5f, 4, 4} * v, 1.0f);
  EXPECT_NEAR(half.x, 0.5f * (c[0].x * d[0] + c[1].x * d[1]), 1e-6f);
  EXPECT_NEAR(half.y, 0.5f * (c[0].y * d[0] + c[1].y * d[1]), 1e-6f);
  // Outside the voxels, the background (0); the bound is the largest value per channel.
  EXPECT_EQ(color.color(Vec3f{9, 9, 9} * v, 1.0f).x, 0.0f);
  EXPECT_EQ(volume->maxColor.x, 0.5f);
  EXPECT_EQ(volume->maxColor.y, 0.125f);
  EXPECT_EQ(volume->maxColor.z, 0.0f);
  // Weighted by the density, as Blender interpolates a domain's colour: the same at the voxels,
  // and halfway the density-weighted mean.
  SceneDescription w;
  applySceneJsonText(R"({"media": [{"sigma_s": 1, "density": {"type": "vdb",
      "file": "smoke.vdb", "color_grid": ["color_r", "color_g", "color_b"],
      "color_density_weighted": true}}]})",
                     dir + "/scene.json", SceneJsonKind::Sidecar, &w);
  // color() is given the medium's density there (the grid's, times the density's scale).
  const VdbColor weighted(w.media[0].vdb, 1.0f), weightedScaled(w.media[0].vdb, 2.5f);
  const auto weightedAt = [&](Vec3f p) {
    const float rho = w.media[0].vdb->density.sample(p);
    const Rgb a = weighted.color(p, rho), b = weightedScaled.color(p, 2.5f * rho);
    EXPECT_NEAR(a.x, b.x, 1e-6f);
    EXPECT_NEAR(a.y, b.y, 1e-6f);
    return a;
  };
  for (int i = 0; i < 2; ++i)
    EXPECT_NEAR(weightedAt(Vec3f{float(4 + i), 4, 4} * v).x, c[i].x * d[i], 1e-6f);
  const Rgb mean = weightedAt(Vec3f{4.5f, 4, 4} * v);
  const float w0 = d[0] / (d[0] + d[1]), w1 = d[1] / (d[0] + d[1]);     // 2/3, 1/3
  EXPECT_NEAR(mean.x, w0 * c[0].x * d[0] + w1 * c[1].x * d[1], 1e-6f);  // 0.375, not 0.3125
  EXPECT_NEAR(mean.y, w0 * c[0].y * d[0] + w1 * c[1].y * d[1], 1e-6f);
  EXPECT_EQ(w.media[0].vdb->maxColor.x, 0.5f);
  // A channel stored as an active tile (an 8^3 block of one value, no voxels) is joined over
  // the whole tile.
  openvdb::FloatGrid::Ptr tile = openvdb::FloatGrid::create(0.0f);
  tile->setName("tile_r");
  tile->setTransform(openvdb::math::Transform::createLinearTransform(v));
  tile->fill(openvdb::CoordBBox({16, 16, 16}, {23, 23, 23}), 0.5f, true);
  ASSERT_EQ(tile->tree().leafCount(), 0u);  // a tile indeed
  auto none = makeGrid("none", v, {0, 0, 0}, {0, 0, 0}, [](int, int, int) { return 0.0f; });
  writeVdb(dir + "/tile.vdb", {cube("density", v, 24, 1), tile, none});
  SceneDescription t;
  applySceneJsonText(R"({"media": [{"sigma_s": 1, "density": {"type": "vdb",
      "file": "tile.vdb", "color_grid": ["tile_r", "none", "none"]}}]})",
                     dir + "/scene.json", SceneJsonKind::Sidecar, &t);
  const Rgb inTile = VdbColor(t.media[0].vdb, 1.0f).color(Vec3f{20, 21, 19} * v, 1.0f);
  EXPECT_EQ(inTile.x, 0.5f);
  EXPECT_EQ(inTile.y, 0.0f);
}

// Bad files and bad names: the error is at the sidecar's key, names the file, says what is
// wrong; for a missing grid it lists the grids the file has.
TEST(VdbFile, BadInputNamesTheFileAndThePointer) {
  const std::string dir = test::scratchDir("VdbFile.BadInputNamesTheFileAndThePointer");
  const std::string file = dir + "/scene.json";
  auto error = [&](const std::string& density) {
    return test::errorFrom([&] {
      SceneDescription d;
      applySceneJsonText("{\"media\": [{\"density\": " + density + "}]}", file,
                         SceneJsonKind::Sidecar, &d);
    });
  };
  writeVdb(dir + "/good.vdb", {cube("density", 0.1f, 4, 1), cube("temperature", 0.1f, 4, 1000)});
  openvdb::Vec3SGrid::Ptr vec = openvdb::Vec3SGrid::create();
  vec->setName("velocity");
  vec->getAccessor().setValueOn({0, 0, 0}, openvdb::Vec3s(1, 2, 3));
  writeVdb(dir + "/vec.vdb", {cube("density", 0.1f, 4, 1), vec});
  writeVdb(dir + "/negative.vdb",
           {makeGrid("density", 0.1f, {0, 0, 0}, {3, 3, 3},
                     [](int i, int, int) { return i == 2 ? -1.0f : 1.0f; })});
  writeVdb(dir + "/nan.vdb", {makeGrid("density", 0.1f, {0, 0, 0}, {3, 3, 3}, [](int i, int, int) {
             return i == 1 ? std::nanf("") : 1.0f;
           })});
  {
    openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
    g->setName("density");
    writeVdb(dir + "/empty.vdb", {g});
  }
  std::ofstream(dir + "/text.vdb") << "this is not a VDB file\n";
  {
    const std::string bytes = test::slurp(dir + "/good.vdb");
    std::ofstream(dir + "/truncated.vdb", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  const std::string p = "/media/0/density";
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "text.vdb"})"), file, p + "/file",
                     "text.vdb: not a readable VDB file");
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "truncated.vdb"})"), file, p + "/file",
                     "truncated.vdb: not a readable VDB file");
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "missing.vdb"})"), file, p + "/file",
                     "file not found");
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "good.vdb", "grid": "dens"})"), file,
                     p + "/grid",
                     "good.vdb has no grid 'dens' (its grids: density (float), temperature "
                     "(float))");
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "vec.vdb", "temperature_grid": "velocity"})"),
                     file, p + "/temperature_grid",
                     "vec.vdb: grid 'velocity' holds vec3s values, not float");
  // The colour grid must be vec3 (and a vec3 is still refused where a float is expected).
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "good.vdb", "color_grid": "temperature"})"),
                     file, p + "/color_grid",
                     "good.vdb: grid 'temperature' holds float values, not vec3s");
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "vec.vdb", "grid": "velocity"})"), file,
                     p + "/grid", "vec.vdb: grid 'velocity' holds vec3s values, not float");
  // Three float grids, or one vec3s: not two, and each float; premultiplied needs a colour.
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "good.vdb",
                               "color_grid": ["temperature", "temperature"]})"),
                     file, p + "/color_grid", "three float grids' (red, green, blue)");
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "vec.vdb",
                               "color_grid": ["density", "velocity", "density"]})"),
                     file, p + "/color_grid/1",
                     "vec.vdb: grid 'velocity' holds vec3s values, not float");
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "good.vdb", "color_mode": "albedo"})"), file,
                     p + "/color_mode", "needs a color_grid");
  EXPECT_SCENE_ERROR(
      error(R"({"type": "vdb", "file": "good.vdb", "color_density_weighted": true})"), file,
      p + "/color_density_weighted", "needs a color_grid");
  // Weighing the colour by the density needs the two on one transform.
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "vec.vdb", "color_grid": "velocity",
                               "color_density_weighted": true})"),
                     file, p + "/color_grid",
                     "vec.vdb: grid 'velocity' has another transform than the density grid");
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "good.vdb", "color_mode": "tint"})"), file,
                     p + "/color_mode", "scattering");
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "negative.vdb"})"), file, p + "/grid",
                     "negative.vdb: grid 'density' has at voxel [2, 0, 0] the value -1");
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "nan.vdb"})"), file, p + "/grid",
                     "nan.vdb: grid 'density' has at voxel [1, 0, 0] the value nan");
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "empty.vdb"})"), file, p + "/grid",
                     "empty.vdb: grid 'density' is empty (no active voxels)");
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "good.vdb", "scale": -1})"), file,
                     p + "/scale", "must be >= 0");
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "good.vdb", "temperature_grid":
                               "temperature", "temperature_cutoff": -1})"),
                     file, p + "/temperature_cutoff", "must be >= 0");
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "good.vdb", "temperature_grid":
                               "temperature", "temperature_scale": -2})"),
                     file, p + "/temperature_scale", "must be >= 0");
  EXPECT_SCENE_ERROR(error(R"({"type": "vdb", "file": "good.vdb", "gird": "density"})"), file,
                     p + "/gird", "unknown key 'gird'");
  // A VDB medium is placed by its transform, not a region.
  EXPECT_SCENE_ERROR(test::errorFrom([&] {
                       SceneDescription d;
                       applySceneJsonText(
                           R"({"media": [{"region": {"type": "sphere", "radius": 1},
                                "density": {"type": "vdb", "file": "good.vdb"}}]})",
                           file, SceneJsonKind::Sidecar, &d);
                     }),
                     file, "/media/0/region", "a vdb medium fills the box");
}

// The command line: exit 2, one line naming the sidecar, the pointer and the VDB file, and the
// output that was there before is left alone.
TEST(VdbFile, CommandLineExitsTwoAndKeepsTheOutput) {
  const std::string dir = test::scratchDir("VdbFile.CommandLineExitsTwoAndKeepsTheOutput");
  writeVdb(dir + "/cloud.vdb", {cube("density", 0.1f, 4, 1)});
  std::ofstream(dir + "/scene.json") << R"({
    "cameras": [{"name": "c", "position": [0, 0, 3], "look_at": [0, 0, 0]}],
    "render": {"width": 8, "height": 8, "spp": 1},
    "media": [{"sigma_s": 1, "density": {"type": "vdb", "file": "cloud.vdb", "grid": "smoke"}}]
  })";
  std::ofstream(dir + "/out.exr") << "previous good image";
  const test::CommandResult r =
      test::runGlint("render '" + dir + "/scene.json' -o '" + dir + "/out.exr'");
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("scene.json: /media/0/density/grid: cloud.vdb has no grid 'smoke' (its "
                       "grids: density (float))"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(test::slurp(dir + "/out.exr"), "previous good image");

  // glint info lists the file's grids.
  std::ofstream(dir + "/ok.json") << R"({
    "cameras": [{"name": "c", "position": [0, 0, 3], "look_at": [0, 0, 0]}],
    "media": [{"sigma_s": 1, "density": {"type": "vdb", "file": "cloud.vdb"}}]
  })";
  const test::CommandResult info = test::runGlint("info '" + dir + "/ok.json'");
  EXPECT_EQ(info.exitCode, 0) << info.err;
  EXPECT_NE(info.out.find("grid 'density': float, voxel 0.1 x 0.1 x 0.1, 64 active voxels"),
            std::string::npos)
      << info.out;
}

// OpenVDB lives in a plugin (scenes/openvdb/plugin.h): a scene without a .vdb medium never
// loads it (nor libopenvdb: the dynamic loader's LD_DEBUG=files log names every file it
// opens), and a missing plugin fails a VDB scene clearly (exit code 1: not the scene's fault)
// without touching the output.
TEST(VdbFile, OnlyVdbScenesLoadTheOpenVdbPlugin) {
  const std::string dir = test::scratchDir("VdbFile.OnlyVdbScenesLoadTheOpenVdbPlugin");
  std::ofstream(dir + "/ball.json") << test::litBallJson(16, 12);
  {
    test::ScopedEnv debug("LD_DEBUG", "files");
    const test::CommandResult r =
        test::runGlint("render '" + dir + "/ball.json' -q --spp 1 -o '" + dir + "/ball.exr'");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("file="), std::string::npos) << "no loader log: " << r.err;
    EXPECT_EQ(r.err.find("openvdb"), std::string::npos) << r.err;
  }
  writeVdb(dir + "/cloud.vdb", {cube("density", 0.1f, 4, 1)});
  std::ofstream(dir + "/scene.json") << R"({
    "cameras": [{"name": "c", "position": [0, 0, 3], "look_at": [0, 0, 0]}],
    "render": {"width": 8, "height": 8, "spp": 1},
    "media": [{"sigma_s": 1, "density": {"type": "vdb", "file": "cloud.vdb"}}]
  })";
  {
    test::ScopedEnv debug("LD_DEBUG", "files");
    const test::CommandResult r =
        test::runGlint("render '" + dir + "/scene.json' -q -o '" + dir + "/out.exr'");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("libglint_openvdb.so"), std::string::npos) << r.err;
  }
  std::ofstream(dir + "/out.exr") << "previous good image";
  test::ScopedEnv noPlugin("GLINT_OPENVDB_PLUGIN", (dir + "/missing/libglint_openvdb.so").c_str());
  const test::CommandResult r =
      test::runGlint("render '" + dir + "/scene.json' -q -o '" + dir + "/out.exr'");
  EXPECT_EQ(r.exitCode, 1) << r.err;
  EXPECT_NE(r.err.find("OpenVDB plugin"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("missing/libglint_openvdb.so: no such file"), std::string::npos) << r.err;
  EXPECT_EQ(test::slurp(dir + "/out.exr"), "previous good image");
}

// ---------------------------------------------------------------------------------------------
// Rendering against closed forms and the existing media
// ---------------------------------------------------------------------------------------------

// A sphere of fog (density 1 in the voxels whose centres lie within 24 voxels of the centre,
// radius 1) absorbing in front of an environment of radiance 1: each pixel sees
// exp(-sigma_a chord). The voxelised surface with its one-voxel trilinear ramp moves the
// chord's ends by up to half a voxel each: the tolerance allows one voxel of optical depth,
// and pixels within two voxels of the silhouette are left out. Delta tracking (path) and
// ratio tracking (Whitted's "track" estimator) both go through the majorant grid.
TEST(VdbRender, SphereFogTransmitsTheExponentialOfTheChord) {
  const std::string dir = test::scratchDir("VdbRender.SphereFogTransmitsTheExponential");
  const int r = 24;
  const float voxel = 1.0f / float(r);
  writeVdb(dir + "/ball.vdb",
           {makeGrid("density", voxel, {-r, -r, -r}, {r, r, r}, [&](int i, int j, int k) {
             return i * i + j * j + k * k <= r * r ? 1.0f : 0.0f;
           })});
  // Chromatic for ratio tracking; grey for delta tracking, whose channel-averaged null
  // collisions weigh the thinner channels by factors > 1 (unbiased, but heavy-tailed: a
  // per-pixel 4-sigma test at 64 spp fails on it).
  const Rgb chromatic{0.4f, 0.8f, 1.2f}, grey{0.8f, 0.8f, 0.8f};
  const float radius = (float(r) + 0.5f) * voxel;  // the ramp's middle on the axes
  for (const char* integrator : {"path", "whitted"}) {
    const Rgb sigmaA = std::string(integrator) == "path" ? grey : chromatic;
    SceneDescription d =
        mediaScene(dir + "/scene.json",
                   R"([{"sigma_a": [)" + std::to_string(sigmaA.x) + ", " +
                       std::to_string(sigmaA.y) + ", " + std::to_string(sigmaA.z) + R"(],
                                        "density": {"type": "vdb", "file": "ball.vdb"}}])",
                   24, 64, 1.2f, integrator);
    d.render.integrator.volumeEstimator = "track";
    RenderScene scene = buildRenderScene(d);
    test::useUniformEnvironment(&scene, {1, 1, 1});
    const Film film = renderScene(scene, d.render);
    int tested = 0;
    for (int y = 0; y < film.height; ++y)
      for (int x = 0; x < film.width; ++x) {
        const Vec2f p = pixelCentre(film, x, y, 1.2f);
        const float rho = std::sqrt(p.x * p.x + p.y * p.y);
        // The pixel's footprint (0.1 wide) spreads the chord: leave out the silhouette.
        if (std::abs(rho - radius) < 2 * voxel + 0.075f) continue;
        const float chord = rho < radius ? 2 * std::sqrt(radius * radius - rho * rho) : 0;
        const size_t i = film.index(x, y);
        for (int c = 0; c < 3; ++c) {
          const float exact = std::exp(-sigmaA[c] * chord);
          const float sigma = std::sqrt(film.variance[i][c]);
          const float slack = exact * (1 - std::exp(-sigmaA[c] * voxel));
          EXPECT_NEAR(film.color[i][c], exact, 4 * sigma + slack + 1e-6f)
              << integrator << " pixel " << x << "," << y << " channel " << c;
        }
        ++tested;
      }
    EXPECT_GT(tested, 300);
  }
}

// Writes `film` with its variance and runs the project's statistical comparison against
// `reference` (also a film): the verdict, and the result printed on failure.
StatisticalResult compareFilms(const std::string& dir, const Film& a, const Film& reference,
                               int spp) {
  ImageMetadata meta;
  meta.spp = spp;
  writeImage(dir + "/a.exr", a, RenderSettings{}, meta);
  writeImage(dir + "/ref.exr", reference, RenderSettings{}, meta);
  return diffStatistical(dir + "/a.exr", dir + "/ref.exr", {});
}

// compareFilms's verdict is a pass (its figures printed when it is not).
void expectSameImage(const std::string& dir, const Film& a, const Film& reference, int spp) {
  const StatisticalResult r = compareFilms(dir, a, reference, spp);
  EXPECT_EQ(r.verdict, DiffVerdict::Pass)
      << "pass " << r.passPercent << "% maxZ " << r.maxZ << " at " << r.maxZX << "," << r.maxZY
      << " globalZ " << r.globalZ[0] << " " << r.globalZ[1] << " " << r.globalZ[2];
}

// The scene of `d` rendered with `seed` under a uniform sky of radiance `sky`.
Film renderUnderSky(SceneDescription d, uint64_t seed, Rgb sky) {
  d.render.seed = seed;
  RenderScene scene = buildRenderScene(d);
  test::useUniformEnvironment(&scene, sky);
  return renderScene(scene, d.render);
}

// A VDB cube of constant density 1 placed by the sidecar's transform over [-1, 1]^3, against
// the homogeneous medium in the box [-1, 1]^3: the same scattering image (the statistical
// comparison of image/statistical.h). The VDB's faces are a one-voxel trilinear ramp where the
// box has a step; along the camera's axis-aligned rays the two integrate to the same optical
// depth, so only the pixels straddling the side faces differ: those are made equal before
// comparing.
TEST(VdbRender, ConstantBoxMatchesTheHomogeneousMedium) {
  const std::string dir = test::scratchDir("VdbRender.ConstantBoxMatchesTheHomogeneous");
  const int n = 16;
  const float voxel = 0.125f;
  writeVdb(dir + "/box.vdb", {cube("density", voxel, n, 1)});
  const std::string common = R"("sigma_a": [0.3, 0.2, 0.1], "sigma_s": [0.6, 0.9, 1.2], "g": 0.4)";
  const float c = -0.5f * float(n - 1) * voxel;  // voxel centres from c to -c: faces at -+1
  SceneDescription dv =
      mediaScene(dir + "/scene.json",
                 "[{" + common + R"(, "transform": [{"translate": [)" + std::to_string(c) + ", " +
                     std::to_string(c) + ", " + std::to_string(c) +
                     R"(]}], "density": {"type": "vdb", "file": "box.vdb"}}])",
                 24, 128, 1.5f);
  SceneDescription dh = mediaScene(
      dir + "/scene.json", "[{" + common + R"(, "region": {"type": "box", "min": [-1, -1, -1],
                                                 "max": [1, 1, 1]}}])",
      24, 128, 1.5f);
  dh.render.seed = 7;
  Film films[2];
  SceneDescription* descs[2] = {&dv, &dh};
  for (int k = 0; k < 2; ++k) {
    RenderScene scene = buildRenderScene(*descs[k]);
    test::useUniformEnvironment(&scene, {1, 1, 1});
    films[k] = renderScene(scene, descs[k]->render);
  }
  // Pixels whose footprint (0.125 wide) touches the ramp of the side faces: equal in both.
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x) {
      const Vec2f p = pixelCentre(films[0], x, y, 1.5f);
      const float edge = std::min(std::abs(std::abs(p.x) - 1), std::abs(std::abs(p.y) - 1));
      if (edge < voxel / 2 + 0.0625f) {
        const size_t i = films[0].index(x, y);
        films[0].color[i] = films[1].color[i];
      }
    }
  expectSameImage(dir, films[0], films[1], 128);
  // And the medium is really there: the centre is darker than the environment.
  EXPECT_LT(films[0].color[films[0].index(12, 12)].x, 0.9f);
}

// Writes dir/box.vdb: a 16^3 cube of density 1 and a colour grid of `colour` everywhere (its
// background too). Returns the sidecar's "transform" entry that centres it at the origin.
std::string colouredBox(const std::string& dir, openvdb::Vec3s colour) {
  const int n = 16;
  const float voxel = 0.125f;
  openvdb::Vec3SGrid::Ptr color = openvdb::Vec3SGrid::create(colour);
  color->setName("color");
  color->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
  color->denseFill(openvdb::CoordBBox({0, 0, 0}, {n - 1, n - 1, n - 1}), colour, true);
  writeVdb(dir + "/box.vdb", {cube("density", voxel, n, 1), color});
  const float c = -0.5f * float(n - 1) * voxel;
  return R"("transform": [{"translate": [)" + std::to_string(c) + ", " + std::to_string(c) + ", " +
         std::to_string(c) + "]}]";
}

// The colour grid (vec3, as Cycles' Principled Volume "Color"): a constant colour
// (0.2, 0.5, 1) times sigma_s = 2 renders as the same box with sigma_s = (0.4, 1, 2) and no
// colour grid, statistically (its background is the colour too, so the ramp at the faces is
// the density's alone in both).
TEST(VdbRender, ConstantColorGridMatchesThatScatteringColour) {
  const std::string dir = test::scratchDir("VdbRender.ConstantColorGridMatches");
  const std::string place = colouredBox(dir, {0.2f, 0.5f, 1});
  const std::string media[2] = {
      "[{" + place + R"(, "sigma_a": 0.1, "sigma_s": 2, "g": 0.3,
          "density": {"type": "vdb", "file": "box.vdb", "color_grid": "color"}}])",
      "[{" + place + R"(, "sigma_a": 0.1, "sigma_s": [0.4, 1, 2], "g": 0.3,
          "density": {"type": "vdb", "file": "box.vdb"}}])"};
  Film films[2];
  for (int k = 0; k < 2; ++k) {
    films[k] = renderUnderSky(mediaScene(dir + "/scene.json", media[k], 24, 128, 1.5f),
                              uint64_t(k + 3), {1, 1, 1});
  }
  expectSameImage(dir, films[0], films[1], 128);
  // The colour is there: ignored, sigma_s would be grey and the centre's channels equal.
  const Rgb centre = films[0].color[films[0].index(12, 12)];
  EXPECT_GT(std::abs(centre.x - centre.z), 0.03f) << centre.x << " " << centre.z;
}

// color_mode "albedo" (Cycles' Principled Volume with a colour attribute and a black Absorption
// Color): the colour tints the albedo and sigma_t stays, except where sigma_s x colour exceeds
// it. A box of colour (0.2, 0.5, 1.5) with sigma_a 0.1 and sigma_s 2 renders as a plain box of
// sigma_s (0.4, 1, 3) and sigma_a (2.1 - 0.4, 2.1 - 1, 0): sigma_t (2.1, 2.1, 3).
TEST(VdbRender, AlbedoColorModeKeepsTheExtinction) {
  const std::string dir = test::scratchDir("VdbRender.AlbedoColorModeKeepsTheExtinction");
  const std::string place = colouredBox(dir, {0.2f, 0.5f, 1.5f});
  const std::string media[3] = {
      "[{" + place + R"(, "sigma_a": 0.1, "sigma_s": 2, "g": 0.3, "density": {"type": "vdb",
          "file": "box.vdb", "color_grid": "color", "color_mode": "albedo"}}])",
      "[{" + place + R"(, "sigma_a": [1.7, 1.1, 0], "sigma_s": [0.4, 1, 3], "g": 0.3,
          "density": {"type": "vdb", "file": "box.vdb"}}])",
      "[{" + place + R"(, "sigma_a": 0.1, "sigma_s": 2, "g": 0.3, "density": {"type": "vdb",
          "file": "box.vdb", "color_grid": "color"}}])"};
  Film films[3];
  for (int k = 0; k < 3; ++k)
    films[k] = renderUnderSky(mediaScene(dir + "/scene.json", media[k], 24, 128, 1.5f),
                              uint64_t(k + 3), {1, 1, 1});
  expectSameImage(dir, films[0], films[1], 128);
  // The default mode keeps sigma_a (0.1): a thinner, brighter box in red and green.
  const Rgb albedo = films[0].color[films[0].index(12, 12)];
  const Rgb scattering = films[2].color[films[2].index(12, 12)];
  EXPECT_GT(scattering.x, albedo.x + 0.05f) << scattering.x << " " << albedo.x;
}

// A sparse cloud (a dense ball in one corner of a mostly empty box, and one faint voxel in the
// opposite corner that makes the box big): the majorant grid renders the same image as the
// single majorant (statistically) and takes far fewer tentative collisions.
TEST(VdbRender, MajorantGridMatchesTheSingleMajorantWithFewerCollisions) {
  const std::string dir = test::scratchDir("VdbRender.MajorantGridMatchesTheSingleMajorant");
  const float voxel = 1.0f / 32;
  writeVdb(dir + "/cloud.vdb",
           {makeGrid("density", voxel, {0, 0, 0}, {63, 63, 63}, [](int i, int j, int k) {
             const int di = i - 16, dj = j - 16, dk = k - 40;
             if (di * di + dj * dj + dk * dk <= 100) return 8.0f;
             return i == 60 && j == 60 && k == 4 ? 0.05f : 0.0f;
           })});
  Film films[2];
  uint64_t tentative[2] = {0, 0}, real[2] = {0, 0};
  const int cells[2] = {64, 1};
  for (int k = 0; k < 2; ++k) {
    SceneDescription d = mediaScene(dir + "/scene.json",
                                    R"([{"sigma_a": 0.1, "sigma_s": [0.8, 1.0, 1.2], "g": 0.5,
             "transform": [{"translate": [-1, -1, -1]}],
             "density": {"type": "vdb", "file": "cloud.vdb", "majorant_cells": )" +
                                        std::to_string(cells[k]) + "}}]",
                                    24, 96, 1.1f);
    resetTrackingCounts();
    films[k] = renderUnderSky(d, uint64_t(k), {1, 1, 1});
    tentative[k] = trackingCounts().tentative + trackingCounts().ratioTentative;
    real[k] = trackingCounts().real;
  }
  expectSameImage(dir, films[0], films[1], 96);
  EXPECT_GT(real[0], 1000u);
  // Real collisions are a property of the medium; tentative ones of the tracker.
  EXPECT_LT(double(tentative[0]), 0.25 * double(tentative[1]))
      << "grid " << tentative[0] << ", single " << tentative[1];
  std::printf("tentative collisions: grid %llu, single %llu; real: %llu, %llu\n",
              (unsigned long long)tentative[0], (unsigned long long)tentative[1],
              (unsigned long long)real[0], (unsigned long long)real[1]);
}

// Coloured extinction (sigma_s = (0.25, 1, 4) in a ball, no absorption, under a uniform sky).
// The channels of such a medium do not interact, so the reference is assembled from three grey
// renders (sigma_s = 0.25, 1 and 4 in every channel: the existing tracker, analogue there), one
// channel from each. Spectral MIS over a hero channel (the default) matches it statistically;
// tracking the largest channel (the older estimator) is unbiased too but heavy-tailed: its
// summed per-pixel variance and largest pixel are far above spectral MIS's, with more
// tentative collisions.
TEST(VdbRender, SpectralMisMatchesTheGreyChannelsWithALighterTail) {
  const std::string dir = test::scratchDir("VdbRender.SpectralMisMatchesTheGreyChannels");
  const float voxel = 1.0f / 32;
  writeVdb(dir + "/ball.vdb",
           {makeGrid("density", voxel, {0, 0, 0}, {40, 40, 40}, [](int i, int j, int k) {
             const int di = i - 20, dj = j - 20, dk = k - 20;
             return di * di + dj * dj + dk * dk <= 324 ? 2.0f : 0.0f;
           })});
  auto render = [&](const std::string& sigmaS, const std::string& mode, uint64_t seed,
                    uint64_t* tentative) {
    SceneDescription d =
        mediaScene(dir + "/scene.json",
                   R"([{"sigma_s": )" + sigmaS + R"(, "g": 0.3, "chromatic_tracking": ")" + mode +
                       R"(", "transform": [{"translate": [-0.625, -0.625, -0.625]}],
             "density": {"type": "vdb", "file": "ball.vdb"}}])",
                   24, 64, 0.7f);
    d.render.seed = seed;
    RenderScene scene = buildRenderScene(d);
    test::useUniformEnvironment(&scene, {1, 1, 1});
    resetTrackingCounts();
    Film film = renderScene(scene, d.render);
    if (tentative) *tentative = trackingCounts().tentative;
    return film;
  };
  Film reference;
  const char* grey[3] = {"0.25", "1", "4"};
  for (int c = 0; c < 3; ++c) {
    const Film f = render(grey[c], "spectral_mis", uint64_t(c + 1), nullptr);
    if (c == 0) reference = f;
    for (size_t i = 0; i < f.color.size(); ++i) {
      reference.color[i][c] = f.color[i][c];
      reference.variance[i][c] = f.variance[i][c];
    }
  }
  uint64_t tentative[2] = {0, 0};
  const Film films[2] = {render("[0.25, 1, 4]", "spectral_mis", 7, &tentative[0]),
                         render("[0.25, 1, 4]", "max_channel", 8, &tentative[1])};
  double variance[2] = {0, 0}, largest[2] = {0, 0};
  for (int k = 0; k < 2; ++k)
    for (size_t i = 0; i < films[k].color.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        variance[k] += films[k].variance[i][c];
        largest[k] = std::max(largest[k], double(films[k].color[i][c]));
      }
  expectSameImage(dir, films[0], reference, 64);
  EXPECT_LT(variance[0], 0.5 * variance[1]) << "mis " << variance[0] << ", max " << variance[1];
  EXPECT_LT(largest[0], largest[1]) << "mis " << largest[0] << ", max " << largest[1];
  EXPECT_LT(tentative[0], tentative[1]);
  std::printf(
      "summed pixel variance: spectral MIS %.3g, largest channel %.3g; largest pixel "
      "%.3g, %.3g; tentative collisions %llu, %llu\n",
      variance[0], variance[1], largest[0], largest[1], (unsigned long long)tentative[0],
      (unsigned long long)tentative[1]);
}

// A fire in thin coloured soot (sigma_a differs per channel, the soot scatters, density 0.05
// to 0.4 and a temperature grid hottest at the centre): spectral MIS (the default) and
// tracking the largest channel give the same image, and, each with the track-length
// estimator on every segment, spectral MIS's summed per-pixel variance stays within 1.5x the
// other's. When spectral MIS weighed emission at the collisions and ended paths at
// absorptions, it had 8x here (6.55 against 0.80) and on a coloured version of the fire of
// scenes/volumes (benchmarks/README, issue 52). Tracking the largest channel, the camera ray's
// whole-segment emission (the default, which spectral MIS does not have) gives the same image
// with less than 0.7x the variance.
TEST(VdbRender, SpectralMisFireMatchesTheLargestChannel) {
  const std::string dir = test::scratchDir("VdbRender.SpectralMisFireMatchesTheLargestChannel");
  const float voxel = 1.0f / 32;
  auto ball = [](float inside, float centre) {
    return [=](int i, int j, int k) {
      const float r2 = float((i - 20) * (i - 20) + (j - 20) * (j - 20) + (k - 20) * (k - 20));
      return r2 <= 324 ? inside + (centre - inside) * (1 - r2 / 324) : 0.0f;
    };
  };
  writeVdb(dir + "/fire.vdb",
           {makeGrid("density", voxel, {0, 0, 0}, {40, 40, 40}, ball(0.05f, 0.4f)),
            makeGrid("temperature", voxel, {0, 0, 0}, {40, 40, 40}, ball(900, 2200))});
  Film films[3];
  double variance[3] = {0, 0, 0};
  const char* modes[3] = {"spectral_mis", "max_channel", "max_channel"};
  for (int k = 0; k < 3; ++k) {
    SceneDescription d = mediaScene(
        dir + "/scene.json",
        std::string(
            R"([{"sigma_a": [0.8, 1.2, 2.0], "sigma_s": 1.5, "g": 0.2, "chromatic_tracking": ")") +
            modes[k] + R"(", "transform": [{"translate": [-0.625, -0.625, -0.625]}],
             "density": {"type": "vdb", "file": "fire.vdb", "temperature_grid": "temperature",
                         "blackbody_intensity": 4}}])",
        24, 64, 0.7f);
    d.render.integrator.wholeSegmentEmission = k == 2;
    films[k] = renderUnderSky(d, uint64_t(k + 3), {0.05f, 0.05f, 0.05f});
    for (size_t i = 0; i < films[k].color.size(); ++i)
      for (int c = 0; c < 3; ++c) variance[k] += films[k].variance[i][c];
  }
  expectSameImage(dir, films[0], films[1], 64);
  expectSameImage(dir, films[2], films[1], 64);
  EXPECT_LT(variance[0], 1.5 * variance[1]) << "mis " << variance[0] << ", max " << variance[1];
  EXPECT_LT(variance[2], 0.7 * variance[1]) << "whole " << variance[2] << ", " << variance[1];
  std::printf(
      "summed pixel variance: spectral MIS %.3g, largest channel %.3g; its camera ray's whole "
      "segment %.3g\n",
      variance[0], variance[1], variance[2]);
}

// Fire: a cube whose temperature grid holds 1,500 K and whose flame grid holds 2, without
// extinction, seen along z: the radiance is the emission integrated along the ray. Inside the
// cube each emits its constant; over the one-voxel ramps at the front and back faces the grid
// value goes linearly from 0 to its constant, so the flame (linear in the value) adds half a
// voxel at each face, and the blackbody (T^4 and a colour) the integral of its emission over
// the ramp, computed here from blackbodyEmission.
TEST(VdbRender, TemperatureAndFlameGridsEmitTheirIntegral) {
  const std::string dir = test::scratchDir("VdbRender.TemperatureAndFlameGridsEmit");
  const int n = 8;
  const float voxel = 0.25f;
  writeVdb(dir + "/fire.vdb", {cube("density", voxel, n, 1), cube("temperature", voxel, n, 1500),
                               cube("flame", voxel, n, 2)});
  const float c = -0.5f * float(n - 1) * voxel;
  const std::string place = R"("transform": [{"translate": [)" + std::to_string(c) + ", " +
                            std::to_string(c) + ", " + std::to_string(c) + "]}]";
  const float inner = float(n - 1) * voxel;
  Rgb ramp;  // the integral of the blackbody emission over one ramp
  const int steps = 2000;
  for (int s = 0; s < steps; ++s)
    ramp += blackbodyEmission(1500 * (float(s) + 0.5f) / float(steps)) * (voxel / float(steps));
  struct Case {
    std::string keys;
    Rgb expected;
  };
  const Rgb flameColor{1, 0.5f, 0.25f};
  const Case cases[] = {
      {R"("temperature_grid": "temperature", "blackbody_intensity": 2)",
       (blackbodyEmission(1500) * inner + ramp * 2) * 2},
      {R"("flame_grid": "flame", "flame_strength": 3, "flame_color": [1, 0.5, 0.25])",
       flameColor * (3 * 2 * (inner + voxel))},
      // The flame grid (2) as the temperature, mapped voxel by voxel to 1,500 K and 0 K
      // outside (500 K before the cutoff): the same ramps as the first case.
      {R"("temperature_grid": "flame", "temperature_scale": 500, "temperature_offset": 500,
          "temperature_cutoff": 600, "blackbody_intensity": 2)",
       (blackbodyEmission(1500) * inner + ramp * 2) * 2},
  };
  for (const Case& k : cases) {
    for (const char* integrator : {"path", "whitted"}) {
      SceneDescription d = mediaScene(dir + "/scene.json",
                                      "[{" + place + R"(, "density": {"type": "vdb",
                                          "file": "fire.vdb", )" +
                                          k.keys + "}}]",
                                      16, 32, 1.5f, integrator);
      d.render.integrator.volumeEstimator = "track";
      RenderScene scene = buildRenderScene(d);
      test::useUniformEnvironment(&scene, {0, 0, 0});
      const Film film = renderScene(scene, d.render);
      // The pixels well inside the cube's silhouette (|x|, |y| < 0.6).
      Rgb sum, var;
      int count = 0;
      for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
          const Vec2f p = pixelCentre(film, x, y, 1.5f);
          if (std::abs(p.x) > 0.6f || std::abs(p.y) > 0.6f) continue;
          sum += film.color[film.index(x, y)];
          var += film.variance[film.index(x, y)];
          ++count;
        }
      ASSERT_GT(count, 10);
      for (int ch = 0; ch < 3; ++ch) {
        const float mean = sum[ch] / float(count), sigma = std::sqrt(var[ch]) / float(count);
        EXPECT_NEAR(mean, k.expected[ch], 4 * sigma + 1e-3f * k.expected[ch])
            << k.keys << " " << integrator << " channel " << ch;
      }
      EXPECT_GT(luminance(k.expected), 0.05f);
    }
  }
}

// The emission bound (VdbEmission::luminanceBound) that guides the path tracer's emission
// samples: it bounds the emission's luminance in every cell, is 0 in cells that cannot emit
// (so those get no samples) and positive in every cell once the temperature grid has an
// ambient background; a fire guided by it renders the same image as the unguided estimator
// (majorant_cells 1: no cells, no bound), with less variance where it burns.
TEST(VdbRender, EmissionBoundGuidesTheEmissionSamples) {
  const std::string dir = test::scratchDir("VdbRender.EmissionBoundGuides");
  const float voxel = 1.0f / 16;
  // Smoke over [0, 31]^3 voxels; a hot core of 6^3 voxels off-centre; flame nowhere else.
  auto hot = [](int i, int j, int k) {
    return i >= 18 && i < 24 && j >= 8 && j < 14 && k >= 12 && k < 18;
  };
  auto density =
      makeGrid("density", voxel, {0, 0, 0}, {31, 31, 31}, [](int, int, int) { return 1.0f; });
  auto temperature = makeGrid("temperature", voxel, {0, 0, 0}, {31, 31, 31},
                              [&](int i, int j, int k) { return hot(i, j, k) ? 1800.0f : 0.0f; });
  writeVdb(dir + "/fire.vdb", {density, temperature});
  auto ambient = temperature->deepCopy();
  openvdb::tools::changeBackground(ambient->tree(), 300.0f);
  writeVdb(dir + "/ambient.vdb", {density, ambient});

  VdbRequest request;
  request.where = {"scene.json", "/media/0/density/file"};
  request.density = {"density", {"scene.json", "/media/0/density/grid"}};
  request.temperature = VdbGridRequest{"temperature", {"scene.json", "/x"}};
  request.majorantCells = 8;
  VdbEmissionParams params;
  params.blackbodyIntensity = 1;
  for (const char* file : {"fire.vdb", "ambient.vdb"}) {
    SCOPED_TRACE(file);
    auto v = std::shared_ptr<const VdbVolume>(readVdbFile(dir + "/" + file, request));
    const VdbEmission emission(v, params);
    ASSERT_NE(emission.luminanceBound(), nullptr);
    const MajorantGrid& b = *emission.luminanceBound();
    ASSERT_EQ(b.res(0), v->majorants->res(0));
    int cold = 0;
    for (int z = 0; z < b.res(2); ++z)
      for (int y = 0; y < b.res(1); ++y)
        for (int x = 0; x < b.res(0); ++x) cold += b.at(x, y, z) > 0 ? 0 : 1;
    if (std::string(file) == "fire.vdb") {
      EXPECT_GT(cold, b.res(0) * b.res(1) * b.res(2) / 2);  // most cells cannot emit
    } else {
      EXPECT_EQ(cold, 0);  // 300 K glows (faintly) everywhere
    }
    // (The bound's blackbody and the emission's may round apart by an ulp or so.)
    expectCellsBound(b, v->bounds, 5, 1e-4f,
                     [&](Vec3f p) { return luminance(emission.emission(p)); });
  }

  // Guided (16 cells) against unguided (1 cell): the same image, less variance in the core.
  Film films[2];
  const int cells[2] = {16, 1};
  for (int k = 0; k < 2; ++k) {
    SceneDescription d = mediaScene(dir + "/scene.json",
                                    R"([{"sigma_a": 0.2, "sigma_s": 0.2,
             "transform": [{"translate": [-1, -1, -1]}],
             "density": {"type": "vdb", "file": "fire.vdb", "temperature_grid": "temperature",
                         "blackbody_intensity": 4, "majorant_cells": )" +
                                        std::to_string(cells[k]) + "}}]",
                                    24, 64, 1.1f);
    films[k] = renderUnderSky(d, uint64_t(k + 3), {0.1f, 0.1f, 0.1f});
  }
  expectSameImage(dir, films[0], films[1], 64);
  double variance[2] = {0, 0};
  for (int k = 0; k < 2; ++k)
    for (size_t i = 0; i < films[k].variance.size(); ++i) variance[k] += films[k].variance[i].y;
  EXPECT_LT(variance[0], 0.8 * variance[1])
      << "guided " << variance[0] << ", unguided " << variance[1];
  std::printf("summed pixel variance (green): guided %.4g, unguided %.4g\n", variance[0],
              variance[1]);
}

// `smoke_####.vdb`: one file per frame, the frame of the scene time at the scene's frame rate.
TEST(VdbFile, FramePatternReadsOneFilePerFrame) {
  const std::string dir = test::scratchDir("VdbFile.FramePatternReadsOneFilePerFrame");
  for (int f = 0; f < 2; ++f) {
    char name[64];
    std::snprintf(name, sizeof name, "/smoke_%04d.vdb", f);
    writeVdb(dir + name, {cube("density", 0.1f, 4, float(f + 1))});
  }
  std::ofstream(dir + "/scene.json") << R"({
    "render": {"fps": 24},
    "cameras": [{"name": "c", "position": [0, 0, 3], "look_at": [0, 0, 0]}],
    "media": [{"sigma_s": 1, "density": {"type": "vdb", "file": "smoke_####.vdb"}}]
  })";
  const SceneLoader loader(dir + "/scene.json");
  EXPECT_EQ(loader.at(0.0).media[0].vdb->maxDensity, 1.0f);
  EXPECT_EQ(loader.at(1.0 / 24).media[0].vdb->maxDensity, 2.0f);
  EXPECT_SCENE_ERROR(test::errorFrom([&] { loader.at(2.0 / 24); }), dir + "/scene.json",
                     "/media/0/density/file", "smoke_0002.vdb");
}

}  // namespace
}  // namespace glint
