// glint — statistical image comparison: per-pixel z-tests with a Šidák correction, a global
// bias test and a hard error cap (see statistical_diff.h for the model).
#include "image/statistical.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "image/output.h"

namespace glint {

namespace {

constexpr const char* kColor[3] = {"R", "G", "B"};
constexpr const char* kVariance[3] = {"variance.R", "variance.G", "variance.B"};

// Channel indices of R, G, B (or variance.R/G/B) in `image`; empty when one is missing.
std::vector<int> channelsOf(const Image& image, const char* const (&names)[3]) {
  std::vector<int> index;
  for (const char* name : names) {
    int c = image.channel(name);
    if (c < 0) return {};
    index.push_back(c);
  }
  return index;
}

// The noise floor: samples that all agree still differ across CPUs in their last bits.
double floorSigma(double reference) { return 1e-4 + 1e-3 * std::abs(reference); }

}  // namespace

double normalTwoSidedQuantile(double p) {
  if (!(p > 0)) return std::numeric_limits<double>::infinity();
  if (p >= 1) return 0;
  // erfc(z/√2) falls monotonically in z: bisect (p is at worst ~1e-300, z < 40).
  double lo = 0, hi = 40;
  for (int i = 0; i < 200 && hi - lo > 1e-12; ++i) {
    double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

StatisticalResult diffStatistical(const std::string& pathA, const std::string& pathB,
                                  const StatisticalThresholds& t) {
  return diffStatistical(readImage(pathA), pathA, readImage(pathB), pathB, t);
}

StatisticalResult diffStatistical(const Image& a, const std::string& pathA, const Image& b,
                                  const std::string& pathB, const StatisticalThresholds& t) {
  StatisticalResult r;
  r.widthA = a.width, r.heightA = a.height;
  r.widthB = b.width, r.heightB = b.height;
  if (a.width != b.width || a.height != b.height) {
    r.sizeMismatch = true;
    r.verdict = DiffVerdict::Fail;
    return r;
  }
  std::vector<int> colorA = channelsOf(a, kColor), colorB = channelsOf(b, kColor);
  if (colorA.empty()) throw ImageReadError(fmt::format("{}: has no R, G, B channels", pathA));
  if (colorB.empty()) throw ImageReadError(fmt::format("{}: has no R, G, B channels", pathB));
  std::vector<int> varB = channelsOf(b, kVariance), varA = channelsOf(a, kVariance);
  if (varB.empty())
    throw ImageReadError(fmt::format(
        "{}: the reference has no variance.R/G/B channels (render it with `glint render "
        "--aovs`)",
        pathB));
  r.sppA = t.sppA > 0 ? t.sppA : a.meta.spp;
  r.sppB = t.sppB > 0 ? t.sppB : b.meta.spp;
  const bool predicted = r.sppA > 0 && r.sppB > 0;
  const bool own = !varA.empty();
  if (!predicted && !own)
    throw ImageReadError(fmt::format(
        "{}: unknown samples per pixel (no glint:spp attribute and no --spp given) and no "
        "variance channels of its own, so its noise cannot be estimated",
        r.sppA > 0 ? pathB : pathA));
  r.varianceModel = predicted && own ? "max(own, predicted)" : predicted ? "predicted" : "own";
  const double sppRatio = predicted ? double(r.sppB) / double(r.sppA) : 0;

  const size_t n = size_t(a.width) * size_t(a.height);
  r.pixels = n;
  const double tests = 3.0 * double(n);
  // Šidák: 1 − (1 − α)^(1/N), computed without cancellation for small α.
  const double pixelAlpha = -std::expm1(std::log1p(-t.significance) / tests);
  r.pixelZ = normalTwoSidedQuantile(pixelAlpha);
  r.globalZLimit = normalTwoSidedQuantile(-std::expm1(std::log1p(-t.significance) / 3.0));
  r.zMap.assign(n, 0.0f);

  std::array<double, 3> sumDiff{}, sumVar{};
  double sumZ2 = 0;
  for (size_t i = 0; i < n; ++i) {
    const float* pa = &a.pixels[i * size_t(a.channels)];
    const float* pb = &b.pixels[i * size_t(b.channels)];
    const int x = int(i % size_t(a.width)), y = int(i / size_t(a.width));
    bool fails = false;
    double pixelMaxZ = 0;
    for (int c = 0; c < 3; ++c) {
      const double va = pa[colorA[size_t(c)]], vb = pb[colorB[size_t(c)]];
      const double varRef = pb[varB[size_t(c)]];
      const double varOwn = own ? double(pa[varA[size_t(c)]]) : 0.0;
      if (!std::isfinite(va) || !std::isfinite(vb) || !std::isfinite(varRef) ||
          !std::isfinite(varOwn)) {
        ++r.nonFinite;
        fails = true;
        pixelMaxZ = std::numeric_limits<double>::infinity();
        continue;
      }
      const double varTest = std::max(varOwn, varRef * sppRatio);
      const double floor = floorSigma(vb);
      const double var = std::max(varRef, 0.0) + std::max(varTest, 0.0) + floor * floor;
      const double diff = va - vb;
      const double z = diff / std::sqrt(var);
      sumDiff[size_t(c)] += diff;
      sumVar[size_t(c)] += var;
      sumZ2 += z * z;
      if (std::abs(z) > r.maxZ) {
        r.maxZ = std::abs(z);
        r.maxZX = x, r.maxZY = y;
        r.maxZChannel = kColor[c];
      }
      pixelMaxZ = std::max(pixelMaxZ, std::abs(z));
      if (std::abs(z) > r.pixelZ) {
        fails = true;
        const double error = std::abs(diff) / std::max(1.0, std::abs(vb));
        if (error > r.maxError) {
          r.maxError = error;
          r.maxErrorX = x, r.maxErrorY = y;
        }
      }
    }
    r.zMap[i] = float(pixelMaxZ);
    if (fails) ++r.failPixels;
  }
  r.passPercent = 100.0 * double(n - r.failPixels) / double(std::max<size_t>(n, 1));
  r.meanZ2 = sumZ2 / std::max(1.0, tests - double(r.nonFinite));
  for (int c = 0; c < 3; ++c) {
    r.globalZ[size_t(c)] =
        sumVar[size_t(c)] > 0 ? sumDiff[size_t(c)] / std::sqrt(sumVar[size_t(c)]) : 0.0;
    r.biased |= std::abs(r.globalZ[size_t(c)]) > r.globalZLimit;
  }
  r.errorCapExceeded = r.maxError > t.maxError;
  if (r.passPercent < t.minPassPercent || r.biased || r.errorCapExceeded || r.nonFinite > 0)
    r.verdict = DiffVerdict::Fail;
  return r;
}

void writeZHeatMap(const std::string& path, const StatisticalResult& result) {
  // |z| in units of the failure threshold: 0 black, 0.5 blue, 1 yellow, 1.5 red, ≥ 2 white.
  struct Stop {
    float at, r, g, b;
  };
  static constexpr Stop kStops[] = {{0.0f, 0, 0, 0},
                                    {0.5f, 0.1f, 0.2f, 0.8f},
                                    {1.0f, 1, 0.9f, 0.1f},
                                    {1.5f, 0.9f, 0.1f, 0.1f},
                                    {2.0f, 1, 1, 1}};
  const int w = result.widthA, h = result.heightA;
  std::vector<float> pixels(size_t(w) * size_t(h) * 3);
  const float scale = result.pixelZ > 0 ? float(1.0 / result.pixelZ) : 0.0f;
  for (size_t i = 0; i < result.zMap.size() && i * 3 < pixels.size(); ++i) {
    float v = std::isfinite(result.zMap[i]) ? result.zMap[i] * scale : 2.0f;
    v = std::clamp(v, 0.0f, 2.0f);
    size_t s = 1;
    while (s + 1 < std::size(kStops) && v > kStops[s].at) ++s;
    const Stop& p = kStops[s - 1];
    const Stop& q = kStops[s];
    float f = (v - p.at) / (q.at - p.at);
    pixels[3 * i + 0] = p.r + f * (q.r - p.r);
    pixels[3 * i + 1] = p.g + f * (q.g - p.g);
    pixels[3 * i + 2] = p.b + f * (q.b - p.b);
  }
  writeRawImage(path, w, h, 3, pixels);
}

}  // namespace glint
