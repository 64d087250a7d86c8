// glint — shared subcommand pieces.
#include "apps/cli_common.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "geometry/accel/accelerator.h"
#include "image/output.h"
#include "renderer/integrator.h"
#include "renderer/light_sampler.h"
#include "scenes/sidecar_lights.h"

namespace glint::app {

CLI::Validator numberIn(const Range& range, bool whole) {
  return CLI::Validator(
      [range, whole](const std::string& text) -> std::string {
        size_t used = 0;
        double value = 0;
        try {
          value = whole ? double(std::stoll(text, &used)) : std::stod(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used == 0 || used != text.size())
          return std::string(whole ? "expected a whole number" : "expected a number") + ", got '" +
                 text + "'";
        if (!std::isfinite(value)) return "must be finite, got '" + text + "'";
        if (!range.contains(value)) return range.describe() + ", got " + text;
        if (whole && value > double(std::numeric_limits<int>::max()))
          return "must be <= " + std::to_string(std::numeric_limits<int>::max()) + ", got " + text;
        return "";
      },
      range.describe().substr(std::string("must be ").size()));
}

void SceneOverrides::addOptions(CLI::App* cmd) {
  const CLI::Validator positiveWhole = numberIn({.ge = 1}, true);
  const CLI::Validator nonNegativeWhole = numberIn({.ge = 0}, true);
  const CLI::Validator nonNegative = numberIn({.ge = 0});
  cmd->add_option("--width", width, "image width in pixels")->check(positiveWhole);
  cmd->add_option("--height", height, "image height in pixels")->check(positiveWhole);
  cmd->add_option("--spp", spp, "samples per pixel")->check(positiveWhole);
  cmd->add_option("--seed", seed, "random seed");
  cmd->add_option("--threads", threads, "worker threads (0 = all cores)")->check(nonNegativeWhole);
  cmd->add_option("--accel", accel, "acceleration structure")
      ->check(CLI::IsMember(acceleratorNames()));
  cmd->add_option("--camera", camera, "camera name");
  cmd->add_option("--integrator", integrator,
                  "light transport (default auto: the path tracer for environments, area lights, "
                  "emitters and rough metals, else Whitted)")
      ->check(CLI::IsMember(integratorNames()));
  cmd->add_option("--max-depth", maxDepth, "maximum bounces")->check(nonNegativeWhole);
  cmd->add_option("--light-sampler", lightSampler, "how next-event estimation picks a light")
      ->check(CLI::IsMember(lightSamplerNames()));
  cmd->add_option("--adaptive", adaptive,
                  "adaptive sampling: a pixel stops once its relative standard error is below "
                  "this (0 = off; --spp is then the most a pixel takes)")
      ->check(nonNegative);
  cmd->add_option("--antialias", antialias,
                  "anti-aliasing by contrast (POV-Ray's +A): a pixel keeps sampling while its "
                  "mean differs from a neighbour's by more than this, on x/(1+x), checked at 1, "
                  "2, 4, 8 and 16 samples; the first goes through the pixel's centre (0 = off; "
                  "e.g. 0.05; --spp is the most a pixel takes)")
      ->check(numberIn({.ge = 0, .le = 1}));
  cmd->add_option("--subdivide", subdivide,
                  "anti-aliasing by recursive subdivision (POV-Ray's +AM2; its +Rn is N = n-1): "
                  "one look per pixel corner, shared with the neighbours; a square whose corners "
                  "differ by more than --antialias is cut in four, down to N levels (1-6; 0 = "
                  "off; --spp and the filter are not used)")
      ->check(numberIn({.ge = 0, .le = kMaxSubdivision}, true));
  cmd->add_option("--jitter", jitter,
                  "with --subdivide: each look moves off its lattice point by up to +-J/2 of "
                  "the finest step (POV-Ray's +J; default 1, 0 = on the lattice)")
      ->check(numberIn({.ge = 0, .le = 1}));
  cmd->add_option("--adaptive-min-spp", adaptiveMinSpp,
                  "samples every pixel takes before --adaptive may stop it (default 32; 4 suits "
                  "Whitted scenes, whose only noise is edges)")
      ->check(numberIn({.ge = 2}, true));
  cmd->add_option("--env", env,
                  "environment light: 'studio' (the built-in default) or an equirectangular "
                  ".exr/.hdr file; replaces the scene's");
  cmd->add_option("--env-strength", envStrength, "multiplies the environment")->check(nonNegative);
  cmd->add_option("--env-rotation", envRotation, "turns the environment about +Y (degrees)");
  cmd->add_flag("--no-default-light", noDefaultLight,
                "no studio light for a scene without lights of its own");
  cmd->add_option("--variant", variant,
                  "glTF material variant to show (KHR_materials_variants; `glint info` lists "
                  "them)");
  cmd->add_option("--shutter", shutter,
                  "motion blur: the shutter stays open S seconds from the frame time, or from "
                  "OPEN to CLOSE seconds (S or OPEN,CLOSE; e.g. 0.02 for half a frame at 24 "
                  "fps); replaces the camera's");
}

namespace {

// "S" -> [0, S], "OPEN,CLOSE" -> [OPEN, CLOSE]; finite, open <= close.
std::array<double, 2> parseShutter(const std::string& text) {
  const SourceLocation where{"command line", "--shutter"};
  auto number = [&](const std::string& s) {
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(s, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != s.size() || !std::isfinite(v))
      throw SceneError(where, "expected seconds S or OPEN,CLOSE, got '" + text + "'");
    return v;
  };
  const size_t comma = text.find(',');
  std::array<double, 2> s{0, 0};
  if (comma == std::string::npos) {
    s[1] = number(text);
  } else {
    s[0] = number(text.substr(0, comma));
    s[1] = number(text.substr(comma + 1));
  }
  if (s[0] > s[1])
    throw SceneError(where, "the shutter must open before it closes, got '" + text + "'");
  return s;
}

}  // namespace

void SceneOverrides::apply(SceneDescription* desc) const {
  RenderSettings& r = desc->render;
  if (width) r.width = *width;
  if (height) r.height = *height;
  if (spp) r.spp = *spp;
  if (seed) r.seed = *seed;
  if (threads) r.threads = *threads;
  if (accel) r.accel = *accel;
  if (integrator) r.integrator.type = *integrator;
  if (maxDepth) r.integrator.maxDepth = *maxDepth;
  if (lightSampler) r.integrator.lightSampler = *lightSampler;
  if (adaptive) r.adaptive.threshold = *adaptive;
  if (adaptiveMinSpp) r.adaptive.minSpp = *adaptiveMinSpp;
  if (antialias) r.adaptive.contrast = *antialias;
  if (subdivide) r.adaptive.subdivide = *subdivide;
  if (jitter) r.adaptive.jitter = *jitter;
  if (aovs) r.aovs = true;
  if (noDefaultLight) r.defaultLight = false;
  if (shutter) r.shutter = parseShutter(*shutter);
  if (variant) {
    if (std::find(desc->variants.begin(), desc->variants.end(), *variant) == desc->variants.end()) {
      const std::string names = quotedNames(desc->variants);
      throw SceneError({"command line", "--variant"},
                       "no material variant named '" + *variant + "' in " + desc->file +
                           (names.empty() ? " (it has none)" : " (variants: " + names + ")"));
    }
    r.variant = *variant;
  }
  if (env) {
    EnvironmentDesc e;
    e.where = {"command line", "--env"};
    if (*env == "studio") {
      e.studio = true;
    } else {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(*env, ec))
        throw SceneError(e.where, "no such file '" + *env + "'");
      if (!isEnvironmentImagePath(*env))
        throw SceneError(e.where,
                         "expected 'studio' or a scene-linear image, OpenEXR (.exr) or "
                         "Radiance (.hdr), got '" +
                             *env + "'");
      e.image = *env;
    }
    desc->environment = e;
  }
  if ((envStrength || envRotation) && !desc->environment) {
    // Tuning the light a scene without one gets: make the studio explicit.
    if (!r.defaultLight)
      throw SceneError({"command line", envStrength ? "--env-strength" : "--env-rotation"},
                       "there is no environment to tune (--no-default-light, and the scene has "
                       "none; give --env)");
    desc->environment = EnvironmentDesc{};
    desc->environment->studio = true;
    desc->environment->where = {"command line", "--env"};
  }
  if (envStrength) desc->environment->intensity = *envStrength;
  if (envRotation) desc->environment->rotation = *envRotation * (kPi / 180.0f);
  if (camera) {
    bool known = std::any_of(desc->cameras.begin(), desc->cameras.end(),
                             [&](const CameraDesc& c) { return c.name == *camera; });
    if (!known) {
      std::vector<std::string> cameras;
      for (const CameraDesc& c : desc->cameras) cameras.push_back(c.name);
      const std::string names = quotedNames(cameras);
      throw SceneError({"command line", "--camera"},
                       "no camera named '" + *camera + "' in " + desc->file +
                           (names.empty() ? " (it has no cameras)" : " (cameras: " + names + ")"));
    }
    r.camera = *camera;
  }
}

void createOutputFolder(const std::string& path) {
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!folder.empty() && !std::filesystem::is_directory(folder, ec) &&
      !std::filesystem::create_directories(folder, ec))
    throw OutputError(path + ": cannot create the folder " + folder.string() + ": " + ec.message());
}

void writeTextAtomically(const std::string& path, const std::string& text) {
  std::filesystem::path target(path);
  std::filesystem::path tmp = target.parent_path() / ("." + target.filename().string() + ".tmp-" +
                                                      std::to_string(::getpid()));
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.flush();
    if (!out) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw OutputError("cannot write " + path);
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, target, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw OutputError("cannot write " + path + ": " + ec.message());
  }
}

}  // namespace glint::app
