// Tests for `glint render --time-limit / --noise-target`, Ctrl-C (SIGINT, SIGTERM) and
// `--resume` continuing a render: through the real executable and signals.
#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "apps/interrupt.h"
#include "image/io.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace glint {
namespace {

// A small path-traced Cornell box: a pass at 1 spp takes a few milliseconds.
std::string writeScene(const std::string& dir, int size = 24) {
  const std::string path = dir + "/box.json";
  std::ofstream(path) << test::cornellBoxJson(size, 4, 3, R"({"type": "path"})");
  return path;
}

struct Exr {
  ImageMetadata meta;
  std::string stop;
  double error = -1;
  std::vector<float> pixels;
  std::vector<std::string> channels;
};

Exr readExrFile(const std::string& path) {
  Exr r;
  auto in = OIIO::ImageInput::open(path);
  if (!in) return r;
  const OIIO::ImageSpec& spec = in->spec();
  r.meta.spp = spec.get_int_attribute("glint:spp");
  r.stop = spec.get_string_attribute("glint:stop");
  if (const OIIO::ParamValue* e = spec.find_attribute("glint:error", OIIO::TypeDesc::DOUBLE))
    r.error = e->get<double>();
  r.channels = spec.channelnames;
  r.pixels.resize(size_t(spec.image_pixels()) * size_t(spec.nchannels));
  in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, r.pixels.data());
  return r;
}

nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// A noise target stops on its own, says where, records it in the EXR and the statistics, and
// the image is exactly the render at the spp it reports (on another thread count).
TEST(CliBudget, ANoiseTargetRenderIsReproducibleFromTheSppItReports) {
  const std::string dir = test::scratchDir("CliBudget.NoiseTarget");
  const std::string scene = writeScene(dir);
  auto r = test::runGlint("render " + scene + " --noise-target 0.08 --threads 2 -o " + dir +
                          "/n.exr --stats " + dir + "/n.json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("noise target reached"), std::string::npos) << r.err;
  const Exr budget = readExrFile(dir + "/n.exr");
  EXPECT_EQ(budget.stop, "noise-target");
  EXPECT_GT(budget.meta.spp, 16);
  EXPECT_GT(budget.error, 0);
  EXPECT_LE(budget.error, 0.08);
  const nlohmann::json stats = readJson(dir + "/n.json");
  EXPECT_EQ(stats["spp_reached"], budget.meta.spp);
  EXPECT_EQ(stats["stop"], "noise-target");
  EXPECT_DOUBLE_EQ(stats["estimated_error"].get<double>(), budget.error);
  EXPECT_TRUE(stats["spp"].is_null());  // no --spp: no cap
  EXPECT_EQ(stats["noise_target"], 0.08);

  r = test::runGlint("render " + scene + " --spp " + std::to_string(budget.meta.spp) +
                     " --threads 1 --quiet -o " + dir + "/s.exr");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const Exr fixed = readExrFile(dir + "/s.exr");
  EXPECT_EQ(fixed.stop, "spp");
  ASSERT_EQ(fixed.pixels.size(), budget.pixels.size());
  EXPECT_EQ(fixed.pixels, budget.pixels);  // determinism: exact by design
}

// A time limit always completes the first pass (1 spp) and stops before a pass that would
// not fit; --spp caps a budget.
TEST(CliBudget, ATimeLimitStopsAtAPassAndSppCapsIt) {
  const std::string dir = test::scratchDir("CliBudget.TimeLimit");
  const std::string scene = writeScene(dir);
  auto r =
      test::runGlint("render " + scene + " --time-limit 0.000001s --quiet -o " + dir + "/t.exr");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  Exr t = readExrFile(dir + "/t.exr");
  EXPECT_EQ(t.stop, "time-limit");
  EXPECT_EQ(t.meta.spp, 1);

  r = test::runGlint("render " + scene + " --time-limit 1h --spp 24 --quiet -o " + dir + "/c.exr");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  t = readExrFile(dir + "/c.exr");
  EXPECT_EQ(t.stop, "spp");
  EXPECT_EQ(t.meta.spp, 24);
}

// Ctrl-C (or Slurm's SIGTERM) writes the passes done, atomically, exits 128 + signal, and
// --resume continues the EXR to the spp asked for: what a fresh render at that spp gives.
TEST(CliBudget, AnInterruptedRenderIsWrittenAndResumeContinuesIt) {
  const std::string dir = test::scratchDir("CliBudget.Interrupt");
  const std::string scene = writeScene(dir);
  for (int sig : {SIGINT, SIGTERM}) {
    SCOPED_TRACE(sig == SIGINT ? "SIGINT" : "SIGTERM");
    const std::string out = dir + "/i.exr", png = dir + "/i.png";
    fs::remove(out);
    const int pid =
        test::startGlint("render " + scene + " --spp 2000000 --threads 2 -o " + out + " -o " + png,
                         dir + "/log", dir + "/log");
    ASSERT_GT(pid, 0);  // kill(-1, ...) would signal every process we may
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // some passes
    ::kill(pid, sig);
    EXPECT_EQ(test::waitGlint(pid), 128 + sig);
    const std::string log = test::slurp(dir + "/log");
    EXPECT_NE(log.find("interrupted: stopping and writing the passes done"), std::string::npos)
        << log;
    EXPECT_NE(log.find("--resume continues it"), std::string::npos) << log;
    const Exr partial = readExrFile(out);
    EXPECT_EQ(partial.stop, "interrupted");
    ASSERT_GE(partial.meta.spp, 1);
    ASSERT_LT(partial.meta.spp, 2000000);
    EXPECT_TRUE(fs::exists(png));
    for (const std::string& f : test::listFolder(dir))
      EXPECT_EQ(f.find(".tmp-"), std::string::npos) << "left behind: " << f;

    // Continue it to more spp than it has.
    const int target = partial.meta.spp + 40;
    auto r = test::runGlint("render " + scene + " --spp " + std::to_string(target) +
                            " --resume -o " + out + " -o " + png + " --stats " + dir + "/r.json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("continuing: " + out + ": interrupted at"), std::string::npos) << r.err;
    EXPECT_EQ(readJson(dir + "/r.json")["resumed_from_spp"], partial.meta.spp);
    const Exr continued = readExrFile(out);
    EXPECT_EQ(continued.stop, "spp");
    EXPECT_EQ(continued.meta.spp, target);

    r = test::runGlint("render " + scene + " --spp " + std::to_string(target) + " --quiet -o " +
                       dir + "/fresh.exr");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const Exr fresh = readExrFile(dir + "/fresh.exr");
    ASSERT_EQ(fresh.pixels.size(), continued.pixels.size());
    ASSERT_EQ(fresh.channels, continued.channels);
    const size_t nch = fresh.channels.size();
    for (size_t i = 0; i < fresh.pixels.size(); ++i) {
      const double a = continued.pixels[i], b = fresh.pixels[i];
      // Means to float rounding; the variance subtracts rebuilt sums, so a looser bound.
      const double rel = fresh.channels[i % nch].rfind("variance", 0) == 0 ? 1e-3 : 1e-5;
      ASSERT_LE(std::abs(a - b), rel * std::max(std::abs(b), 1e-3))
          << fresh.channels[i % nch] << " of pixel " << i / nch;
    }

    // Now complete: --resume does nothing and leaves the file alone.
    const auto before = fs::last_write_time(out);
    r = test::runGlint("render " + scene + " --spp " + std::to_string(target) + " --resume -o " +
                       out + " -o " + png);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("already complete"), std::string::npos) << r.err;
    EXPECT_EQ(fs::last_write_time(out), before);
  }
}

// --resume starts over, saying why, when the file is not a part of this render.
TEST(CliBudget, ResumeStartsOverWhenTheOutputIsAnotherRender) {
  const std::string dir = test::scratchDir("CliBudget.ResumeOther");
  const std::string scene = writeScene(dir);
  const std::string out = dir + "/o.exr";
  ASSERT_EQ(test::runGlint("render " + scene + " --spp 4 --seed 1 --quiet -o " + out).exitCode, 0);
  auto r = test::runGlint("render " + scene + " --spp 8 --seed 2 --resume -o " + out + " --stats " +
                          dir + "/s.json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("redoing: " + out + ": rendered with seed 1, not 2"), std::string::npos)
      << r.err;
  EXPECT_FALSE(readJson(dir + "/s.json").contains("resumed_from_spp"));
  EXPECT_EQ(readExrFile(out).meta.spp, 8);
}

// A noise target not met by an earlier, capped run is continued by --resume.
TEST(CliBudget, ResumeContinuesANoiseTargetNotYetMet) {
  const std::string dir = test::scratchDir("CliBudget.ResumeNoise");
  const std::string scene = writeScene(dir);
  const std::string out = dir + "/o.exr";
  auto r = test::runGlint("render " + scene + " --noise-target 0.06 --spp 16 --quiet -o " + out);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const Exr capped = readExrFile(out);
  ASSERT_EQ(capped.meta.spp, 16);
  ASSERT_GT(capped.error, 0.06);  // this scene needs more than 16 spp for 6%
  r = test::runGlint("render " + scene + " --noise-target 0.06 --resume -o " + out);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find("continuing: " + out), std::string::npos) << r.err;
  const Exr met = readExrFile(out);
  EXPECT_EQ(met.stop, "noise-target");
  EXPECT_LE(met.error, 0.06);
  EXPECT_GT(met.meta.spp, 16);
}

// The handlers themselves: the first signal only raises the flag; the second ends the process
// at once with 128 + signal.
TEST(InterruptGuard, TheFirstSignalAsksTheSecondQuits) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    app::InterruptGuard guard;
    ::raise(SIGINT);
    if (!guard.interrupted() || guard.signal() != SIGINT) ::_exit(3);
    ::raise(SIGINT);  // the second: _exit(130)
    ::_exit(4);
  }
  EXPECT_EQ(test::waitGlint(pid), 130);

  // Outside the guard the default action is back.
  const pid_t other = ::fork();
  if (other == 0) {
    { app::InterruptGuard guard; }
    ::raise(SIGTERM);
    ::_exit(5);
  }
  EXPECT_EQ(test::waitGlint(other), 1000 + SIGTERM);
}

}  // namespace
}  // namespace glint
