// Tests for `glint diff`: exit codes 0 (pass) / 1 (fail) / 2 (bad input) and --json output.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <vector>

#include "image/output.h"
#include "test_support.h"

namespace glint {
namespace {

void writeRgb(const std::string& path, int w, int h, const std::vector<float>& pixels) {
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << OIIO::geterror();
  ASSERT_TRUE(out->open(path, spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
  ASSERT_TRUE(out->close());
}

struct Images {
  std::string dir, ref, same, off, small;
};

// ref: 4×4 grey 0.5; same: a copy; off: pixel (3, 0) red +0.5; small: 2×2.
Images makeImages(const std::string& name) {
  Images im;
  im.dir = test::scratchDir(name);
  std::vector<float> grey(16 * 3, 0.5f), off = grey;
  off[3 * 3] = 1.0f;
  im.ref = im.dir + "/ref.exr";
  im.same = im.dir + "/same.exr";
  im.off = im.dir + "/off.exr";
  im.small = im.dir + "/small.exr";
  writeRgb(im.ref, 4, 4, grey);
  writeRgb(im.same, 4, 4, grey);
  writeRgb(im.off, 4, 4, off);
  writeRgb(im.small, 2, 2, std::vector<float>(12, 0.5f));
  return im;
}

std::string q(const std::string& s) { return "'" + s + "'"; }

// Writes the R, G, B, A channels of the EXR `from` alone to `to`: an image without variance,
// as other renderers (and glint before every EXR carried its variance) write them.
void writeWithoutVariance(const std::string& from, const std::string& to) {
  auto in = OIIO::ImageInput::open(from);
  ASSERT_TRUE(in);
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<float> px(size_t(spec.image_pixels()) * 4);
  ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, px.data()));
  OIIO::ImageSpec out(spec.width, spec.height, 4, OIIO::TypeDesc::FLOAT);
  out.channelnames = {"R", "G", "B", "A"};
  auto o = OIIO::ImageOutput::create(to);
  ASSERT_TRUE(o && o->open(to, out));
  ASSERT_TRUE(o->write_image(OIIO::TypeDesc::FLOAT, px.data()));
  o->close();
}

TEST(DiffCommand, ExitCodesPassFailBadInput) {
  Images im = makeImages("DiffCommand.ExitCodesPassFailBadInput");
  test::CommandResult r = test::runGlint("diff " + q(im.same) + " " + q(im.ref));
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("PASS"), std::string::npos) << r.out;

  r = test::runGlint("diff " + q(im.off) + " " + q(im.ref));
  EXPECT_EQ(r.exitCode, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("FAILURE"), std::string::npos) << r.out;

  r = test::runGlint("diff " + q(im.small) + " " + q(im.ref));
  EXPECT_EQ(r.exitCode, 1) << r.out << r.err;

  r = test::runGlint("diff " + q(im.ref) + " " + q(im.dir + "/missing.exr"));
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("missing.exr"), std::string::npos) << r.err;

  r = test::runGlint("diff " + q(im.ref));  // usage error: B missing
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
}

TEST(DiffCommand, PercentThresholdsSwitchTheExitCode) {
  Images im = makeImages("DiffCommand.PercentThresholdsSwitchTheExitCode");
  // 1 of 16 pixels (6.25 %) is off by 0.5.
  EXPECT_EQ(test::runGlint("diff --failpercent 10 " + q(im.off) + " " + q(im.ref)).exitCode, 0);
  EXPECT_EQ(test::runGlint("diff --failpercent 5 " + q(im.off) + " " + q(im.ref)).exitCode, 1);
  EXPECT_EQ(test::runGlint("diff --fail 0.6 --warn 0.6 " + q(im.off) + " " + q(im.ref)).exitCode,
            0);
  test::CommandResult r = test::runGlint("diff --failpercent 10 " + q(im.off) + " " + q(im.ref));
  EXPECT_NE(r.out.find("WARNING"), std::string::npos) << r.out;  // warn threshold still 0 %
}

TEST(DiffCommand, JsonReportsTheMetrics) {
  Images im = makeImages("DiffCommand.JsonReportsTheMetrics");
  test::CommandResult r = test::runGlint("diff --json " + q(im.off) + " " + q(im.ref));
  EXPECT_EQ(r.exitCode, 1) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out, nullptr, /*allow_exceptions=*/false);
  ASSERT_FALSE(j.is_discarded()) << r.out;
  EXPECT_EQ(j["verdict"], "fail");
  EXPECT_EQ(j["pass"], false);
  EXPECT_EQ(j["fail_pixels"], 1);
  EXPECT_NEAR(j["fail_pixel_percent"].get<double>(), 6.25, 1e-9);
  EXPECT_NEAR(j["rmse"].get<double>(), std::sqrt(0.25 / 48), 1e-6);
  EXPECT_NEAR(j["max_error"].get<double>(), 0.5, 1e-6);
  EXPECT_EQ(j["max_pixel"], nlohmann::json::array({3, 0}));
  EXPECT_EQ(j["max_channel"], "R");

  r = test::runGlint("diff --json " + q(im.same) + " " + q(im.ref));
  EXPECT_EQ(r.exitCode, 0);
  j = nlohmann::json::parse(r.out, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << r.out;
  EXPECT_EQ(j["rmse"], 0.0);
  EXPECT_TRUE(j["psnr"].is_null());  // +inf has no JSON spelling
}

// Statistical mode end to end: a glint reference with variance, renders at lower spp.
TEST(DiffCommand, StatisticalModeJudgesRendersAgainstAReferenceWithVariance) {
  std::string dir = test::scratchDir("DiffCommand.StatisticalMode");
  std::string scene = test::sourceDir() + "/tests/reference_images/scenes/cornell_path.json";
  std::string size = " --width 24 --height 24 --quiet";
  test::CommandResult r =
      test::runGlint("render " + q(scene) + size + " --spp 1024 --aovs -o " + q(dir + "/ref.exr"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  r = test::runGlint("render " + q(scene) + size + " --spp 32 --seed 5 -o " + q(dir + "/a.exr"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  r = test::runGlint("diff " + q(dir + "/a.exr") + " " + q(dir + "/ref.exr") +
                     " --statistical --json --heatmap " + q(dir + "/heat.png"));
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("mode"), "statistical");
  EXPECT_EQ(j.at("spp"), nlohmann::json::array({32, 1024}));
  // Every glint EXR carries its variance: A's own counts, where above the prediction.
  EXPECT_EQ(j.at("variance_model"), "max(own, predicted)");
  EXPECT_TRUE(j.at("max_error_allowed").is_null());  // no cap unless asked
  EXPECT_TRUE(std::filesystem::exists(dir + "/heat.png"));

  // An image without variance is no reference.
  writeWithoutVariance(dir + "/a.exr", dir + "/plain.exr");
  r = test::runGlint("diff " + q(dir + "/ref.exr") + " " + q(dir + "/plain.exr") +
                     " --statistical");
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("plain.exr"), std::string::npos) << r.err;

  // A lamp twice as bright fails.
  std::string text = test::slurp(scene);
  std::string brighter =
      std::regex_replace(text, std::regex("\"intensity\": 10"), "\"intensity\": 20");
  ASSERT_NE(brighter, text);
  { std::ofstream(dir + "/brighter.json") << brighter; }
  r = test::runGlint("render " + q(dir + "/brighter.json") + size + " --spp 32 -o " +
                     q(dir + "/b.exr"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  r = test::runGlint("diff " + q(dir + "/b.exr") + " " + q(dir + "/ref.exr") + " --statistical");
  EXPECT_EQ(r.exitCode, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("BIASED"), std::string::npos) << r.out;
}

// A reference B (grey 0.5, variance of the mean 1e-4 per channel, 1024 spp) and a render A equal
// to it but for two pixels 500 sigma off in opposite directions: 2 of 1000 pixels fail their
// z-test (99.8% pass, 99.5% needed), the offsets cancel in the global bias test, and mean z^2 is
// about 167. The verdict is PASS; the text must say what was checked and what mean z^2 means.
TEST(DiffCommand, StatisticalTextSaysWhatItChecksAndWhatMeanZ2Means) {
  const std::string dir = test::scratchDir("DiffCommand.StatisticalTextSaysWhatItChecks");
  const int w = 40, h = 25;
  Film ref(w, h, true);
  ref.color.assign(ref.color.size(), Rgb{0.5f, 0.5f, 0.5f});
  ref.alpha.assign(ref.alpha.size(), 1.0f);
  ref.variance.assign(ref.variance.size(), Rgb{1e-4f, 1e-4f, 1e-4f});
  ImageMetadata meta;
  meta.spp = 1024;
  writeImage(dir + "/ref.exr", ref, RenderSettings{}, meta);
  // sigma^2 = Var[B] + Var[A] (predicted: the same at the same spp) + the floor (6e-4)^2.
  const float sigma = float(std::sqrt(2e-4 + 6e-4 * 6e-4));
  Film a(w, h, false);
  a.color = ref.color;
  a.alpha = ref.alpha;
  a.color[3 + 4 * w].x += 500 * sigma;
  a.color[10 + 20 * w].x -= 500 * sigma;
  writeImage(dir + "/a.exr", a, RenderSettings{}, meta);

  test::CommandResult r =
      test::runGlint("diff " + q(dir + "/a.exr") + " " + q(dir + "/ref.exr") + " --statistical");
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  for (const char* line :
       {"  Each pixel channel is tested: z = (A - B) / sigma, where sigma^2 is B's variance "
        "of its mean plus A's own variance channels or, where larger, predicted from B's (1024 "
        "vs 1024 spp).\n",
        "  The test passes when all of these hold; each |z| limit is set so that a correct "
        "render exceeds it with a 1% chance (--significance) over all the values it is "
        "applied to:\n",
        "  [ok]   pixels within the noise: 99.800% have every |z| <= 4.65; need >= 99.5% "
        "(--min-pass); 2 pixels over\n",
        "  [--]   error cap: none (--max-error sets one); the largest |A-B|/max(1,|B|) of a "
        "pixel over |z| = 4.65 is 7.08 @ (3, 4)\n",
        "  [ok]   no NaN or Inf: 0 channel values are NaN or Inf\n",
        "  Not part of the verdict: largest |z| = 500 @ (3, 4, R); mean z^2 = 167 (about 1 when "
        "sigma is the true size of the differences;",
        "  Note: mean z^2 = 167 is far above 1: the differences are about 12.9 times the noise "
        "the variances predict",
        "\nPASS: every check above holds (but see the note on mean z^2)\n"})
    EXPECT_NE(r.out.find(line), std::string::npos) << "missing: " << line << "\nin:\n" << r.out;
  EXPECT_NE(r.out.find("  [ok]   no overall bias: sum(A - B) / sqrt(sum sigma^2) per channel is "),
            std::string::npos)
      << r.out;

  // Both offsets the same way: biased, and the failure says so.
  a.color[10 + 20 * w].x += 1000 * sigma;
  writeImage(dir + "/b.exr", a, RenderSettings{}, meta);
  r = test::runGlint("diff " + q(dir + "/b.exr") + " " + q(dir + "/ref.exr") + " --statistical");
  EXPECT_EQ(r.exitCode, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("  [FAIL] no overall bias:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(": BIASED\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\nFAILURE: biased\n"), std::string::npos) << r.out;

  // A equal to B: a pass, with a note that it is the same image.
  r = test::runGlint("diff " + q(dir + "/ref.exr") + " " + q(dir + "/ref.exr") + " --statistical");
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("  Note: mean z^2 = 0: A equals B exactly"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("error cap: none (--max-error sets one); no pixel is over |z| = 4.65\n"),
            std::string::npos)
      << r.out;
}

// FLIP: LDR for display images, HDR for EXRs, never one of each; --flip-max fails.
TEST(DiffCommand, FlipReportsAPerceptualDifference) {
  Images im = makeImages("DiffCommand.FlipReportsAPerceptualDifference");
  test::CommandResult r =
      test::runGlint("diff " + q(im.off) + " " + q(im.ref) + " --flip --json --fail 1");
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("flip").at("mode"), "hdr");
  EXPECT_GT(j.at("flip").at("mean").get<double>(), 0);
  EXPECT_EQ(j.at("flip").at("max_pixel"), nlohmann::json::array({3, 0}));

  r = test::runGlint("diff " + q(im.same) + " " + q(im.ref) + " --flip --json");
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out).at("flip").at("mean").get<double>(), 0);

  // Display-referred copies: LDR-FLIP, and a map.
  for (const char* name : {"off", "ref"}) {
    r = test::runGlint("tonemap " + q(im.dir + "/" + name + ".exr") + " -o " +
                       q(im.dir + "/" + name + ".png") + " --quiet");
    ASSERT_EQ(r.exitCode, 0) << r.err;
  }
  r = test::runGlint("diff " + q(im.dir + "/off.png") + " " + q(im.dir + "/ref.png") +
                     " --fail 1 --json --flip-map " + q(im.dir + "/flip.png"));
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out).at("flip").at("mode"), "ldr");
  EXPECT_TRUE(std::filesystem::exists(im.dir + "/flip.png"));

  r = test::runGlint("diff " + q(im.dir + "/off.png") + " " + q(im.ref) + " --flip");
  EXPECT_EQ(r.exitCode, 2) << r.out << r.err;

  r = test::runGlint("diff " + q(im.off) + " " + q(im.ref) + " --fail 1 --flip-max 0.0001");
  EXPECT_EQ(r.exitCode, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("FLIP"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace glint
