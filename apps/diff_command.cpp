// glint — `glint diff A B`: numeric image comparison with idiff's thresholds, or statistical
// (per-pixel z-tests against a reference's mean and variance).
#include <fmt/format.h>

#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "apps/cli_common.h"
#include "apps/commands.h"
#include "image/compare.h"

namespace glint::app {

namespace {

struct DiffOptions : CompareOptions {
  bool json = false;
};

void printFlipText(const DiffOptions& o, const FlipReport& f) {
  const FlipStats& s = f.result.stats;
  std::string how = f.hdr
                        ? fmt::format("HDR, {} exposures {:.2f}..{:.2f}", f.result.exposures.count,
                                      f.result.exposures.start, f.result.exposures.stop)
                        : "LDR";
  fmt::print(
      "  FLIP ({}, {:.3g} pixels/degree): mean {:.4g}, weighted median {:.4g}, 95th percentile "
      "{:.4g}, max {:.4g} @ ({}, {}){}\n",
      how, o.pixelsPerDegree, s.mean, s.weightedMedian, s.percentile95, s.max, s.maxX, s.maxY,
      std::isfinite(o.flipMax) ? fmt::format(" (limit {:g})", o.flipMax) : "");
}

void printText(const DiffOptions& o, const DiffResult& r, const std::optional<FlipReport>& flip) {
  fmt::print("Comparing \"{}\" and \"{}\"\n", o.a, o.b);
  if (r.sizeMismatch) {
    fmt::print("  Resolutions differ: {}x{} vs {}x{}\nFAILURE\n", r.widthA, r.heightA, r.widthB,
               r.heightB);
    return;
  }
  fmt::print("  Mean error = {:g}\n  RMS error = {:g}\n  Relative MSE = {:g}\n", r.meanAbsError,
             r.rmse, r.relMse);
  fmt::print("  Peak SNR = {:g}\n  Max error = {:g} @ ({}, {}, {})\n", r.psnr, r.maxError, r.maxX,
             r.maxY, r.maxChannel);
  fmt::print("  {} pixels ({:.3g}%) over {:g} (fail)\n", r.failPixels, r.failPixelPercent,
             o.thresholds.fail);
  fmt::print("  {} pixels ({:.3g}%) over {:g} (warn)\n", r.warnPixels, r.warnPixelPercent,
             o.thresholds.warn);
  if (flip) printFlipText(o, *flip);
  fmt::print("{}\n", r.verdict == DiffVerdict::Pass   ? "PASS"
                     : r.verdict == DiffVerdict::Warn ? "WARNING"
                                                      : "FAILURE");
}

// How A's variance was set, in words: "A's predicted from B's (32 vs 1024 spp)".
std::string varianceOfA(const StatisticalResult& r) {
  const std::string predicted = fmt::format("predicted from B's ({} vs {} spp)", r.sppA, r.sppB);
  if (r.varianceModel == "own") return "A's own variance channels";
  if (r.varianceModel == "predicted") return "A's " + predicted;
  return "A's own variance channels or, where larger, " + predicted;
}

// What mean z² says, which the verdict does not use, when it says something: above 2 the
// differences are well beyond the noise the variances predict; 0 means A equals B. Below 1 says
// nothing: glint's film stores the variance of the mean as sample variance / n, which assumes
// independent samples, and its Owen-scrambled Sobol samples err less than that (a correct
// Cornell box at 32 vs 1024 spp gives about 0.55).
std::string meanZ2Note(const StatisticalResult& r) {
  if (r.meanZ2 > 2)
    return fmt::format(
        "mean z^2 = {:.3g} is far above 1: the differences are about {:.3g} times the noise the "
        "variances predict (the square root of mean z^2), from a few pixels far off ({} over "
        "|z| = {:.3g}, which --min-pass allows: fireflies, or a real difference confined to "
        "them) or from a variance that is too small; --heatmap shows where",
        r.meanZ2, std::sqrt(r.meanZ2), r.failPixels, r.pixelZ);
  if (r.meanZ2 == 0 && r.nonFinite == 0)
    return "mean z^2 = 0: A equals B exactly, so it is the same image rather than an independent "
           "render";
  return "";
}

void printText(const DiffOptions& o, const StatisticalResult& r,
               const std::optional<FlipReport>& flip) {
  const StatisticalThresholds& t = o.statistics;
  fmt::print("Comparing \"{}\" with reference \"{}\" statistically\n", o.a, o.b);
  if (r.sizeMismatch) {
    fmt::print("  Resolutions differ: {}x{} vs {}x{}\nFAILURE\n", r.widthA, r.heightA, r.widthB,
               r.heightB);
    return;
  }
  fmt::print(
      "  Each pixel channel is tested: z = (A - B) / sigma, where sigma^2 is B's variance of "
      "its mean plus {}.\n",
      varianceOfA(r));
  fmt::print(
      "  The test passes when all of these hold; each |z| limit is set so that a correct "
      "render exceeds it with a {:g}% chance (--significance) over all the values it is "
      "applied to:\n",
      100 * t.significance);
  auto mark = [](bool ok) { return ok ? "[ok]  " : "[FAIL]"; };
  std::vector<std::string> failed;
  const bool enoughPass = !(r.passPercent < t.minPassPercent);
  if (!enoughPass) failed.push_back("too few pixels within the noise");
  fmt::print(
      "  {} pixels within the noise: {:.3f}% have every |z| <= {:.3g}; need >= {:g}% "
      "(--min-pass); {} pixel{} over\n",
      mark(enoughPass), r.passPercent, r.pixelZ, t.minPassPercent, r.failPixels,
      r.failPixels == 1 ? "" : "s");
  if (r.biased) failed.push_back("biased");
  fmt::print(
      "  {} no overall bias: sum(A - B) / sqrt(sum sigma^2) per channel is R {:.3g}, G {:.3g}, "
      "B {:.3g}; need |z| <= {:.3g}{}\n",
      mark(!r.biased), r.globalZ[0], r.globalZ[1], r.globalZ[2], r.globalZLimit,
      r.biased ? ": BIASED" : "");
  const std::string largestError =
      r.failPixels > 0 ? fmt::format(
                             "the largest |A-B|/max(1,|B|) of a pixel over |z| = {:.3g} is "
                             "{:.3g} @ ({}, {})",
                             r.pixelZ, r.maxError, r.maxErrorX, r.maxErrorY)
                       : std::string("no pixel is over |z| = ") + fmt::format("{:.3g}", r.pixelZ);
  if (std::isfinite(t.maxError)) {
    if (r.errorCapExceeded) failed.push_back("error cap exceeded");
    fmt::print("  {} error cap: {}; need <= {:g} (--max-error){}\n", mark(!r.errorCapExceeded),
               largestError, t.maxError, r.errorCapExceeded ? ": EXCEEDED" : "");
  } else {
    fmt::print("  [--]   error cap: none (--max-error sets one); {}\n", largestError);
  }
  if (r.nonFinite > 0) failed.push_back("NaN or Inf");
  fmt::print("  {} no NaN or Inf: {} channel value{} NaN or Inf\n", mark(r.nonFinite == 0),
             r.nonFinite, r.nonFinite == 1 ? " is" : "s are");
  if (flip) {
    printFlipText(o, *flip);
    if (flip->result.stats.mean > o.flipMax) failed.push_back("mean FLIP over --flip-max");
  }
  fmt::print(
      "  Not part of the verdict: largest |z| = {:.3g}{}; mean z^2 = {:.3g} (about 1 when sigma "
      "is the true size of the differences; below 1 is usual for glint renders, whose stratified "
      "samples err less than the sample variance / spp that sigma is built from)\n",
      r.maxZ, r.maxZ > 0 ? fmt::format(" @ ({}, {}, {})", r.maxZX, r.maxZY, r.maxZChannel) : "",
      r.meanZ2);
  const std::string note = meanZ2Note(r);
  if (!note.empty()) fmt::print("  Note: {}.\n", note);
  if (r.verdict != DiffVerdict::Fail) {
    fmt::print("PASS: every check above holds{}\n",
               note.empty() ? "" : " (but see the note on mean z^2)");
  } else {
    std::string reasons;
    for (const std::string& f : failed) reasons += (reasons.empty() ? "" : ", ") + f;
    fmt::print("FAILURE{}\n", reasons.empty() ? "" : ": " + reasons);
  }
}

// Prints the verdict; true when the images differ (a warning passes).
bool runDiff(const DiffOptions& o) {
  // An unreadable image (ImageReadError) or a failed write (OutputError) goes to main.
  const Comparison c = compareImages(o);
  if (o.json)
    fmt::print("{}\n", comparisonJson(o, c));
  else if (c.plain)
    printText(o, *c.plain, c.flip);
  else
    printText(o, *c.statistical, c.flip);
  return c.differ();
}

}  // namespace

void addDiffCommand(CLI::App& app, Outcome* outcome) {
  auto options = std::make_shared<DiffOptions>();
  const CLI::Validator nonNegative = numberIn({.ge = 0}), percent = numberIn({.ge = 0, .le = 100});
  CLI::App* cmd = app.add_subcommand(
      "diff", "Compare two images; exit 0 pass, 1 fail (or different sizes), 2 bad input");
  cmd->add_option("A", options->a, "Image to check")->required();
  cmd->add_option("B", options->b, "Reference image")->required();
  cmd->add_option("--fail", options->thresholds.fail, "Absolute error above which a pixel fails")
      ->capture_default_str()
      ->check(nonNegative);
  cmd->add_option("--failpercent", options->thresholds.failPercent,
                  "Fail only when more than this percentage of pixels fail")
      ->capture_default_str()
      ->check(percent);
  cmd->add_option("--warn", options->thresholds.warn, "Absolute error above which a pixel warns")
      ->capture_default_str()
      ->check(nonNegative);
  cmd->add_option("--warnpercent", options->thresholds.warnPercent,
                  "Warn only when more than this percentage of pixels warn")
      ->capture_default_str()
      ->check(percent);
  cmd->add_flag("--json", options->json, "Print the metrics as JSON on stdout");
  cmd->add_flag("--statistical", options->statistical,
                "Per-pixel z-tests of A against B's mean and variance (B needs variance.R/G/B, "
                "as `glint render --aovs` writes), a global bias test and an error cap; the "
                "idiff thresholds above are then unused");
  cmd->add_option("--significance", options->statistics.significance,
                  "Statistical mode: family-wise false-alarm rate (Sidak-corrected per pixel)")
      ->capture_default_str()
      ->check(numberIn({.ge = 1e-12, .le = 0.5}));
  cmd->add_option("--min-pass", options->statistics.minPassPercent,
                  "Statistical mode: percentage of pixels that must pass their test")
      ->capture_default_str()
      ->check(percent);
  cmd->add_option("--max-error", options->statistics.maxError,
                  "Statistical mode: fail when a pixel that fails its z-test has a channel with "
                  "|a-b|/max(1,|b|) above this (default: no cap)")
      ->check(nonNegative);
  cmd->add_option("--spp-a", options->statistics.sppA,
                  "Statistical mode: samples per pixel of A (default: its glint:spp)")
      ->check(numberIn({.ge = 1}, true));
  cmd->add_option("--spp-b", options->statistics.sppB,
                  "Statistical mode: samples per pixel of B (default: its glint:spp)")
      ->check(numberIn({.ge = 1}, true));
  cmd->add_option("--heatmap", options->heatMap,
                  "Statistical mode: write a heat map of each pixel's |z| (black, blue, yellow "
                  "at the failure threshold, red, white) to this PNG/EXR");
  cmd->add_flag("--flip", options->flip,
                "Also compute FLIP, a perceptual difference (HPG 2020): LDR-FLIP for two "
                "PNG/JPEG images, HDR-FLIP for two EXRs");
  cmd->add_option("--ppd", options->pixelsPerDegree,
                  "FLIP: pixels per degree of visual angle (default: 0.7 m from a 0.7 m wide "
                  "3840-pixel monitor)")
      ->check(numberIn({.gt = 0}));
  cmd->add_option("--flip-max", options->flipMax,
                  "FLIP: fail when the mean FLIP error exceeds this (default: no limit)")
      ->check(numberIn({.ge = 0, .le = 1}));
  cmd->add_option("--flip-map", options->flipMap,
                  "FLIP: write the error map (magma colours) to this PNG");
  cmd->callback([options, outcome] { outcome->imagesDiffer = runDiff(*options); });
}

}  // namespace glint::app
