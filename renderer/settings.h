// glint — render settings: what the sidecar's "render" block and the command line control.
//
// Precedence: these defaults, then the sidecar (or glint .json scene), then command-line
// options. Loaders fill these fields; the renderer only reads them.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "geometry/math.h"

namespace glint {

// Pixel reconstruction filter. Samples are drawn from the filter's distribution (filter
// importance sampling, as pbrt-v4 does), so every sample belongs to exactly one pixel: tiles
// stay independent and images are identical for any thread count.
struct FilterSettings {
  std::string type = "gaussian";  // "box" | "tent" | "gaussian"
  float radius = 1.5f;            // in pixels; box and tent use it as half-width
};

// Display transform for PNG/JPEG/TIFF output (EXR stays scene-linear).
struct ToneMapSettings {
  float exposure = 0;       // stops: scene-linear values are multiplied by 2^exposure
  std::string op = "none";  // "none" (clip in the display transform) | "ward"
  // Ward (1994) contrast-based scale factor. Scene-linear 1.0 is taken as
  // `sceneLuminance` cd/m^2; the display's maximum is `displayMax` cd/m^2.
  float wardDisplayMax = 100.0f;
  float wardSceneLuminance = 100.0f;
  std::string display;  // colour-managed display (image/color.h); empty = default
  std::string view;     // view of that display; empty = the display's default
};

// Light transport: the render block's "integrator" (a name, or an object with "type" and the
// keys below) and `--integrator`.
struct IntegratorSettings {
  std::string type = "auto";           // "whitted" | "path" | "instant-radiosity" | "auto"
  int maxDepth = 8;                    // bounces: Whitted's mirror/glass recursion, path length
  int rrDepth = 5;                     // path: Russian roulette from this many bounces on
  std::string lightSampler = "power";  // next-event estimation: "uniform" | "power" | "bvh"
  // Participating media. Whitted: emission only, or single scattering ("multiple" acts as
  // "single"); path: "emission" scatters nothing, the others scatter any number of times
  // (tracking); instant radiosity renders them as Whitted does, its VPL light attenuated by
  // them but not scattered.
  std::string volume = "single";          // "emission" (absorb and emit) | "single" | "multiple"
  std::string volumeEstimator = "march";  // "march" (fixed steps) | "track" (ratio/delta tracking)
  float volumeStep = 0;                   // march step, world units; 0 = from each medium's size
  // Path tracer (which always tracks): the camera ray gathers the emission of media along its whole
  // segment under a ratio-tracked transmittance, past where it scatters (SegmentSamples in
  // renderer/volume.h; not under spectral MIS); false: up to where it scatters only (the
  // track-length estimator every other segment uses).
  bool wholeSegmentEmission = true;
  // Whitted: shadow rays cross glass and glTF transmission, attenuated by the surfaces'
  // Fresnel transmittance and tint, straight and unrefracted (POV-Ray's filtered shadows: an
  // approximation, no caustics); false: glass casts a black shadow. The path tracer ignores
  // it (it finds the light through glass itself).
  bool glassShadows = true;
  // Whitted (and instant radiosity's specular bounces): mirror and glass branches whose weight
  // as the camera sees it falls below this are followed by Russian roulette (unbiased; see
  // WhittedIntegrator::specularBounces). POV-Ray's adc_bailout default; 0 follows every branch.
  float minWeight = 1.0f / 255;
  // Instant radiosity (Keller 1997).
  int vplPaths = 64;   // light paths traced from the lights (Halton-seeded)
  float vplClamp = 0;  // bound on the geometry term cos cos / d^2 of a VPL; 0 = no clamp
  // VPLs sending a point at least this share of its unshadowed VPL light get a shadow ray
  // each; the others share shadow rays by unbiased sampling (InstantRadiosityIntegrator).
  // 0: every VPL gets a shadow ray.
  float vplShadowShare = 1.0f / 16;

  friend bool operator==(const IntegratorSettings&, const IntegratorSettings&) = default;
};

// The deepest anti-aliasing by subdivision (AdaptiveSettings::subdivide): 2^6 = 64 squares per
// pixel side, at most 65² looks in a pixel.
inline constexpr int kMaxSubdivision = 6;

// Adaptive sampling: a pixel stops drawing samples once its estimate is good enough, so the
// samples go where the noise is. At the checkpoints from `minSpp` samples on (2, 4, 8, then
// every multiple of 16), a pixel stops when every channel's variance of the mean satisfies
//   Var[mean] <= threshold² · (mean² + 0.01),
// the relative error of the relative MSE metric (Rousselle et al.) that `glint diff` reports;
// `spp` stays the most any pixel takes. The stopping rule looks at the pixel's own samples
// only, so the image is still the same for any thread count. It is biased (a pixel that has
// not yet met a rare bright path looks converged); the bias vanishes as threshold -> 0.
//
// Anti-aliasing by contrast (`contrast` > 0), the rule of POV-Ray's adaptive anti-aliasing: in
// a scene without noise (hard shadows, mirrors, glass: Whitted) the only error is at edges, and
// a pixel's own few samples may all fall on one side of one. So after 1, 2, 4, 8 and 16 samples
// a pixel also compares its mean with its 8 neighbours' means, channel by channel on x/(1+x)
// (scene-linear radiance squeezed into [0, 1), like a displayed value): it stops there only
// when no neighbour differs by more than `contrast` (and, with `threshold` > 0, when its own
// variance rule is met too, from 2 samples and minSpp on); a pixel still going after 16 takes
// the rest (or stops by `threshold` alone). The decisions are made between passes over the
// whole window, so they do not depend on the thread count; a crop or tile renders a margin of
// ContrastStop::margin() pixels around its window (what its border pixels' decisions can depend
// on), so its pixels are those of the whole frame's render (renderer/stopping.h).
// A pixel's first look goes through its centre, as POV-Ray's does: the midpoint rule, exact for
// a linear gradient across the pixel (a highlight's slope), where one sample at a random place
// in the pixel errs by the slope times its offset. A pixel that is not stopped there drops that
// look and takes its stratified samples from the first (a centre mixed into a stratified set
// breaks its strata: measured worse), so its estimate is a plain render's; the film's sample
// count is the samples in the estimate, RenderStats::meanSpp counts the dropped look too.
struct AdaptiveSettings {
  float threshold = 0;  // 0: off, every pixel takes spp samples
  float contrast = 0;   // 0: off (see above)
  // Anti-aliasing by recursive subdivision (renderer/subdivide.h, POV-Ray's method 2): up to
  // this many levels of squares cut in four inside a pixel where their corners differ by more
  // than `contrast`, instead of whole-pixel samples; 0: off. spp and the filter are then not
  // used, and the render is one pass (a preview takes whole-pixel samples instead).
  int subdivide = 0;
  // With subdivision: each look moves off its lattice point by up to ±jitter/2 of the finest
  // lattice step, by its own random numbers (POV-Ray's +J, on by default there too): a regular
  // lattice errs the same way along a straight edge and beats with fine patterns; jittered,
  // the errors do not add up (measured: 16-22% lower RMSE at equal looks, benchmarks/README).
  float jitter = 1;
  // Samples every pixel takes first; at least 2. A noisy (path-traced) pixel's variance needs
  // tens of samples to be trusted; a Whitted scene's pixels (edges are their only noise) can
  // be judged after 4, like supersampling anti-aliasing.
  int minSpp = 32;
};

struct RenderSettings {
  std::optional<int> width, height;  // unset: 640 wide, height from the camera's aspect
  int spp = 16;                      // samples per pixel (the most, with adaptive sampling)
  AdaptiveSettings adaptive;
  uint64_t seed = 0;
  int threads = 0;  // 0 = all hardware threads
  std::string accel = "embree";
  std::string camera;  // camera name; empty = the first camera
  double time = 0;     // seconds: the scene time of a single frame
  double fps = 24;     // frames per second of a sequence (frame f at f / fps)
  // The shutter, [open, close] in seconds from the frame time (--shutter, sidecar
  // render.shutter): replaces the rendering camera's own, and gives the automatic camera one.
  // Unset: the camera's (none for the automatic camera: nothing blurs).
  std::optional<std::array<double, 2>> shutter;
  IntegratorSettings integrator;
  FilterSettings filter;
  ToneMapSettings tonemap;
  Rgb background{0, 0, 0};  // radiance of rays that leave the scene
  // A scene with no light (no punctual, area or environment light, and a black background;
  // emitting surfaces do not count) is lit by the studio environment. False: it stays dark
  // but for its emitters (--no-default-light, sidecar "default_light": false).
  bool defaultLight = true;
  // The glTF material variant to show (KHR_materials_variants; --variant, sidecar "variant"),
  // or empty for each primitive's default material.
  std::string variant;
  bool exrHalf = false;  // write EXR as half instead of float
  bool aovs = false;     // add albedo, normal and depth channels to EXR output
};

}  // namespace glint
