// `glint render` and `glint info` end to end: determinism across thread counts, statistics,
// command-line precedence, quiet output, and what `info` reports.
#include <OpenImageIO/imagebuf.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "image/input.h"
#include "test_support.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

std::string lambertPlane() { return "'" + test::dataDir() + "/scenes/lambert_plane.gltf'"; }

std::vector<float> readPixels(const std::string& path, OIIO::ImageSpec* spec = nullptr) {
  OIIO::ImageBuf buf(path);
  EXPECT_TRUE(buf.read(0, 0, true, OIIO::TypeDesc::FLOAT)) << path << ": " << buf.geterror();
  std::vector<float> pixels(size_t(buf.spec().image_pixels()) * size_t(buf.nchannels()));
  buf.get_pixels(buf.roi(), OIIO::TypeDesc::FLOAT, pixels.data());
  if (spec) *spec = buf.spec();
  return pixels;
}

TEST(CliRender, ExrIsIdenticalForOneAndTwoThreads) {
  std::string dir = test::scratchDir("cli_determinism");
  for (int threads : {1, 2}) {
    test::CommandResult r = test::runGlint("render " + lambertPlane() +
                                           " --quiet --spp 8 --threads " + std::to_string(threads) +
                                           " -o " + dir + "/t" + std::to_string(threads) + ".exr");
    ASSERT_EQ(r.exitCode, 0) << r.err;
  }
  std::vector<float> a = readPixels(dir + "/t1.exr"), b = readPixels(dir + "/t2.exr");
  ASSERT_EQ(a.size(), b.size());
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(a == b) << "1-thread and 2-thread renders differ";
}

TEST(CliRender, StatsJsonHasEveryField) {
  std::string dir = test::scratchDir("cli_stats");
  test::CommandResult r = test::runGlint("render " + lambertPlane() + " --quiet --spp 4 -o " + dir +
                                         "/img.exr --stats " + dir + "/stats.json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  std::ifstream in(dir + "/stats.json");
  nlohmann::json j = nlohmann::json::parse(in);
  for (const char* key :
       {"accel", "width", "height", "spp", "threads", "triangles", "primitives", "build_seconds",
        "render_seconds", "rays", "mrays_per_second", "effects", "nonfinite_samples"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["accel"], "embree");
  EXPECT_EQ(j["spp"], 4);
  EXPECT_EQ(j["triangles"], 2);
  EXPECT_EQ(j["width"], 64);
  EXPECT_EQ(j["rays"]["camera"], 64 * 64 * 4);
  // Every pixel sees the plane, lit by the bulb: one shadow ray per camera ray.
  EXPECT_EQ(j["rays"]["shadow"], 64 * 64 * 4);
  EXPECT_EQ(j["nonfinite_samples"], 0);
  EXPECT_EQ(j["effects"], nlohmann::json::array({"shadows"}));
  EXPECT_GT(j["mrays_per_second"].get<double>(), 0.0);
}

// The stats name the integrator that rendered ("auto" resolved; the request kept beside it),
// and instant radiosity reports the VPLs it built before rendering.
TEST(CliRender, StatsJsonNamesTheResolvedIntegratorAndItsSetup) {
  std::string dir = test::scratchDir("cli_stats_integrator");
  test::CommandResult r =
      test::runGlint("render " + lambertPlane() + " --quiet --spp 1 --integrator auto -o " + dir +
                     "/auto.exr --stats " + dir + "/auto.json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(std::ifstream(dir + "/auto.json"));
  EXPECT_EQ(j["integrator"], "whitted");  // one point light: nothing with an extent
  EXPECT_EQ(j["integrator_requested"], "auto");
  EXPECT_FALSE(j.contains("integrator_setup"));

  r = test::runGlint("render " + lambertPlane() +
                     " --quiet --spp 1 --integrator instant-radiosity -o " + dir +
                     "/ir.exr --stats " + dir + "/ir.json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  j = nlohmann::json::parse(std::ifstream(dir + "/ir.json"));
  EXPECT_EQ(j["integrator"], "instant-radiosity");
  ASSERT_TRUE(j.contains("integrator_setup")) << j.dump();
  const nlohmann::json& setup = j["integrator_setup"];
  EXPECT_EQ(setup["vpl_paths"], 64);  // the default
  EXPECT_EQ(setup["vpl_clamp"], 0);
  // A point light over one lit plane: every light path leaves a VPL on the plane (the
  // light's downward half of the paths, at least), and each VPL took at least one ray.
  EXPECT_GT(setup["vpls"].get<double>(), 0);
  EXPECT_LE(setup["vpls"].get<double>(), 64 * 8);
  EXPECT_GE(setup["light_path_rays"].get<double>(), setup["vpls"].get<double>());
  EXPECT_NE(std::find(j["effects"].begin(), j["effects"].end(), "virtual point lights"),
            j["effects"].end())
      << j["effects"].dump();
}

TEST(CliInfo, NamesTheIntegratorAutoPicks) {
  test::CommandResult r = test::runGlint("info " + lambertPlane() + " --integrator auto");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("integrator whitted (auto)"), std::string::npos) << r.out;
}

TEST(CliRender, CommandLineOverridesTheSidecar) {
  std::string dir = test::scratchDir("cli_override");
  test::CommandResult r =
      test::runGlint("render " + lambertPlane() +
                     " --quiet --spp 3 --width 20 --height 10 --seed 9 -o " + dir + "/img.exr");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  OIIO::ImageSpec spec;
  readPixels(dir + "/img.exr", &spec);
  EXPECT_EQ(spec.width, 20);
  EXPECT_EQ(spec.height, 10);
  EXPECT_EQ(spec.get_int_attribute("glint:spp"), 3);
  EXPECT_EQ(spec.get_string_attribute("glint:seed"), "9");
}

TEST(CliRender, WritesSeveralFormatsFromOneRender) {
  std::string dir = test::scratchDir("cli_formats");
  test::CommandResult r = test::runGlint("render " + lambertPlane() + " --quiet --spp 2 -o " + dir +
                                         "/a.exr -o " + dir + "/a.png");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir + "/a.exr"));
  EXPECT_TRUE(fs::exists(dir + "/a.png"));
}

TEST(CliRender, QuietPrintsNothingAndNonTerminalGetsNoProgressBar) {
  std::string dir = test::scratchDir("cli_quiet");
  test::CommandResult quiet =
      test::runGlint("render " + lambertPlane() + " --quiet --spp 1 -o " + dir + "/q.exr");
  ASSERT_EQ(quiet.exitCode, 0);
  EXPECT_EQ(quiet.err, "");
  EXPECT_EQ(quiet.out, "");
  test::CommandResult normal =
      test::runGlint("render " + lambertPlane() + " --spp 1 -o " + dir + "/n.exr");
  ASSERT_EQ(normal.exitCode, 0);
  // stderr is a file here, not a terminal: a one-line summary, no carriage-return redraws.
  EXPECT_EQ(normal.err.find('\r'), std::string::npos) << normal.err;
  EXPECT_NE(normal.err.find("wrote"), std::string::npos) << normal.err;
}

// --aovs with only display outputs would be lost work: refused, saying where AOVs go.
TEST(CliRender, AovsWithoutAnExrOutputAreRefused) {
  std::string dir = test::scratchDir("cli_aovs_png");
  test::CommandResult r =
      test::runGlint("render " + lambertPlane() + " --aovs --spp 1 -o " + dir + "/a.png");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--aovs: the AOVs (albedo, normal, depth) go only into EXR output"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir + "/a.png"));
}

// A crop's summary says which pixels of which frame it holds; --threads above the core count
// prints nothing but that summary (no warning from the thread library).
TEST(CliRender, ACropSaysItsSizeAndManyThreadsWarnNothing) {
  std::string dir = test::scratchDir("cli_crop_size");
  test::CommandResult r = test::runGlint("render " + lambertPlane() +
                                         " --width 40 --height 30 --spp 1 --threads 64 "
                                         "--crop 4,2,20,12 -o " +
                                         dir + "/c.exr");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("(16x10 pixels 4,2..20,12 of the 40x30 frame, 1 spp"), std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(CliInfo, ListsContentsAndEffects) {
  test::CommandResult r = test::runGlint("info " + lambertPlane());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("2 triangles"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Bulb (point)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Top (orthographic)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("effects:    shadows\n"), std::string::npos) << r.out;
}

// With a shutter over its animation, the skinned and the weight-animated triangles of
// skin_morph.gltf deform (3 time steps for the linear morph, more for the turning joint).
TEST(CliInfo, ListsWhatMovesOverTheShutter) {
  const std::string dir = test::scratchDir("cli_info_motion");
  std::ofstream(dir + "/shutter.json") << R"({
  "cameras": [{"name": "c", "position": [0, 0, 20], "look_at": [0, 0, 0], "shutter": [0, 1]}]
})";
  const std::string scene = test::dataDir() + "/gltf/skin_morph.gltf";
  test::CommandResult r = test::runGlint("info " + scene + " --sidecar " + dir + "/shutter.json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("motion:     2 deforming meshes (up to "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("motion blur"), std::string::npos) << r.out;
  // Without the sidecar there is no shutter and nothing moves.
  r = test::runGlint("info " + scene);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.out.find("motion:"), std::string::npos) << r.out;
  // --shutter gives the automatic camera one.
  r = test::runGlint("info " + scene + " --shutter 0.5");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("motion:     2 deforming meshes"), std::string::npos) << r.out;
  r = test::runGlint("info " + scene + " --shutter 0.25,0.5");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("motion:     2 deforming meshes"), std::string::npos) << r.out;
  // Bad values are input errors naming the option.
  for (const char* bad : {"0.5,0.1", "soon", "1,", "nan"}) {
    r = test::runGlint("info " + scene + " --shutter " + bad);
    EXPECT_EQ(r.exitCode, 2) << bad;
    EXPECT_NE(r.err.find("--shutter"), std::string::npos) << r.err;
  }
}

// Effects that come and go over an animation: a lens whose aperture opens at 1 s is listed
// from frame 24 on, and a bad frame range is an input error.
TEST(CliInfo, FramesListEachEffectWithTheFramesItAppearsIn) {
  const std::string dir = test::scratchDir("cli_info_frames");
  const std::string scene = dir + "/lens.json";
  std::ofstream(scene) << R"({
  "cameras": [{"name": "c", "position": [0, 0, 5], "look_at": [0, 0, 0],
               "aperture": {"keys": [[0, 0], [0.5, 0], [1, 0.1]]}, "focus_distance": 5}],
  "objects": [{"type": "sphere", "radius": 1}]})";
  test::CommandResult r = test::runGlint("info '" + scene + "' --frames 0-48:6");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("effects over frames 0-48 (every 6, 9 frames at 24 fps):"),
            std::string::npos)
      << r.out;
  // At 0.5 s the aperture is still 0; frame 18 (0.75 s) is the first checked with a lens.
  EXPECT_NE(r.out.find("  depth of field         frames 18-48 (6 of 9 checked)"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("  analytic               frames 0-48 (9 of 9 checked)"), std::string::npos)
      << r.out;
  test::CommandResult bad = test::runGlint("info '" + scene + "' --frames 9-2");
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("--frames"), std::string::npos) << bad.err;
}

TEST(CliInfo, SceneWithoutLightsReportsTheDefaultLight) {
  const std::string scene = test::dataDir() + "/scenes/two_instances.gltf";
  test::CommandResult r = test::runGlint("info '" + scene + "'");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("default light"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("environment light"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("instancing"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("path (auto)"), std::string::npos) << r.out;
  // Switched off: no light at all, so nothing casts shadows and Whitted is enough.
  test::CommandResult off = test::runGlint("info '" + scene + "' --no-default-light");
  ASSERT_EQ(off.exitCode, 0) << off.err;
  EXPECT_EQ(off.out.find("default light"), std::string::npos) << off.out;
  EXPECT_EQ(off.out.find("shadows"), std::string::npos) << off.out;
  EXPECT_NE(off.out.find("whitted (auto)"), std::string::npos) << off.out;
}

TEST(CliRender, EnvironmentOptions) {
  const std::string dir = test::scratchDir("cli_env");
  const std::string scene = test::dataDir() + "/scenes/two_instances.gltf";
  // The studio, twice as strong, turned: a 16 x 11 render twice as bright in the mean.
  const std::string common = " --width 16 --spp 16 --quiet --seed 3";
  ASSERT_EQ(test::runGlint("render '" + scene + "' -o '" + dir + "/a.exr'" + common).exitCode, 0);
  test::CommandResult twice = test::runGlint("render '" + scene + "' -o '" + dir + "/b.exr'" +
                                             common + " --env studio --env-strength 2");
  ASSERT_EQ(twice.exitCode, 0) << twice.err;
  const Film a = readExr(dir + "/a.exr"), b = readExr(dir + "/b.exr");
  double sa = 0, sb = 0;
  for (size_t i = 0; i < a.color.size(); ++i) sa += a.color[i].y, sb += b.color[i].y;
  EXPECT_NEAR(sb / sa, 2.0, 1e-3);  // same samples, every light term doubled
  // Bad values: exit 2, naming the option.
  for (const std::string& bad :
       {std::string(" --env nowhere.exr"), std::string(" --env '") + scene + "'",
        std::string(" --no-default-light --env-strength 2")}) {
    test::CommandResult r =
        test::runGlint("render '" + scene + "' -o '" + dir + "/c.exr'" + common + bad);
    EXPECT_EQ(r.exitCode, 2) << bad;
    EXPECT_NE(r.err.find("--env"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/c.exr"));
}

TEST(CliRender, VariantOption) {
  const std::string dir = test::scratchDir("cli_variant");
  const std::string scene = test::dataDir() + "/gltf/variants.gltf";
  test::CommandResult info = test::runGlint("info '" + scene + "' --variant green");
  ASSERT_EQ(info.exitCode, 0) << info.err;
  EXPECT_NE(info.out.find("variants:   3: blue, green, lime; showing 'green'"), std::string::npos)
      << info.out;
  test::CommandResult r =
      test::runGlint("render '" + scene + "' -o '" + dir +
                     "/v.exr' --width 4 --height 4 --spp 1 --quiet --variant blue");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const Film f = readExr(dir + "/v.exr");
  EXPECT_NEAR(f.color[5].z, 0.8f, 1e-5f);
  EXPECT_NEAR(f.color[5].x, 0.0f, 1e-5f);
  test::CommandResult bad = test::runGlint("render '" + scene + "' -o '" + dir +
                                           "/w.exr' --width 4 --spp 1 --quiet --variant purple");
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("--variant: no material variant named 'purple'"), std::string::npos)
      << bad.err;
  EXPECT_NE(bad.err.find("(variants: 'blue', 'green', 'lime')"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/w.exr"));
}

}  // namespace
}  // namespace glint
