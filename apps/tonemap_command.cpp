// glint — `glint tonemap IN.exr|'IN_####.exr' -o OUT.png|'OUT_####.png'`: scene-linear EXR
// frames to display-referred images, as a separate step that can be re-run with other settings.
// With --sequence every frame shares one Ward scale, so an animation does not flicker.
#include <fmt/format.h>
#include <sys/wait.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/frames.h"
#include "image/color.h"
#include "image/input.h"
#include "image/output.h"
#include "image/tonemap.h"
#include "renderer/progress.h"
#include "scenes/load.h"

namespace fs = std::filesystem;

namespace glint::app {

namespace {

struct TonemapArgs {
  std::string input;
  std::optional<std::string> output;
  std::string op = "none";
  bool sequence = false;
  float ldmax = 100;
  float sceneLuminance = 100;
  float exposure = 0;
  std::string display, view;
  std::optional<std::string> frames;
  std::optional<std::string> mp4;
  double fps = 24;
  bool quiet = false;
  std::optional<std::string> scene;    // take the tone mapping settings from this scene
  std::optional<std::string> sidecar;  // its sidecar
};

std::string lowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// ---- ffmpeg ----------------------------------------------------------------------------------

std::optional<std::string> findOnPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (!path) return std::nullopt;
  std::string dirs = path;
  size_t start = 0;
  while (start <= dirs.size()) {
    size_t end = dirs.find(':', start);
    if (end == std::string::npos) end = dirs.size();
    std::string dir = dirs.substr(start, end - start);
    fs::path candidate = fs::path(dir.empty() ? "." : dir) / program;
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0)
      return candidate.string();
    start = end + 1;
  }
  return std::nullopt;
}

std::string shellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Pipes the PNGs (in order) into ffmpeg, which writes a temporary file renamed to `mp4` on
// success. A pipe rather than ffmpeg's own %0Nd input, because --frames with a step or missing
// frames leave gaps that the image2 demuxer stops at. Throws OutputError.
void encodeMp4(const std::string& ffmpeg, const std::vector<std::string>& pngs,
               const std::string& mp4, double fps) {
  fs::path target(mp4);
  fs::path temp =
      target.parent_path() / fmt::format(".{}.tmp-{}.mp4", target.stem().string(), ::getpid());
  // yuv420p (what players accept) needs even sizes: pad by one pixel where needed.
  std::string command = fmt::format(
      "{} -hide_banner -loglevel error -y -f image2pipe -framerate {} -c:v png -i - "
      "-vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -pix_fmt yuv420p {}",
      shellQuote(ffmpeg), fps, shellQuote(temp.string()));
  auto fail = [&](const std::string& why) {
    std::error_code ec;
    fs::remove(temp, ec);
    return OutputError(fmt::format("cannot write '{}': {}", mp4, why));
  };
  // A crashed ffmpeg must be an error message, not a SIGPIPE that kills glint.
  auto oldHandler = std::signal(SIGPIPE, SIG_IGN);
  std::FILE* pipe = ::popen(command.c_str(), "w");
  if (!pipe) {
    std::signal(SIGPIPE, oldHandler);
    throw fail("cannot start ffmpeg");
  }
  bool written = true;
  for (const std::string& png : pngs) {
    std::ifstream in(png, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    if (!in.good() && !in.eof()) written = false;
    if (std::fwrite(bytes.data(), 1, bytes.size(), pipe) != bytes.size()) written = false;
    if (!written) break;
  }
  int status = ::pclose(pipe);
  std::signal(SIGPIPE, oldHandler);
  if (!written || status != 0)
    throw fail(fmt::format("ffmpeg failed (exit status {})",
                           WIFEXITED(status) ? WEXITSTATUS(status) : -1));
  std::error_code ec;
  fs::rename(temp, target, ec);
  if (ec) throw fail(ec.message());
}

// ---- the command -----------------------------------------------------------------------------

struct Job {
  std::vector<std::string> inputs, outputs;  // one pair per frame
  ToneMapSettings tonemap;
  std::optional<std::string> ffmpeg;
};

// Everything that can be checked without reading pixels; throws InputError (ColorError among them).
Job plan(const TonemapArgs& args) {
  Job job;
  if (!isKnownToneMapOperator(args.op))
    throw InputError(
        fmt::format("unknown tone-map operator '{}'; available: 'none', 'ward'", args.op));
  if (args.sequence && args.op != "ward")
    throw InputError("--sequence shares Ward's scale between frames; it needs --operator ward");
  job.tonemap.op = args.op;
  job.tonemap.exposure = args.exposure;
  job.tonemap.wardDisplayMax = args.ldmax;
  job.tonemap.wardSceneLuminance = args.sceneLuminance;
  auto [display, view] = resolveDisplayView(args.display, args.view);
  job.tonemap.display = display;
  job.tonemap.view = view;

  FramePattern in = parseFramePattern(args.input);
  std::string outText =
      args.output ? *args.output : fs::path(args.input).replace_extension(".png").string();
  FramePattern out = parseFramePattern(outText);
  if (in.isPattern() != out.isPattern())
    throw InputError(fmt::format(
        "mismatched patterns: input '{}' {} a '#' frame pattern but output '{}' {}", args.input,
        in.isPattern() ? "is" : "is not", outText, out.isPattern() ? "is" : "is not"));
  if (lowerExtension(args.input) != ".exr")
    throw InputError(
        fmt::format("'{}': tonemap reads scene-linear OpenEXR (.exr) images", args.input));
  std::string why;
  if (!isSupportedOutput(outText, &why)) throw InputError(why);
  if (lowerExtension(outText) == ".exr")
    throw InputError(fmt::format(
        "'{}': tone-mapped output is display-referred (.png, .jpg, .tif); EXR stays scene-linear",
        outText));
  if (args.frames && !in.isPattern())
    throw InputError(fmt::format("--frames needs a '#' frame pattern, not '{}'", args.input));

  if (args.mp4) {
    if (lowerExtension(outText) != ".png")
      throw InputError(fmt::format("--mp4 encodes the PNG frames; '{}' is not .png", outText));
    if (lowerExtension(*args.mp4) != ".mp4")
      throw InputError(fmt::format("--mp4 '{}': the file name must end in .mp4", *args.mp4));
    job.ffmpeg = findOnPath("ffmpeg");
    if (!job.ffmpeg)
      throw InputError(
          "ffmpeg not found on PATH; install it (apt install ffmpeg) or encode the PNGs "
          "yourself");
  }

  if (in.isPattern()) {
    std::optional<FrameRange> range;
    if (args.frames) range = parseFrameRange(*args.frames);
    for (int f : findFrames(in, range)) {
      job.inputs.push_back(in.path(f));
      job.outputs.push_back(out.path(f));
    }
  } else {
    std::error_code ec;
    if (!fs::exists(args.input, ec)) throw InputError(fmt::format("{}: no such file", args.input));
    job.inputs.push_back(args.input);
    job.outputs.push_back(outText);
  }
  return job;
}

// Ward's statistic and scale, and how many black pixels the statistic left out (tonemap.h: it
// adapts to the lit pixels only).
std::string describeWard(const ToneMapSettings& tm, const LogLuminanceStats& stats) {
  const double lwa = stats.logAverage();
  std::string lit;
  if (stats.dark > 0 && stats.count > 0)
    lit = fmt::format(" over the {} lit pixels ({} black left out)", stats.count, stats.dark);
  return fmt::format(
      "log-average luminance {:.6g} cd/m²{}, Ward scale factor {:.6g}, scene-linear × {:.6g}", lwa,
      lit, wardScaleFactor(lwa, tm.wardDisplayMax), toneMapScale(tm, lwa));
}

// The first error of a parallel pass in frame order, whichever thread met it first.
void rethrowFirst(const std::vector<std::exception_ptr>& errors) {
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);
}

// Throws InputError (ImageReadError, ColorError) for bad input and OutputError for a failed
// write: main.cpp decides the exit code.
void runTonemap(const TonemapArgs& args) {
  const Job job = plan(args);
  const ToneMapSettings& tm = job.tonemap;
  const size_t n = job.inputs.size();
  // An error ends the run: unwinding ends the bar's line before main prints the message.
  ProgressBar progress("tonemap", 2 * n, !args.quiet && isTerminal(stderr));

  // Pass 1 reads every frame before any output is written: a missing or broken frame stops
  // the run with nothing changed, and the sequence statistic needs every frame anyway. Frames
  // are read again in pass 2 rather than kept, so a long sequence needs memory for one frame.
  // Frames are read and written in parallel (decoding and compressing dominate); each frame's
  // work is its own, and the first error in frame order is the one reported.
  std::vector<LogLuminanceStats> stats(n);
  std::vector<std::exception_ptr> readErrors(n);
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    try {
      Film film = readExr(job.inputs[i]);
      stats[i].add(film.color, tm);
    } catch (const ImageReadError&) {
      readErrors[i] = std::current_exception();
    }
    progress.advance();
  });
  rethrowFirst(readErrors);

  LogLuminanceStats sequence = sequenceStats(stats);
  std::vector<std::string> report;
  if (tm.op == "ward") {
    if (args.sequence) {
      size_t black = size_t(std::count_if(stats.begin(), stats.end(),
                                          [](const LogLuminanceStats& s) { return s.allBlack(); }));
      std::string left = black == 0 || black == n ? ""
                                                  : fmt::format(", {} all-black frame{} left out",
                                                                black, black == 1 ? "" : "s");
      report.push_back(fmt::format("sequence of {} frame{}{}: {}", n, n == 1 ? "" : "s", left,
                                   describeWard(tm, sequence)));
    } else {
      for (size_t i = 0; i < n; ++i)
        report.push_back(fmt::format("{}: {}", job.inputs[i], describeWard(tm, stats[i])));
    }
  }

  if (!job.outputs.empty()) createOutputFolder(job.outputs.front());
  // An ImageReadError (a frame changed since pass 1), ColorError or OutputError, per frame.
  std::vector<std::exception_ptr> writeErrors(n);
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    try {
      ImageMetadata meta;
      Film film = readExr(job.inputs[i], &meta);
      double lwa = args.sequence ? sequence.logAverage() : stats[i].logAverage();
      writeDisplayImage(job.outputs[i], film, tm, lwa, meta);
    } catch (const std::exception&) {
      writeErrors[i] = std::current_exception();
    }
    progress.advance();
  });
  rethrowFirst(writeErrors);
  progress.finish();
  if (args.mp4) encodeMp4(*job.ffmpeg, job.outputs, *args.mp4, args.fps);

  if (!args.quiet) {
    for (const std::string& line : report) fmt::print("{}\n", line);
    if (tm.op == "ward")
      for (size_t i = 0; i < n; ++i)
        if (stats[i].nonFinite)
          fmt::print(stderr, "glint: warning: {}: {} NaN/Inf pixels left out of the statistic\n",
                     job.inputs[i], stats[i].nonFinite);
    fmt::print(stderr, "glint: wrote {}{}{}\n", job.outputs.front(),
               n > 1 ? fmt::format(" … {} ({} frames)", job.outputs.back(), n) : "",
               args.mp4 ? " and " + *args.mp4 : "");
  }
}

}  // namespace

// --scene: the tone mapping the scene asks for (its render.tonemap) for every setting not given
// on the command line, so a farm's tone-mapping job looks like `glint render -o x.png` would.
// Throws SceneError.
void applySceneSettings(const CLI::App& cmd, TonemapArgs* args) {
  const ToneMapSettings tm = SceneLoader(*args->scene, args->sidecar).at().render.tonemap;
  if (!cmd.count("--operator")) args->op = tm.op;
  if (!cmd.count("--ldmax")) args->ldmax = tm.wardDisplayMax;
  if (!cmd.count("--scene-luminance")) args->sceneLuminance = tm.wardSceneLuminance;
  if (!cmd.count("--exposure")) args->exposure = tm.exposure;
  if (!cmd.count("--display")) args->display = tm.display;
  if (!cmd.count("--view")) args->view = tm.view;
}

void addTonemapCommand(CLI::App& app) {
  auto args = std::make_shared<TonemapArgs>();
  CLI::App* cmd = app.add_subcommand(
      "tonemap", "tone-map scene-linear EXR frames to PNG/JPEG/TIFF (one file or a sequence)");
  cmd->add_option("input", args->input,
                  "an .exr file, or a frame pattern such as 'out/frame_####.exr'")
      ->required();
  cmd->add_option("-o,--output", args->output,
                  "output image or pattern (default: the input with .png); a pattern for a "
                  "pattern input");
  cmd->add_option("--operator", args->op, "tone-map operator: none | ward")->capture_default_str();
  cmd->add_flag("--sequence", args->sequence,
                "one Ward scale for all frames (no flicker); otherwise one per frame");
  cmd->add_option("--ldmax", args->ldmax, "Ward: display maximum luminance, cd/m²")
      ->capture_default_str()
      ->check(numberIn({.gt = 0}));
  cmd->add_option("--scene-luminance", args->sceneLuminance,
                  "Ward: luminance of scene-linear 1.0, cd/m²")
      ->capture_default_str()
      ->check(numberIn({.gt = 0}));
  cmd->add_option("--exposure", args->exposure, "exposure in stops (EV), before tone mapping")
      ->capture_default_str();
  cmd->add_option("--display", args->display, "OCIO display (default: the config's)");
  cmd->add_option("--view", args->view,
                  "OCIO view, e.g. Standard, Raw, 'ACES 1.0 SDR-video' (default: the display's)");
  cmd->add_option("--frames", args->frames, "only frames A-B[:STEP] of a pattern");
  CLI::Option* mp4 =
      cmd->add_option("--mp4", args->mp4, "also encode the PNG frames to this .mp4 (needs ffmpeg)");
  cmd->add_option("--fps", args->fps, "frame rate of --mp4")
      ->capture_default_str()
      ->check(numberIn({.gt = 0}))
      ->needs(mp4);
  cmd->add_flag("-q,--quiet", args->quiet, "no progress bar, statistics or summary");
  CLI::Option* scene = cmd->add_option(
      "--scene", args->scene,
      "take the settings not given here (operator, Ward luminances, exposure, display, view) "
      "from this scene's render.tonemap");
  cmd->add_option("--sidecar", args->sidecar, "the sidecar of --scene's glTF")->needs(scene);
  cmd->callback([args, cmd] {
    if (args->scene) applySceneSettings(*cmd, args.get());
    runTonemap(*args);
  });
}

}  // namespace glint::app
