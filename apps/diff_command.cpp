// glint — `glint diff A B`: numeric image comparison with idiff's thresholds.
#include <fmt/format.h>

#include <cmath>
#include <exception>
#include <memory>
#include <string>

#include "apps/cli_common.h"
#include "apps/commands.h"
#include "renderer/image_diff.h"

namespace glint::app {

namespace {

struct DiffOptions {
  std::string a, b;
  DiffThresholds thresholds;
  bool json = false;
};

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20)
          out += fmt::format("\\u{:04x}", int(c));
        else
          out += c;
    }
  }
  return out + "\"";
}

// JSON has no infinity (PSNR of identical images): those become null.
std::string jsonNumber(double v) { return std::isfinite(v) ? fmt::format("{}", v) : "null"; }

void printJson(const DiffOptions& o, const DiffResult& r) {
  std::string channels;
  for (const std::string& c : r.channels)
    channels += (channels.empty() ? "" : ", ") + jsonString(c);
  std::string s = "{\n";
  s += fmt::format("  \"a\": {},\n  \"b\": {},\n", jsonString(o.a), jsonString(o.b));
  s += fmt::format("  \"verdict\": \"{}\",\n  \"pass\": {},\n", verdictName(r.verdict),
                   r.verdict != DiffVerdict::Fail);
  s += fmt::format("  \"size_a\": [{}, {}],\n  \"size_b\": [{}, {}],\n", r.widthA, r.heightA,
                   r.widthB, r.heightB);
  s += fmt::format("  \"size_mismatch\": {}", r.sizeMismatch);
  if (!r.sizeMismatch) {
    s += fmt::format(",\n  \"channels\": [{}],\n  \"pixels\": {},\n", channels, r.pixels);
    s += fmt::format("  \"mean_abs_error\": {},\n  \"rmse\": {},\n  \"rel_mse\": {},\n",
                     jsonNumber(r.meanAbsError), jsonNumber(r.rmse), jsonNumber(r.relMse));
    s += fmt::format("  \"psnr\": {},\n  \"max_error\": {},\n", jsonNumber(r.psnr),
                     jsonNumber(r.maxError));
    s += fmt::format("  \"max_pixel\": [{}, {}],\n  \"max_channel\": {},\n", r.maxX, r.maxY,
                     jsonString(r.maxChannel));
    s += fmt::format("  \"fail_threshold\": {},\n  \"fail_percent_allowed\": {},\n",
                     jsonNumber(o.thresholds.fail), jsonNumber(o.thresholds.failPercent));
    s += fmt::format("  \"fail_pixels\": {},\n  \"fail_pixel_percent\": {},\n", r.failPixels,
                     jsonNumber(r.failPixelPercent));
    s += fmt::format("  \"warn_threshold\": {},\n  \"warn_percent_allowed\": {},\n",
                     jsonNumber(o.thresholds.warn), jsonNumber(o.thresholds.warnPercent));
    s += fmt::format("  \"warn_pixels\": {},\n  \"warn_pixel_percent\": {}", r.warnPixels,
                     jsonNumber(r.warnPixelPercent));
  }
  s += "\n}\n";
  fmt::print("{}", s);
}

void printText(const DiffOptions& o, const DiffResult& r) {
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
  fmt::print("{}\n", r.verdict == DiffVerdict::Pass   ? "PASS"
                     : r.verdict == DiffVerdict::Warn ? "WARNING"
                                                      : "FAILURE");
}

int runDiff(const DiffOptions& o) {
  DiffResult r;
  try {
    r = diffImages(o.a, o.b, o.thresholds);
  } catch (const ImageReadError& e) {
    printError(e.what());
    return 2;
  }
  if (o.json)
    printJson(o, r);
  else
    printText(o, r);
  return r.verdict == DiffVerdict::Fail ? 1 : 0;
}

// CLI::NonNegativeNumber prints DBL_MAX in full in its message; this one reads well.
const CLI::Validator kNonNegative(
    [](const std::string& text) -> std::string {
      try {
        return std::stod(text) >= 0 ? "" : "must be >= 0, got " + text;
      } catch (const std::exception&) {
        return "not a number: " + text;
      }
    },
    "NONNEGATIVE");

}  // namespace

void addDiffCommand(CLI::App& app, int* exitCode) {
  auto options = std::make_shared<DiffOptions>();
  CLI::App* cmd = app.add_subcommand(
      "diff", "Compare two images; exit 0 pass, 1 fail (or different sizes), 2 bad input");
  cmd->add_option("A", options->a, "Image to check")->required();
  cmd->add_option("B", options->b, "Reference image")->required();
  cmd->add_option("--fail", options->thresholds.fail, "Absolute error above which a pixel fails")
      ->capture_default_str()
      ->check(kNonNegative);
  cmd->add_option("--failpercent", options->thresholds.failPercent,
                  "Fail only when more than this percentage of pixels fail")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  cmd->add_option("--warn", options->thresholds.warn, "Absolute error above which a pixel warns")
      ->capture_default_str()
      ->check(kNonNegative);
  cmd->add_option("--warnpercent", options->thresholds.warnPercent,
                  "Warn only when more than this percentage of pixels warn")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  cmd->add_flag("--json", options->json, "Print the metrics as JSON on stdout");
  cmd->callback([options, exitCode] { *exitCode = runDiff(*options); });
}

}  // namespace glint::app
