// glint — `glint render`: load, build, render, write images and statistics.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "apps/cli_common.h"
#include "apps/commands.h"
#include "renderer/color.h"
#include "renderer/output.h"
#include "renderer/progress.h"
#include "renderer/render.h"
#include "renderer/tonemap.h"
#include "scenes/build.h"
#include "scenes/load.h"

namespace glint::app {

namespace {

struct RenderArgs {
  std::string scene;
  std::vector<std::string> outputs;
  std::optional<std::string> sidecar;
  std::optional<std::string> statsPath;
  SceneOverrides overrides;
  bool quiet = false;
};

std::string statsJson(const RenderArgs& args, const SceneDescription& desc,
                      const RenderScene& scene, const BuildTimings& build,
                      const RenderStats& stats) {
  nlohmann::json j;
  j["scene"] = args.scene;
  j["accel"] = desc.render.accel;
  j["integrator"] = desc.render.integrator;
  j["camera"] = scene.cameraName;
  j["width"] = scene.camera.width();
  j["height"] = scene.camera.height();
  j["spp"] = desc.render.spp;
  j["seed"] = desc.render.seed;
  j["threads"] = stats.threads;
  j["triangles"] = scene.geometry.instancedTriangleCount();
  j["triangles_stored"] = scene.geometry.uniqueTriangleCount();
  // Everything the accelerator intersects: placed triangles plus analytic objects (a CSG tree
  // counts as one primitive: it is one Embree user primitive).
  j["primitives"] = scene.geometry.instancedTriangleCount() + scene.geometry.shapeInstanceCount();
  j["analytic_objects"] = scene.geometry.shapeInstanceCount();
  j["instances"] = scene.geometry.instances.size();
  j["lights"] = scene.lights.size();
  j["build_seconds"] = build.totalSeconds;
  j["accel_build_seconds"] = build.acceleratorSeconds;
  j["render_seconds"] = stats.renderSeconds;
  j["rays"] = {{"camera", stats.rays.camera},
               {"shadow", stats.rays.shadow},
               {"secondary", stats.rays.secondary},
               {"total", stats.rays.total()}};
  j["mrays_per_second"] =
      stats.renderSeconds > 0 ? double(stats.rays.total()) / stats.renderSeconds * 1e-6 : 0.0;
  j["effects"] = scene.features.names();
  j["nonfinite_samples"] = stats.nonfiniteSamples;
  return j.dump(2) + "\n";
}

int runRender(const RenderArgs& args) {
  std::vector<std::string> outputs = args.outputs;
  if (outputs.empty())
    outputs.push_back(std::filesystem::path(args.scene).stem().string() + ".exr");
  for (const std::string& out : outputs) {
    std::string why;
    if (!isSupportedOutput(out, &why)) {
      printError(out + ": " + why);
      return 2;
    }
  }

  SceneDescription desc;
  RenderScene scene;
  BuildTimings build;
  try {
    desc = loadScene(args.scene, args.sidecar);
    args.overrides.apply(&desc);
    scene = buildRenderScene(desc, &build);
  } catch (const SceneError& e) {
    printError(e.what());
    return 2;
  } catch (const std::invalid_argument& e) {  // unknown integrator/accelerator/filter names
    printError(args.scene + ": " + e.what());
    return 2;
  } catch (const std::exception& e) {
    printError(args.scene + ": cannot build the scene: " + std::string(e.what()));
    return 1;
  }
  // Display settings are only used when writing, after the render: check them now.
  bool displayReferred = std::any_of(outputs.begin(), outputs.end(), [](const std::string& o) {
    return std::filesystem::path(o).extension() != ".exr";
  });
  if (displayReferred) {
    try {
      if (!isKnownToneMapOperator(desc.render.tonemap.op))
        throw ColorError("unknown tone mapping operator '" + desc.render.tonemap.op + "'");
      resolveDisplayView(desc.render.tonemap.display, desc.render.tonemap.view);
    } catch (const ColorError& e) {
      printError(desc.file + ": /render/tonemap: " + e.what());
      return 2;
    }
  }
  if (!args.quiet)
    for (const std::string& w : desc.warnings) std::fprintf(stderr, "glint: warning: %s\n", w.c_str());

  RenderStats stats;
  Film film;
  try {
    auto integrator = makeIntegrator(desc.render.integrator, scene, desc.render);
    RenderOptions options;
    options.threads = desc.render.threads;
    options.progress = !args.quiet && isTerminal(stderr);
    film = render(scene, *integrator, desc.render, options, &stats);
  } catch (const std::invalid_argument& e) {
    printError(args.scene + ": " + e.what());
    return 2;
  } catch (const std::exception& e) {
    printError(args.scene + ": render failed: " + std::string(e.what()));
    return 1;
  }

  ImageMetadata meta{args.scene, desc.render.spp, desc.render.seed, stats.renderSeconds,
                     desc.render.accel, desc.render.integrator};
  try {
    for (const std::string& out : outputs) writeImage(out, film, desc.render, meta);
    if (args.statsPath)
      writeTextAtomically(*args.statsPath, statsJson(args, desc, scene, build, stats));
  } catch (const std::exception& e) {
    printError(e.what());
    return 1;
  }
  if (!args.quiet) {
    double mrays = stats.renderSeconds > 0 ? double(stats.rays.total()) / stats.renderSeconds * 1e-6 : 0;
    std::string names;
    for (const std::string& out : outputs) names += (names.empty() ? "" : ", ") + out;
    std::fprintf(stderr, "glint: wrote %s (%dx%d, %d spp, %.2f s, %.1f Mrays/s%s)\n",
                 names.c_str(), film.width, film.height, desc.render.spp, stats.renderSeconds,
                 mrays,
                 stats.nonfiniteSamples
                     ? (", " + std::to_string(stats.nonfiniteSamples) + " NaN/Inf samples dropped").c_str()
                     : "");
  }
  return 0;
}

}  // namespace

void addRenderCommand(CLI::App& app, int* exitCode) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand("render", "render a scene to EXR (scene-linear) or PNG/JPEG/TIFF");
  cmd->add_option("scene", args->scene, "a .gltf/.glb scene or a glint .json scene")->required();
  cmd->add_option("-o,--output", args->outputs,
                  "output image(s): .exr, .png, .jpg, .tif (repeat to write several)");
  cmd->add_option("--sidecar", args->sidecar, "sidecar JSON (default: NAME.glint.json beside the glTF)");
  cmd->add_option("--stats", args->statsPath, "write render statistics as JSON");
  cmd->add_flag("-q,--quiet", args->quiet, "no progress bar or summary");
  args->overrides.addOptions(cmd);
  cmd->callback([args, exitCode] { *exitCode = runRender(*args); });
}

}  // namespace glint::app
