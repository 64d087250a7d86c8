// glint — `glint render`: load, build, render, write images and statistics.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/frames.h"
#include "apps/interrupt.h"
#include "apps/resume.h"
#include "apps/tiles.h"
#include "image/color.h"
#include "image/output.h"
#include "image/tonemap.h"
#include "materials/image_texture.h"
#include "renderer/progress.h"
#include "renderer/render.h"
#include "renderer/subdivide.h"
#include "renderer/volume.h"
#include "scenes/build.h"
#include "scenes/load.h"

namespace glint::app {

namespace {

struct RenderArgs {
  std::string scene;
  std::vector<std::string> outputs;
  std::optional<std::string> sidecar;
  std::optional<std::string> statsPath;
  std::optional<std::string> frames;  // "A-B[:STEP]"
  std::optional<double> fps;
  std::optional<double> time;  // a single frame's scene time, seconds
  bool resume = false;
  bool listMissing = false;
  std::optional<std::string> crop;       // "X0,Y0,X1,Y1"
  std::optional<std::string> tile;       // "I/N"
  std::optional<std::string> timeLimit;  // "30s", "2m", "1h30m", "90"
  double timeLimitSeconds = 0;           // parsed by runRender
  std::optional<double> noiseTarget;     // estimated relative error
  SceneOverrides overrides;
  bool quiet = false;
  const std::atomic<bool>* cancel = nullptr;  // set by runRender: Ctrl-C
};

// The spp cap of a budgeted render given no --spp: none, in effect (glint:spp is an int).
constexpr uint32_t kNoSppCap = 0x7fffffff;

// "30s", "2m", "1.5h", "1h30m", "90" (seconds) as seconds. Throws InputError.
double parseDuration(const std::string& text) {
  const auto bad = [&] {
    return InputError("--time-limit '" + text +
                      "': need a duration > 0 such as 30s, 2m, 1.5h, 1h30m or 90 (seconds)");
  };
  double total = 0;
  size_t i = 0;
  bool any = false;
  while (i < text.size()) {
    size_t used = 0;
    double value;
    try {
      value = std::stod(text.substr(i), &used);
    } catch (const std::exception&) {
      throw bad();
    }
    if (!(value >= 0) || !std::isfinite(value) || text[i] == '+' || text[i] == '-') throw bad();
    i += used;
    double unit = 1;
    if (i < text.size()) {
      switch (text[i]) {
        case 's':
          unit = 1;
          break;
        case 'm':
          unit = 60;
          break;
        case 'h':
          unit = 3600;
          break;
        default:
          throw bad();
      }
      ++i;
    } else if (any) {
      throw bad();  // "1h30": 30 what?
    }
    total += value * unit;
    any = true;
  }
  if (!any || !(total > 0)) throw bad();
  return total;
}

bool hasBudget(const RenderArgs& args) { return args.timeLimit || args.noiseTarget; }

// When this render stops: --spp, or a budget (capped by --spp only when it is given).
StopRule stopRuleFor(const RenderArgs& args, const SceneDescription& desc) {
  const RenderBudget budget{.timeLimit = args.timeLimitSeconds,
                            .noiseTarget = args.noiseTarget.value_or(0),
                            .sppAsked = args.overrides.spp.has_value()};
  return glint::stopRuleFor(desc.render, budget, args.cancel);
}

// The process's resident memory now and at its peak, in MiB, from /proc/self/status (Linux);
// 0 where that cannot be read.
std::pair<double, double> residentMemoryMiB() {
  std::ifstream status("/proc/self/status");
  double now = 0, peak = 0;
  for (std::string line; std::getline(status, line);) {
    auto kib = [&](const char* key) {
      return line.rfind(key, 0) == 0 ? std::strtod(line.c_str() + std::strlen(key), nullptr) / 1024
                                     : -1.0;
    };
    if (double v = kib("VmRSS:"); v >= 0) now = v;
    if (double v = kib("VmHWM:"); v >= 0) peak = v;
  }
  return {now, peak};
}

// One rendered frame, for the statistics.
struct FrameRecord {
  int frame = 0;
  ProgressiveResult result;  // spp reached, why it stopped, estimated error
  PixelWindow window;        // the pixels rendered (the whole frame, or --crop / --tile)
  uint32_t resumedSpp = 0;   // continued from an earlier output at this spp (0: fresh)
  double time = 0;
  double loadSeconds = 0;  // reading the scene files (single renders; 0 for sequences)
  BuildTimings build;
  RenderStats stats;
  std::vector<Integrator::SetupStat> integratorSetup;  // e.g. instant radiosity's VPLs
  int subdivide = 0;  // levels of anti-aliasing by subdivision (0: whole-pixel samples)
};

// What one render measured: its time, timings, rays and dropped samples.
nlohmann::json frameJson(const FrameRecord& r) {
  nlohmann::json j;
  j["time"] = r.time;
  if (r.loadSeconds > 0) j["load_seconds"] = r.loadSeconds;
  j["build_seconds"] = r.build.totalSeconds;
  j["accel_build_seconds"] = r.build.acceleratorSeconds;
  j["render_seconds"] = r.stats.renderSeconds;
  j["rays"] = {{"camera", r.stats.rays.camera},
               {"shadow", r.stats.rays.shadow},
               {"secondary", r.stats.rays.secondary},
               {"total", r.stats.rays.total()}};
  j["mrays_per_second"] =
      r.stats.renderSeconds > 0 ? double(r.stats.rays.total()) / r.stats.renderSeconds * 1e-6 : 0.0;
  j["nonfinite_samples"] = r.stats.nonfiniteSamples;
  j["brightest_sample"] = r.stats.brightestSample;
  j["mean_spp"] = r.stats.meanSpp;
  j["spp_reached"] = r.result.spp;
  j["stop"] = std::string(stopReasonName(r.result.reason));
  j["estimated_error"] = r.result.error;
  j["passes"] = r.result.passes;
  if (r.resumedSpp) j["resumed_from_spp"] = r.resumedSpp;
  // The whole process's, measured after the frame (decoded images, BVHs, film, libraries).
  const auto [resident, peak] = residentMemoryMiB();
  j["resident_mib"] = resident;
  j["peak_resident_mib"] = peak;
  // Media tracking's collisions, summed over the process so far (a single render: its own).
  if (const TrackingCounts t = trackingCounts(); t.tentative + t.ratioTentative > 0)
    j["tracking_collisions"] = {{"delta_tentative", t.tentative},
                                {"delta_real", t.real},
                                {"ratio_tentative", t.ratioTentative},
                                {"null_per_real", t.nullPerReal()}};
  if (!r.integratorSetup.empty()) {
    nlohmann::json setup = nlohmann::json::object();
    for (const Integrator::SetupStat& s : r.integratorSetup) setup[s.name] = s.value;
    j["integrator_setup"] = setup;
  }
  return j;
}

// What the scene and settings are: the same for every frame of a sequence.
nlohmann::json sceneJson(const RenderArgs& args, const SceneDescription& desc,
                         const RenderScene& scene, int threads) {
  nlohmann::json j;
  j["scene"] = args.scene;
  j["accel"] = desc.render.accel;
  j["integrator"] =
      integratorName(resolveIntegrator(scene, desc.render.integrator));  // "auto" resolved
  j["integrator_requested"] = desc.render.integrator.type;
  j["camera"] = scene.cameraName();
  j["width"] = scene.camera().width();
  j["height"] = scene.camera().height();
  // The spp asked for; with a budget and no --spp there is no cap (spp_reached says where the
  // render stopped).
  j["spp"] = hasBudget(args) && !args.overrides.spp ? nlohmann::json(nullptr)
                                                    : nlohmann::json(desc.render.spp);
  if (args.timeLimit) j["time_limit_seconds"] = args.timeLimitSeconds;
  if (args.noiseTarget) j["noise_target"] = *args.noiseTarget;
  if (desc.render.adaptive.threshold > 0 || desc.render.adaptive.contrast > 0 ||
      desc.render.adaptive.subdivide > 0)
    j["adaptive"] = {{"threshold", desc.render.adaptive.threshold},
                     {"contrast", desc.render.adaptive.contrast},
                     {"min_spp", desc.render.adaptive.minSpp},
                     {"subdivide", desc.render.adaptive.subdivide},
                     {"jitter", desc.render.adaptive.jitter}};
  j["seed"] = desc.render.seed;
  j["threads"] = threads;
  j["triangles"] = scene.geometry().instancedTriangleCount();
  j["triangles_stored"] = scene.geometry().uniqueTriangleCount();
  // Everything the accelerator intersects: placed triangles plus analytic objects (a CSG tree
  // counts as one primitive: it is one Embree user primitive).
  j["primitives"] =
      scene.geometry().instancedTriangleCount() + scene.geometry().shapeInstanceCount();
  j["analytic_objects"] = scene.geometry().shapeInstanceCount();
  j["instances"] = scene.geometry().instances.size();
  j["lights"] = scene.lights().size();
  j["effects"] = scene.features().names();
  if (scene.images()) {
    // The images glint holds decoded (MIP pyramids); those in OpenImageIO's cache not counted.
    size_t bytes = 0;
    for (TextureImages::Handle h : scene.images()->handles())
      bytes += scene.images()->residentBytes(h);
    j["texture_mib"] = double(bytes) / (1024.0 * 1024.0);
  }
  return j;
}

// The scene as it is at `time` (sidecar keyframes evaluated; unset: the file's render.time),
// with the command line applied.
SceneDescription loadAt(const RenderArgs& args, const SceneLoader& loader,
                        std::optional<double> time) {
  SceneDescription desc = loader.at(time);
  if (args.fps) desc.render.fps = *args.fps;
  args.overrides.apply(&desc);
  return desc;
}

// Display settings are only used when writing, after the render: check them before it.
// Throws SceneError.
void checkDisplaySettings(const SceneDescription& desc, const std::vector<std::string>& outputs) {
  bool displayReferred = std::any_of(outputs.begin(), outputs.end(), [](const std::string& o) {
    return std::filesystem::path(o).extension() != ".exr";
  });
  if (!displayReferred) return;
  const SourceLocation where{desc.file, "/render/tonemap"};
  if (!isKnownToneMapOperator(desc.render.tonemap.op))
    throw SceneError(where, "unknown tone mapping operator '" + desc.render.tonemap.op + "'");
  try {
    resolveDisplayView(desc.render.tonemap.display, desc.render.tonemap.view);
  } catch (const ColorError& e) {  // OpenColorIO's config does not know the display or view
    throw SceneError(where, e.what());
  }
}

// The pixels --crop or --tile ask for in a width x height frame (the whole frame without them).
// Throws InputError for a tile count above the height (render() checks a crop).
PixelWindow requestedWindow(const RenderArgs& args, int width, int height) {
  if (args.tile) {
    const TileSpec t = parseTileSpec(*args.tile);
    return tileWindow(width, height, t.index, t.count);
  }
  if (args.crop) return parseCropWindow(*args.crop);
  return PixelWindow{0, 0, width, height};
}

// Renders one built scene (continuing `partial` when given) and writes `outputs`. Returns false
// when Ctrl-C stopped it before its first pass: nothing was written.
bool renderAndWrite(const RenderArgs& args, const SceneDescription& desc, const RenderScene& scene,
                    const std::vector<std::string>& outputs, bool tileProgress, FrameRecord* record,
                    const std::optional<PartialRender>& partial = std::nullopt) {
  Film film;
  const std::string integrator = integratorName(resolveIntegrator(scene, desc.render.integrator));
  StopRule rule = stopRuleFor(args, desc);
  const PartialRender* from = nullptr;
  if (partial && partial->integrator == integrator) {
    from = &*partial;
    record->resumedSpp = partial->spp;
    // A time limit counts the time the earlier run already spent.
    if (rule.timeLimit > 0) rule.timeLimit = std::max(1e-3, rule.timeLimit - partial->seconds);
  } else if (partial && !args.quiet) {
    std::fprintf(stderr, "glint: %s: rendered with the %s integrator, not %s: starting over\n",
                 partial->path.c_str(), partial->integrator.c_str(), integrator.c_str());
  }
  namingFile(args.scene, "render failed", [&] {
    auto integ = makeIntegrator(scene, desc.render);
    record->integratorSetup = integ->setupStats();
    RenderOptions options;
    options.threads = desc.render.threads;
    options.progress = tileProgress;
    // Arguments were checked in runRender; whether the window fits is known only now.
    record->window = requestedWindow(args, scene.camera().width(), scene.camera().height());
    record->subdivide = desc.render.adaptive.subdivide;
    if (args.crop || args.tile) options.crop = record->window;
    film = renderUntil(scene, *integ, desc.render, options, rule, &record->stats, &record->result,
                       from ? &from->film : nullptr, from ? from->spp : 0);
  });
  if (record->result.spp == 0) return false;  // interrupted before a pass completed
  const ImageMetadata meta =
      renderMetadata(args.scene, desc.render, integrator, record->result,
                     record->stats.renderSeconds + (from ? from->seconds : 0));
  for (const std::string& out : outputs) writeImage(out, film, desc.render, meta);
  return true;
}

void printSummary(const std::vector<std::string>& outputs, const RenderScene& scene,
                  const FrameRecord& record) {
  const RenderStats& stats = record.stats;
  double mrays =
      stats.renderSeconds > 0 ? double(stats.rays.total()) / stats.renderSeconds * 1e-6 : 0;
  std::string names;
  for (const std::string& out : outputs) names += (names.empty() ? "" : ", ") + out;
  std::string dropped = stats.nonfiniteSamples ? ", " + std::to_string(stats.nonfiniteSamples) +
                                                     " NaN/Inf samples dropped"
                                               : "";
  // How it ended, when that is not simply the spp asked for.
  const ProgressiveResult& r = record.result;
  std::string ended;
  if (record.resumedSpp) ended += fmt::format(", continued from {} spp", record.resumedSpp);
  if (r.reason == StopReason::TimeLimit) ended += ", time limit reached";
  if (r.reason == StopReason::NoiseTarget) ended += ", noise target reached";
  if (r.reason == StopReason::Interrupted) ended += ", interrupted: --resume continues it";
  // A crop or tile says which pixels of which frame it holds.
  const int w = scene.camera().width(), h = scene.camera().height();
  const std::string size =
      record.window == PixelWindow{0, 0, w, h}
          ? fmt::format("{}x{}", w, h)
          : fmt::format("{}x{} pixels {},{}..{},{} of the {}x{} frame", record.window.width(),
                        record.window.height(), record.window.x0, record.window.y0,
                        record.window.x1, record.window.y1, w, h);
  // One sample per pixel has no variance: no estimate. A subdivided pixel is a quadrature, not
  // a mean of samples: it says how many looks it took instead.
  const std::string sampling =
      record.subdivide > 0
          ? fmt::format("subdivision {}, {:.2f} looks per pixel", record.subdivide, stats.meanSpp)
          : fmt::format("{} spp", r.spp) +
                (r.error > 0 ? fmt::format(", estimated error {:.2g}%", 100 * r.error) : "");
  std::fprintf(stderr, "glint: wrote %s (%s, %s, %.2f s, %.1f Mrays/s%s%s)\n", names.c_str(),
               size.c_str(), sampling.c_str(), stats.renderSeconds, mrays, dropped.c_str(),
               ended.c_str());
}

// What --resume found for one frame's outputs.
struct ResumePlan {
  std::vector<std::pair<std::string, std::string>> incomplete;  // output, why: still to write
  std::optional<PartialRender> partial;  // the furthest EXR output to continue from
};

ResumePlan planResume(const RenderArgs& args, const SceneDescription& desc,
                      const std::vector<std::string>& outputs) {
  ResumePlan plan;
  ExpectedImage expected{.scene = args.scene,
                         .spp = int(stopRuleFor(args, desc).maxSpp),
                         .seed = desc.render.seed,
                         .time = desc.render.time,
                         .budget = hasBudget(args),
                         .noiseTarget = args.noiseTarget.value_or(0)};
  imageSize(desc, &expected.fullWidth, &expected.fullHeight);
  const PixelWindow w = requestedWindow(args, expected.fullWidth, expected.fullHeight);
  expected.x0 = w.x0, expected.y0 = w.y0;
  expected.width = w.width(), expected.height = w.height();
  for (const std::string& out : outputs)
    if (std::string why = whyIncomplete(out, expected); !why.empty())
      plan.incomplete.emplace_back(out, why);
  // A subdivided render is one pass: an unfinished one is rendered again, not continued.
  if (plan.incomplete.empty() || desc.render.adaptive.subdivide > 0) return plan;
  for (const std::string& out : outputs) {
    std::optional<PartialRender> p = continuableRender(out, expected, nullptr);
    if (p && (!plan.partial || p->spp > plan.partial->spp)) plan.partial = std::move(p);
  }
  return plan;
}

// Tells what --resume does with a frame's incomplete outputs.
void reportResume(const ResumePlan& plan, const std::string& frameLabel) {
  for (const auto& [out, why] : plan.incomplete)
    if (why != "missing")
      std::fprintf(stderr, "glint: %s%s: %s: %s\n", frameLabel.c_str(),
                   plan.partial && plan.partial->path == out ? "continuing" : "redoing",
                   out.c_str(), why.c_str());
}

// Checks the formats (InputError) and creates missing output folders (OutputError).
void checkOutputs(const std::vector<std::string>& outputs) {
  for (const std::string& out : outputs) {
    std::string why;
    if (!isSupportedOutput(out, &why)) throw InputError(out + ": " + why);
    createOutputFolder(out);
  }
}

void runSingle(const RenderArgs& args, const std::vector<std::string>& outputs) {
  SceneDescription desc;
  RenderScene scene;
  FrameRecord record;
  ResumePlan plan;
  namingFile(args.scene, "cannot build the scene", [&] {
    const auto start = std::chrono::steady_clock::now();
    SceneLoader loader(args.scene, args.sidecar);
    desc = loadAt(args, loader, args.time);
    record.loadSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    record.time = desc.render.time;
    if (args.resume) plan = planResume(args, desc, outputs);
  });
  if (args.resume) {
    if (plan.incomplete.empty()) {
      if (!args.quiet) std::fprintf(stderr, "glint: outputs already complete: nothing to do\n");
      return;
    }
    if (!args.quiet) reportResume(plan, "");
  }
  namingFile(args.scene, "cannot build the scene",
             [&] { scene = buildRenderScene(desc, &record.build); });
  checkDisplaySettings(desc, outputs);
  if (!args.quiet)
    for (const std::string& w : desc.warnings)
      std::fprintf(stderr, "glint: warning: %s\n", w.c_str());
  if (!renderAndWrite(args, desc, scene, outputs, !args.quiet && isTerminal(stderr), &record,
                      plan.partial)) {
    std::fprintf(stderr, "glint: interrupted before the first pass finished: nothing written\n");
    return;
  }
  if (args.statsPath)
    writeTextAtomically(*args.statsPath, [&] {
      nlohmann::json j = sceneJson(args, desc, scene, record.stats.threads);
      j.update(frameJson(record));
      return j.dump(2) + "\n";
    }());
  if (!args.quiet) printSummary(outputs, scene, record);
}

// A sequence: frame f at time f / fps, one set of outputs per frame from the '#' patterns.
// Frames are independent renders, so --resume can skip every frame whose outputs are all
// complete (whyIncomplete: written atomically, for this render, checksum intact) and redo the
// rest; --list-missing only prints the frames --resume would render.
void runSequence(const RenderArgs& args, const std::vector<std::string>& patterns) {
  const std::vector<int> frames = parseFrameRange(*args.frames).frames();
  std::vector<FramePattern> outputPatterns;
  for (const std::string& p : patterns) outputPatterns.push_back(parseFramePattern(p));
  if (frames.size() > 1)
    for (const FramePattern& p : outputPatterns)
      if (!p.isPattern())
        throw InputError("-o " + p.text + ": a sequence of " + std::to_string(frames.size()) +
                         " frames needs a '#' run for the frame number, e.g. frame_####.exr");
  if (args.fps && !(*args.fps > 0)) throw InputError("--fps must be > 0");

  // The files are read once; each frame re-evaluates the sidecar at its time. fps may come
  // from the sidecar: read it before deciding the frames' times.
  std::optional<SceneLoader> loader;
  double fps = 0;
  namingFile(args.scene, "cannot build the scene", [&] {
    loader.emplace(args.scene, args.sidecar);
    fps = args.fps ? *args.fps : loader->at().render.fps;
  });

  const bool terminal = !args.quiet && !args.listMissing && isTerminal(stderr);
  // An error ends the run: unwinding ends the bar's line before main prints the message.
  ProgressBar progress("frames", frames.size(), terminal);
  std::vector<FrameRecord> records;
  nlohmann::json first;  // scene-wide statistics, from the first rendered frame
  int skipped = 0;
  bool warned = false;
  // The images decoded for one frame serve the next ones (the files are read once).
  std::shared_ptr<TextureImages> images;
  for (int frame : frames) {
    std::vector<std::string> outputs;
    for (const FramePattern& p : outputPatterns) outputs.push_back(p.path(frame));
    SceneDescription desc;
    FrameRecord record;
    record.frame = frame;
    record.time = double(frame) / fps;
    ResumePlan plan;
    namingFile(args.scene, "cannot build the scene", [&] {
      desc = loadAt(args, *loader, record.time);
      if (args.resume || args.listMissing) plan = planResume(args, desc, outputs);
    });
    if (args.listMissing) {
      if (!plan.incomplete.empty()) std::printf("%d\n", frame);
      continue;
    }
    if (args.resume) {
      if (plan.incomplete.empty()) {
        ++skipped;
        progress.advance();
        continue;
      }
      if (!args.quiet) reportResume(plan, fmt::format("frame {}: ", frame));
    }
    RenderScene scene;
    namingFile(args.scene, "cannot build the scene", [&] {
      scene = buildRenderScene(desc, &record.build, BuildOptions{.images = images});
    });
    if (scene.images()) images = scene.images();
    if (records.empty()) {
      checkDisplaySettings(desc, outputs);
      if (!args.quiet && !warned)
        for (const std::string& w : desc.warnings)
          std::fprintf(stderr, "glint: warning: %s\n", w.c_str());
      warned = true;
    }
    const bool wrote = renderAndWrite(args, desc, scene, outputs, false, &record, plan.partial);
    if (!wrote) {
      std::fprintf(stderr, "glint: frame %d: interrupted before its first pass finished\n", frame);
      break;
    }
    if (records.empty()) first = sceneJson(args, desc, scene, record.stats.threads);
    records.push_back(record);
    progress.advance();
    if (!args.quiet && (!terminal || record.result.reason == StopReason::Interrupted))
      printSummary(outputs, scene, record);
    if (record.result.reason == StopReason::Interrupted) break;  // the rest: --resume
  }
  progress.finish();
  if (args.listMissing) return;

  double total = 0;
  nlohmann::json perFrame = nlohmann::json::array();
  for (const FrameRecord& r : records) {
    total += r.stats.renderSeconds;
    perFrame.push_back(frameJson(r));
    perFrame.back()["frame"] = r.frame;
  }
  if (args.statsPath) {
    nlohmann::json j = first.is_null() ? nlohmann::json::object() : first;
    j["scene"] = args.scene;
    j["frames"] = perFrame;
    j["frames_rendered"] = records.size();
    j["frames_skipped"] = skipped;
    j["render_seconds_total"] = total;
    writeTextAtomically(*args.statsPath, j.dump(2) + "\n");
  }
  if (!args.quiet)
    std::fprintf(stderr, "glint: rendered %zu frame%s (%d skipped, already complete) in %.2f s\n",
                 records.size(), records.size() == 1 ? "" : "s", skipped, total);
}

// Throws InputError for options that cannot work together, SceneError for the scene, and a
// FailureError (OutputError among them) for a render or write that failed. Returns the signal
// that interrupted the render once its outputs are written, else 0. main.cpp decides the exit
// code of each.
int runRender(RenderArgs args) {
  std::vector<std::string> outputs = args.outputs;
  if (outputs.empty())
    outputs.push_back(std::filesystem::path(args.scene).stem().string() +
                      (args.frames ? "_####.exr" : ".exr"));
  if (args.time && args.frames)
    throw InputError("--time and --frames exclude each other (frame f is at time f / fps)");
  if (args.listMissing && !args.frames)
    throw InputError(
        "--list-missing applies to a sequence (--frames A-B; one frame: --frames F-F)");
  if (args.timeLimit) args.timeLimitSeconds = parseDuration(*args.timeLimit);
  if (args.noiseTarget && !(*args.noiseTarget > 0 && *args.noiseTarget < 1))
    throw InputError("--noise-target: must be > 0 and < 1 (a relative error: 0.01 is 1%)");
  if (args.crop || args.tile) {
    if (args.crop && args.tile) throw InputError("--crop and --tile exclude each other");
    if (args.crop) parseCropWindow(*args.crop);
    if (args.tile) parseTileSpec(*args.tile);
    // A piece is tone-mapped only once the frame is whole (a per-piece Ward scale would
    // differ from piece to piece).
    for (const std::string& out : outputs)
      if (std::filesystem::path(out).extension() != ".exr")
        throw InputError(out +
                         ": --crop and --tile write partial EXRs (the data window of the frame); "
                         "join them with `glint assemble`, then tone-map");
  }
  if (args.overrides.aovs && std::none_of(outputs.begin(), outputs.end(),
                                          [](const std::string& o) { return isExrPath(o); }))
    throw InputError(
        "--aovs: the AOVs (albedo, normal, depth) go only into EXR output; add "
        "-o NAME.exr");
  checkOutputs(outputs);
  // Ctrl-C (or Slurm's SIGTERM) stops the render and writes what it has; a second one quits.
  InterruptGuard interrupt;
  args.cancel = interrupt.flag();
  if (args.frames)
    runSequence(args, outputs);
  else
    runSingle(args, outputs);
  // Interrupted: the outputs are written (or there was nothing to write); main's exit status
  // says the render did not finish.
  return interrupt.interrupted() ? interrupt.signal() : 0;
}

}  // namespace

void addRenderCommand(CLI::App& app, Outcome* outcome) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* cmd =
      app.add_subcommand("render", "render a scene to EXR (scene-linear) or PNG/JPEG/TIFF");
  cmd->add_option("scene", args->scene,
                  "a .gltf/.glb scene, a .ply/.obj mesh or a glint .json scene")
      ->required();
  cmd->add_option("-o,--output", args->outputs,
                  "output image(s): .exr, .png, .jpg, .tif (repeat to write several; default "
                  "SCENE_STEM.exr in the current folder, SCENE_STEM_####.exr with --frames)");
  cmd->add_option("--sidecar", args->sidecar,
                  "sidecar JSON (default: NAME.glint.json beside the glTF or mesh)");
  cmd->add_option("--stats", args->statsPath, "write render statistics as JSON");
  cmd->add_option("--frames", args->frames,
                  "render a sequence: frames A-B[:STEP] at time frame / fps; outputs need a '#' "
                  "run for the frame number (frame_####.exr)");
  cmd->add_option("--fps", args->fps,
                  "frames per second of the sequence (default: the sidecar's, else 24)");
  cmd->add_option(
      "--time", args->time,
      "scene time of a single frame, in seconds (default: the sidecar's render.time, else 0)");
  cmd->add_flag("--resume", args->resume,
                "skip outputs that are complete (this render's metadata, checksum intact); "
                "continue an EXR that stopped short (interrupted, fewer spp, noise target not "
                "met) to the spp or budget asked for now; redo the rest");
  cmd->add_flag("--list-missing", args->listMissing,
                "render nothing: print the frames --resume would render, one per line");
  cmd->add_option("--crop", args->crop,
                  "render only pixels X0,Y0,X1,Y1 (X1, Y1 exclusive) to a partial EXR; "
                  "`glint assemble` joins the pieces");
  cmd->add_option("--tile", args->tile,
                  "render only tile I/N: the I-th (from 0) of N horizontal bands of the frame");
  cmd->add_option("--time-limit", args->timeLimit,
                  "render passes until this much time is spent (30s, 2m, 1h30m; a number is "
                  "seconds); --spp, when given, caps the samples");
  cmd->add_option("--noise-target", args->noiseTarget,
                  "render passes until the estimated relative error of the image is below this "
                  "(0.01 = 1%; checked from 16 spp on); --spp, when given, caps the samples");
  cmd->add_flag("-q,--quiet", args->quiet, "no progress bar or summary");
  args->overrides.addOptions(cmd);
  cmd->add_flag("--aovs", args->overrides.aovs,
                "EXR output also carries albedo, normal and depth (every EXR carries the "
                "variance of each pixel's mean)");
  cmd->callback([args, outcome] { outcome->interruptedBy = runRender(*args); });
}

}  // namespace glint::app
