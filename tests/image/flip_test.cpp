// Tests for image/flip: LDR-FLIP and HDR-FLIP (Andersson et al. 2020, 2021) on image pairs
// whose answer is known by hand or by an independent computation in this file.
//
// No published reference numbers are checked: the FLIP authors' reference pairs and expected
// pooled values ship as images this repository does not carry. The closed-form cases below
// (uniform images, where FLIP reduces to the re-mapped HyAB distance) are computed here from
// textbook colour constants, independently of image/flip.cpp.
#include "image/flip.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

namespace glint {
namespace {

using Image = std::vector<float>;

Image uniform(int w, int h, Rgb c) {
  Image img(size_t(w) * size_t(h) * 3);
  for (size_t i = 0; i < img.size(); i += 3) img[i] = c.x, img[i + 1] = c.y, img[i + 2] = c.z;
  return img;
}

// A smooth, colourful LDR test image with some detail: sines of different frequencies.
Image pattern(int w, int h) {
  Image img(size_t(w) * size_t(h) * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      size_t i = 3 * (size_t(y) * size_t(w) + size_t(x));
      img[i] = 0.5f + 0.3f * std::sin(0.11f * float(x) + 0.05f * float(y));
      img[i + 1] = 0.5f + 0.3f * std::sin(0.07f * float(y) + 1.0f);
      img[i + 2] = 0.4f + 0.2f * std::cos(0.13f * float(x + y));
    }
  return img;
}

Image noise(int w, int h, unsigned seed, float lo = 0, float hi = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  Image img(size_t(w) * size_t(h) * 3);
  for (float& v : img) v = u(rng);
  return img;
}

float& at(Image& img, int w, int x, int y, int c) {
  return img[3 * (size_t(y) * size_t(w) + size_t(x)) + size_t(c)];
}

// ---- an independent colour computation -------------------------------------------------------
//
// Double precision, with Lindbloom's sRGB (D65) matrix and white rounded to 7 digits, where
// flip.cpp derives its matrix from the primaries: the two agree to ~1e-6 relative.

struct D3 {
  double x, y, z;
};

double toLinear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

D3 huntLab(D3 srgbOrLinear, bool isSrgb) {
  D3 l = isSrgb ? D3{toLinear(srgbOrLinear.x), toLinear(srgbOrLinear.y), toLinear(srgbOrLinear.z)}
                : srgbOrLinear;
  double X = 0.4124564 * l.x + 0.3575761 * l.y + 0.1804375 * l.z;
  double Y = 0.2126729 * l.x + 0.7151522 * l.y + 0.0721750 * l.z;
  double Z = 0.0193339 * l.x + 0.1191920 * l.y + 0.9503041 * l.z;
  auto f = [](double t) {
    const double d = 6.0 / 29.0;
    return t > d * d * d ? std::cbrt(t) : t / (3 * d * d) + 4.0 / 29.0;
  };
  double fx = f(X / 0.9504559), fy = f(Y / 1.0), fz = f(Z / 1.0890578);
  double L = 116 * fy - 16, a = 500 * (fx - fy), b = 200 * (fy - fz);
  return {L, 0.01 * L * a, 0.01 * L * b};
}

double hyab(D3 p, D3 q) { return std::abs(p.x - q.x) + std::hypot(p.y - q.y, p.z - q.z); }

// HPG 2020, Sec. 4.2: ΔE_c = re-mapped HyAB^qc, qc = 0.7, pc = 0.4, pt = 0.95, cmax from the
// green–blue distance.
double expectedColorError(D3 srgbA, D3 srgbB) {
  const double qc = 0.7, pc = 0.4, pt = 0.95;
  double cmax = std::pow(hyab(huntLab({0, 1, 0}, false), huntLab({0, 0, 1}, false)), qc);
  double e = std::pow(hyab(huntLab(srgbA, true), huntLab(srgbB, true)), qc);
  return e < pc * cmax ? pt / (pc * cmax) * e
                       : pt + (e - pc * cmax) / (cmax - pc * cmax) * (1 - pt);
}

// ---- LDR-FLIP --------------------------------------------------------------------------------

TEST(Flip, DefaultPixelsPerDegreeIsThePapersObserver) {
  // 0.7 m from a 0.7 m wide 3840-pixel monitor: 3840 · π / 180.
  EXPECT_NEAR(flipPixelsPerDegree(0.7, 3840, 0.7), 67.0206432, 1e-6);
  EXPECT_NEAR(kFlipDefaultPixelsPerDegree, 67.0206432, 1e-6);
}

TEST(Flip, IdenticalImagesGiveZeroEverywhere) {
  const int w = 48, h = 32;
  for (const Image& img : {pattern(w, h), noise(w, h, 3)}) {
    FlipResult r = flipLdr(img, img, w, h);
    ASSERT_EQ(r.error.size(), size_t(w * h));
    EXPECT_EQ(*std::max_element(r.error.begin(), r.error.end()), 0.0f);
    EXPECT_EQ(r.stats.mean, 0.0);
    EXPECT_EQ(r.stats.max, 0.0);
    EXPECT_EQ(r.stats.weightedMedian, 0.0);
  }
}

TEST(Flip, IsSymmetric) {
  const int w = 40, h = 30;
  Image a = pattern(w, h), b = noise(w, h, 7, 0.2f, 0.8f);
  FlipResult ab = flipLdr(a, b, w, h), ba = flipLdr(b, a, w, h);
  for (size_t i = 0; i < ab.error.size(); ++i) ASSERT_NEAR(ab.error[i], ba.error[i], 1e-6f) << i;
}

TEST(Flip, ErrorMapStaysInTheUnitInterval) {
  // Odd sizes, smaller than the filters' support, down to a single pixel.
  const std::pair<int, int> sizes[] = {{37, 23}, {1, 1}, {1, 9}, {12, 1}};
  for (unsigned seed = 1; seed <= 4; ++seed) {
    auto [w, h] = sizes[seed - 1];
    FlipResult r = flipLdr(noise(w, h, seed), noise(w, h, seed + 100), w, h);
    ASSERT_EQ(r.error.size(), size_t(w) * size_t(h));
    for (float e : r.error) {
      ASSERT_TRUE(std::isfinite(e));
      ASSERT_GE(e, 0.0f);
      ASSERT_LE(e, 1.0f);
    }
    EXPECT_GT(r.stats.mean, 0.1) << w << "×" << h;  // noise against other noise: clearly different
  }
}

TEST(Flip, LargerColourShiftGivesLargerMeanError) {
  const int w = 48, h = 32;
  Image ref = pattern(w, h);
  double previous = 0;
  for (float shift : {0.01f, 0.03f, 0.06f, 0.1f, 0.2f, 0.35f}) {
    Image test = ref;
    for (size_t i = 0; i < test.size(); i += 3) test[i] = std::min(1.0f, test[i] + shift);
    double mean = flipLdr(ref, test, w, h).stats.mean;
    EXPECT_GT(mean, previous) << "shift " << shift;
    previous = mean;
  }
  EXPECT_GT(previous, 0.3);
}

TEST(Flip, UniformImagesReduceToTheRemappedHyabDistance) {
  // On uniform images the CSF filters return the image, the feature detectors respond with 0,
  // so FLIP = ΔE_c^(1 − 0) = the re-mapped HyAB distance of the two colours.
  const int w = 24, h = 24;
  const D3 pairs[][2] = {{{0.5, 0.5, 0.5}, {0.55, 0.5, 0.5}}, {{0.2, 0.4, 0.6}, {0.2, 0.45, 0.6}},
                         {{0.9, 0.1, 0.1}, {0.1, 0.9, 0.1}},  {{0.0, 0.0, 0.0}, {0.05, 0.05, 0.05}},
                         {{0.3, 0.3, 0.8}, {0.8, 0.8, 0.3}},  {{1.0, 1.0, 1.0}, {0.95, 1.0, 0.9}}};
  for (const auto& p : pairs) {
    Image a = uniform(w, h, {float(p[0].x), float(p[0].y), float(p[0].z)});
    Image b = uniform(w, h, {float(p[1].x), float(p[1].y), float(p[1].z)});
    double expected = expectedColorError(p[0], p[1]);
    FlipComponents c = flipLdrComponents(a, b, w, h);
    FlipResult r = flipLdr(a, b, w, h);
    for (size_t i = 0; i < r.error.size(); ++i) {
      ASSERT_LT(c.feature[i], 1e-3f);  // float rounding of a zero response
      ASSERT_NEAR(c.color[i], expected, 2e-4 + 1e-3 * expected) << p[0].x << " vs " << p[1].x;
      ASSERT_NEAR(r.error[i], std::pow(c.color[i], 1 - c.feature[i]), 1e-6);
    }
    EXPECT_NEAR(r.stats.mean, expected, 2e-3 + 1e-3 * expected);
  }
}

TEST(Flip, BlackAgainstWhiteIsNearOne) {
  // HyAB = 100 (L* 0 vs 100, no chroma): above pc·cmax, so ΔE = pt + a little ≈ 0.967.
  const int w = 16, h = 16;
  FlipResult r = flipLdr(uniform(w, h, {0, 0, 0}), uniform(w, h, {1, 1, 1}), w, h);
  double expected = expectedColorError({0, 0, 0}, {1, 1, 1});
  EXPECT_NEAR(expected, 0.967, 0.002);  // the hand value
  EXPECT_NEAR(r.stats.min, expected, 1e-3);
  EXPECT_NEAR(r.stats.max, expected, 1e-3);
}

TEST(Flip, CsfFiltersAreNormalised) {
  // A uniform image filters to itself (its linear RGB) at any viewing distance.
  const int w = 30, h = 20;
  for (double ppd : {8.0, 30.0, kFlipDefaultPixelsPerDegree, 120.0})
    for (Rgb c : {Rgb{0.5f, 0.5f, 0.5f}, Rgb{0.9f, 0.2f, 0.1f}, Rgb{0.1f, 0.3f, 1.0f}}) {
      std::vector<float> f = flipCsfFiltered(uniform(w, h, c), w, h, ppd);
      float lin[3] = {float(toLinear(c.x)), float(toLinear(c.y)), float(toLinear(c.z))};
      for (size_t i = 0; i < f.size(); ++i)
        ASSERT_NEAR(f[i], lin[i % 3], 2e-5f) << "ppd " << ppd << " channel " << i % 3;
    }
}

TEST(Flip, CsfFilterBlursAWhiteDotSymmetrically) {
  const int w = 41, h = 41, cx = 20, cy = 20;
  Image img = uniform(w, h, {0, 0, 0});
  for (int c = 0; c < 3; ++c) at(img, w, cx, cy, c) = 1;
  std::vector<float> f = flipCsfFiltered(img, w, h);
  auto lum = [&](int x, int y) {
    size_t i = 3 * (size_t(y) * w + size_t(x));
    return 0.2126f * f[i] + 0.7152f * f[i + 1] + 0.0722f * f[i + 2];
  };
  EXPECT_LT(lum(cx, cy), 0.9f);                          // spread out …
  EXPECT_GT(lum(cx + 1, cy), 0.01f);                     // … onto the neighbours,
  EXPECT_NEAR(lum(cx + 2, cy), lum(cx - 2, cy), 1e-6f);  // evenly in x and y
  EXPECT_NEAR(lum(cx, cy + 2), lum(cx + 2, cy), 1e-6f);
  EXPECT_GT(lum(cx + 1, cy), lum(cx + 3, cy));
}

// The paper's CSF kernel of one opponent channel at (x, y) pixels, normalised to sum 1:
// Σ a_i √(π/b_i) exp(−π² d² / b_i), d in degrees, on a (2r+1)² window with
// r = ⌈3 √(b_max / 2π²) · ppd⌉, b_max = 0.04.
double csfWeight(int channel, int x, int y, double ppd) {
  const double pi = 3.14159265358979323846;
  const double p[3][4] = {{1, 0.0047, 0, 1}, {1, 0.0053, 0, 1}, {34.1, 0.04, 13.5, 0.025}};
  const int r = int(std::ceil(3 * std::sqrt(0.04 / (2 * pi * pi)) * ppd));
  auto s = [&](int u, int v) {
    double d2 = (u * u + v * v) / (ppd * ppd);
    const double* q = p[channel];
    return q[0] * std::sqrt(pi / q[1]) * std::exp(-pi * pi * d2 / q[1]) +
           q[2] * std::sqrt(pi / q[3]) * std::exp(-pi * pi * d2 / q[3]);
  };
  double sum = 0;
  for (int v = -r; v <= r; ++v)
    for (int u = -r; u <= r; ++u) sum += s(u, v);
  return s(x, y) / sum;
}

// Linear sRGB ↔ YCxCz (D65), with Lindbloom's matrices.
D3 ycxczFromLinear(D3 l) {
  double X = 0.4124564 * l.x + 0.3575761 * l.y + 0.1804375 * l.z;
  double Y = 0.2126729 * l.x + 0.7151522 * l.y + 0.0721750 * l.z;
  double Z = 0.0193339 * l.x + 0.1191920 * l.y + 0.9503041 * l.z;
  X /= 0.9504559, Z /= 1.0890578;
  return {116 * Y - 16, 500 * (X - Y), 200 * (Y - Z)};
}

D3 linearFromYcxcz(D3 c) {
  double Y = (c.x + 16) / 116, X = (Y + c.y / 500) * 0.9504559, Z = (Y - c.z / 200) * 1.0890578;
  return {3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z,
          -0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z,
          0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z};
}

TEST(Flip, CsfKernelsAreThePapersGaussians) {
  // An impulse in one opponent channel (Y, Cx or Cz) on a grey: after filtering, that channel
  // is the background plus the impulse times the paper's 2-D kernel; the others are unchanged.
  const int w = 41, h = 41, cx = 20, cy = 20;
  const D3 background = {7.2, 0, 0};  // linear grey 0.2
  const double impulse = 6;
  for (double ppd : {30.0, kFlipDefaultPixelsPerDegree})
    for (int channel = 0; channel < 3; ++channel) {
      D3 dot = background;
      (channel == 0 ? dot.x : channel == 1 ? dot.y : dot.z) += impulse;
      auto encode = [](D3 c) {
        D3 l = linearFromYcxcz(c);
        auto e = [](double v) {
          return float(v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055);
        };
        return Rgb{e(l.x), e(l.y), e(l.z)};
      };
      Image img = uniform(w, h, encode(background));
      Rgb d = encode(dot);
      at(img, w, cx, cy, 0) = d.x, at(img, w, cx, cy, 1) = d.y, at(img, w, cx, cy, 2) = d.z;
      std::vector<float> f = flipCsfFiltered(img, w, h, ppd);
      for (auto [x, y] : {std::pair{0, 0}, std::pair{1, 0}, std::pair{0, 3}, std::pair{4, 2}}) {
        size_t i = 3 * (size_t(cy + y) * w + size_t(cx + x));
        D3 got = ycxczFromLinear({f[i], f[i + 1], f[i + 2]});
        double expected = impulse * csfWeight(channel, x, y, ppd);
        double values[3] = {got.x - background.x, got.y - background.y, got.z - background.z};
        for (int k = 0; k < 3; ++k)
          EXPECT_NEAR(values[k], k == channel ? expected : 0.0, 2e-3 + 1e-3 * expected)
              << "ppd " << ppd << " channel " << channel << " at " << x << "," << y << " out " << k;
      }
      // The support is the paper's radius, set by the widest Gaussian (BY's b = 0.04 deg²):
      // the impulse reaches (r, 0) and not (r + 1, 0), where the result is bit for bit the
      // background's.
      const double pi = 3.14159265358979323846;
      const int r = int(std::ceil(3 * std::sqrt(0.04 / (2 * pi * pi)) * ppd));
      auto pixel = [&](int x, int y) {
        size_t i = 3 * (size_t(y) * w + size_t(x));
        return Rgb{f[i], f[i + 1], f[i + 2]};
      };
      Rgb far = pixel(0, 0);
      if (channel == 2) {
        EXPECT_FALSE(pixel(cx + r, cy) == far) << "ppd " << ppd;
      }
      EXPECT_TRUE(pixel(cx + r + 1, cy) == far) << "ppd " << ppd << " channel " << channel;
      EXPECT_TRUE(pixel(cx, cy - r - 1) == far) << "ppd " << ppd << " channel " << channel;
    }
}

TEST(Flip, ThinLineIsDetectedByTheFeaturePipeline) {
  // A one-pixel vertical line and a wide Gaussian ridge that add the same linear light to a
  // mid-grey image: the CSF blurs both, but only the line has the sharp edges the feature
  // detectors see, so its error is boosted well above its colour error and above the ridge's.
  const int w = 64, h = 32, cx = 32;
  const float grey = 0.5f, lineSrgb = 0.8f;
  const double base = toLinear(grey), energy = toLinear(lineSrgb) - base;
  Image ref = uniform(w, h, {grey, grey, grey}), line = ref, ridge = ref;
  const double sigma = 6.0;
  double norm = 0;
  for (int x = 0; x < w; ++x) norm += std::exp(-0.5 * (x - cx) * (x - cx) / (sigma * sigma));
  for (int y = 0; y < h; ++y)
    for (int c = 0; c < 3; ++c) {
      at(line, w, cx, y, c) = lineSrgb;
      for (int x = 0; x < w; ++x) {
        double add = energy * std::exp(-0.5 * (x - cx) * (x - cx) / (sigma * sigma)) / norm;
        double lin = base + add;  // back to sRGB encoding
        at(ridge, w, x, y, c) =
            float(lin <= 0.0031308 ? 12.92 * lin : 1.055 * std::pow(lin, 1 / 2.4) - 0.055);
      }
    }
  FlipComponents lc = flipLdrComponents(ref, line, w, h);
  FlipComponents rc = flipLdrComponents(ref, ridge, w, h);
  FlipResult lr = flipLdr(ref, line, w, h), rr = flipLdr(ref, ridge, w, h);
  size_t mid = size_t(h / 2) * w + cx;
  EXPECT_GT(lc.feature[mid], 0.2f);
  EXPECT_LT(*std::max_element(rc.feature.begin(), rc.feature.end()), 0.5f * lc.feature[mid]);
  EXPECT_GT(lr.error[mid], 1.2f * lc.color[mid]);  // the feature term raises the error
  EXPECT_GT(lr.stats.max, 1.5 * rr.stats.max);
}

TEST(Flip, SinglePixelPointFeatureMatchesTheHandValue) {
  // A one-pixel grey point of luminance step ΔY on a uniform grey. At the point the edge
  // detectors (odd kernels) respond with 0 in both images; each point detector responds with
  // ΔY · ddg(0) · g(0) along x and along y, so the feature difference is √2 · |ddg(0)| g(0) ΔY
  // and ΔE_f = (that / √2)^qf, qf = 0.5. ddg and g are the paper's kernels: σ = 0.082/2 · ppd,
  // radius ⌈3σ⌉, g summing to 1, ddg = (x²/σ² − 1)·exp(−x²/2σ²) with positive and negative
  // weights summing to ±1.
  const int w = 33, h = 33, c = 16;
  const float lo = 0.3f, hi = 0.7f;
  Image ref = uniform(w, h, {lo, lo, lo}), test = ref;
  for (int k = 0; k < 3; ++k) at(test, w, c, c, k) = hi;

  const double sd = 0.5 * 0.082 * kFlipDefaultPixelsPerDegree;
  const int r = int(std::ceil(3 * sd));
  double gSum = 0, ddgNeg = 0;
  for (int x = -r; x <= r; ++x) {
    double g = std::exp(-x * x / (2 * sd * sd)), ddg = (x * x / (sd * sd) - 1) * g;
    gSum += g;
    if (ddg < 0) ddgNeg -= ddg;
  }
  const double dY = toLinear(hi) - toLinear(lo);  // Y of a grey is its linear value
  const double expected = std::sqrt((1 / ddgNeg) * (1 / gSum) * dY);

  FlipComponents comp = flipLdrComponents(ref, test, w, h);
  FlipResult res = flipLdr(ref, test, w, h);
  size_t i = size_t(c) * w + c;
  EXPECT_NEAR(comp.feature[i], expected, 1e-4);
  EXPECT_NEAR(comp.feature[i], 0.1276, 1e-3);  // the number, for the record
  EXPECT_GT(res.error[i], comp.color[i]);      // the feature term raises the error
  EXPECT_EQ(res.stats.maxX, c);
  EXPECT_EQ(res.stats.maxY, c);
  EXPECT_EQ(res.error[0], 0.0f);  // far from the point nothing differs
}

TEST(Flip, StepEdgeFeatureIsTheLuminanceStep) {
  // A vertical step from luminance Y0 to Y1 between columns c − 1 and c, against a uniform Y0.
  // The edge filter across x, dg(x)·g(y), has its positive weights (x < 0) summing to 1 and its
  // negative ones (x > 0) to −1, so on both columns next to the step it responds with exactly
  // Y0 − Y1, whatever the viewing distance; the point response there is smaller. Hence
  // ΔE_f = (ΔY / √2)^0.5 on those columns.
  const int w = 64, h = 16, c = 32;
  const float lo = 0.25f, hi = 0.6f;
  Image ref = uniform(w, h, {lo, lo, lo}), test = ref;
  for (int y = 0; y < h; ++y)
    for (int x = c; x < w; ++x)
      for (int k = 0; k < 3; ++k) at(test, w, x, y, k) = hi;
  const double expected = std::sqrt((toLinear(hi) - toLinear(lo)) / std::sqrt(2.0));
  for (double ppd : {20.0, kFlipDefaultPixelsPerDegree, 100.0}) {
    FlipComponents comp = flipLdrComponents(ref, test, w, h, ppd);
    for (int y : {0, h / 2, h - 1})
      for (int x : {c - 1, c}) EXPECT_NEAR(comp.feature[size_t(y) * w + x], expected, 1e-4) << ppd;
  }
}

TEST(Flip, RejectsBuffersOfTheWrongSize) {
  Image a = uniform(4, 4, {0.5f, 0.5f, 0.5f});
  Image b = uniform(4, 3, {0.5f, 0.5f, 0.5f});
  EXPECT_THROW(flipLdr(a, b, 4, 4), std::logic_error);
  EXPECT_THROW(flipLdr(a, a, 0, 4), std::logic_error);
  EXPECT_THROW(flipLdr(a, a, 4, 4, 0.0), std::logic_error);
  EXPECT_THROW(flipHdr(a, b, 4, 4), std::logic_error);
}

TEST(Flip, NonFiniteInputCountsAsZero) {
  const int w = 8, h = 8;
  Image a = uniform(w, h, {0, 0, 0}), b = a;
  at(b, w, 3, 3, 0) = std::nanf("");
  at(b, w, 4, 4, 1) = -1;  // clamped to 0 in LDR
  FlipResult r = flipLdr(a, b, w, h);
  EXPECT_EQ(r.stats.max, 0.0);
}

// ---- pooling and display ---------------------------------------------------------------------

TEST(Flip, WeightedPercentilesAndStatistics) {
  // Sorted 0.1, 0.2, 0.3, 0.4 (sum 1): running sums 0.1, 0.3, 0.6, 1.0.
  std::vector<float> e = {0.4f, 0.1f, 0.3f, 0.2f};
  EXPECT_FLOAT_EQ(flipWeightedPercentile(e, 0.25), 0.2f);
  EXPECT_FLOAT_EQ(flipWeightedPercentile(e, 0.5), 0.3f);
  EXPECT_FLOAT_EQ(flipWeightedPercentile(e, 0.75), 0.4f);
  FlipStats s = flipStatistics(e, 2);
  EXPECT_NEAR(s.mean, 0.25, 1e-7);
  EXPECT_FLOAT_EQ(s.min, 0.1f);
  EXPECT_FLOAT_EQ(s.max, 0.4f);
  EXPECT_EQ(s.maxX, 0);
  EXPECT_EQ(s.maxY, 0);
  EXPECT_FLOAT_EQ(s.weightedQuartile1, 0.2f);
  EXPECT_FLOAT_EQ(s.weightedMedian, 0.3f);
  EXPECT_FLOAT_EQ(s.weightedQuartile3, 0.4f);
  EXPECT_FLOAT_EQ(s.percentile95, 0.4f);  // nearest rank: ceil(0.95 * 4) = 4th
  // The 95th percentile of 0.01, 0.02, ..., 1.00 (shuffled) is 0.95 by nearest rank; a
  // weighted percentile would say more, as the large errors carry the sum.
  std::vector<float> hundred;
  for (int i = 0; i < 100; ++i) hundred.push_back(float((i * 37) % 100 + 1) / 100);
  EXPECT_FLOAT_EQ(flipStatistics(hundred, 10).percentile95, 0.95f);
  // A weighted median leans towards the large errors that carry the sum.
  std::vector<float> skewed(50, 0.01f);
  skewed[7] = 0.9f;
  EXPECT_FLOAT_EQ(flipWeightedPercentile(skewed, 0.5), 0.9f);
  EXPECT_EQ(flipWeightedPercentile(std::vector<float>(10, 0.0f), 0.5), 0.0);
}

TEST(Flip, MagmaHeatMap) {
  Rgb lo = flipMagma(0), hi = flipMagma(1);
  EXPECT_FLOAT_EQ(lo.x, 0.001462f);
  EXPECT_FLOAT_EQ(lo.z, 0.013866f);
  EXPECT_FLOAT_EQ(hi.x, 0.987053f);
  EXPECT_FLOAT_EQ(hi.z, 0.749504f);
  EXPECT_EQ(flipMagma(-3).x, lo.x);
  EXPECT_EQ(flipMagma(7).y, hi.y);
  EXPECT_EQ(flipMagma(std::nanf("")).x, lo.x);
  // Magma's lightness rises monotonically: a brighter colour means a larger error.
  float previous = -1;
  for (int i = 0; i <= 255; ++i) {
    float y = luminance(flipMagma(float(i) / 255));
    ASSERT_GT(y, previous) << i;
    previous = y;
  }
  std::vector<float> heat = flipHeatMap(std::vector<float>{0, 0.5f, 1});
  ASSERT_EQ(heat.size(), 9u);
  EXPECT_EQ(heat[3], flipMagma(0.5f).x);
  EXPECT_EQ(heat[8], hi.z);
}

// ---- HDR-FLIP --------------------------------------------------------------------------------

double acesExposureAt085() {
  // Narkowicz's ACES fit with the 0.6 pre-exposure: (2.51·(0.6x)² + 0.03·0.6x) /
  // (2.43·(0.6x)² + 0.59·0.6x + 0.14) = 0.85, solved for x > 0.
  double a = 2.51 * 0.36 - 0.85 * 2.43 * 0.36, b = 0.03 * 0.6 - 0.85 * 0.59 * 0.6, c = -0.85 * 0.14;
  return (-b + std::sqrt(b * b - 4 * a * c)) / (2 * a);
}

TEST(Flip, ToneMappersMatchTheirCurves) {
  double x = acesExposureAt085();
  EXPECT_NEAR(flipToneMap({float(x), 0, 0}, 0, FlipToneMapper::Aces).x, 0.85, 1e-5);
  EXPECT_NEAR(flipToneMap({float(x / 4), 0, 0}, 2, FlipToneMapper::Aces).x, 0.85, 1e-5);
  // Hable's filmic curve with exposure bias 2 and white 11.2.
  auto hable = [](double v) {
    const double A = 0.15, B = 0.5, C = 0.1, D = 0.2, E = 0.02, F = 0.3;
    return (v * (A * v + C * B) + D * E) / (v * (A * v + B) + D * F) - E / F;
  };
  for (float v : {0.05f, 0.3f, 1.0f, 4.0f})
    EXPECT_NEAR(flipToneMap({v, v, v}, 0, FlipToneMapper::Hable).y,
                std::min(1.0, hable(2.0 * v) / hable(11.2)), 1e-5)
        << v;
  // Reinhard divides by 1 + luminance.
  Rgb r = flipToneMap({1, 0.5f, 0.25f}, 0, FlipToneMapper::Reinhard);
  double y = 0.2126 + 0.7152 * 0.5 + 0.0722 * 0.25;
  EXPECT_NEAR(r.x, 1 / (1 + y), 1e-6);
  EXPECT_NEAR(r.z, 0.25 / (1 + y), 1e-6);
  // Negative, NaN and infinite input.
  EXPECT_EQ(flipToneMap({-1, std::nanf(""), kInfinity}, 0, FlipToneMapper::Aces).x, 0.0f);
  EXPECT_EQ(flipToneMap({-1, std::nanf(""), kInfinity}, 0, FlipToneMapper::Aces).y, 0.0f);
  EXPECT_EQ(flipToneMap({-1, std::nanf(""), kInfinity}, 0, FlipToneMapper::Aces).z, 1.0f);
}

TEST(Flip, HdrExposureRangeFollowsThePaper) {
  // Luminances: a 4×4 image, 12 grey pixels at 0.6 and 4 at 8 (max 8, median 0.6).
  const int w = 4, h = 4;
  Image img = uniform(w, h, {0.6f, 0.6f, 0.6f});
  for (int x = 0; x < 4; ++x)
    for (int c = 0; c < 3; ++c) at(img, w, x, 0, c) = 8;
  double xt = acesExposureAt085();
  FlipExposures e = flipExposureRange(img, w, h);
  EXPECT_NEAR(e.start, std::log2(xt / 8), 1e-4);
  EXPECT_NEAR(e.stop, std::log2(xt / 0.6), 1e-4);
  EXPECT_EQ(e.count, 4);  // ⌈log2(8 / 0.6)⌉ = ⌈3.74⌉ stops
  // All black: no range.
  FlipExposures black = flipExposureRange(uniform(w, h, {0, 0, 0}), w, h);
  EXPECT_EQ(black.start, 0);
  EXPECT_EQ(black.stop, 0);
  EXPECT_EQ(black.count, 1);
  // Mostly black (median 0): the median of the lit pixels, not an infinite exposure.
  Image dark = uniform(w, h, {0, 0, 0});
  for (int x = 0; x < 3; ++x)
    for (int c = 0; c < 3; ++c) at(dark, w, x, 1, c) = 2;
  FlipExposures d = flipExposureRange(dark, w, h);
  EXPECT_NEAR(d.stop, std::log2(xt / 2), 1e-4);
  EXPECT_EQ(d.count, 1);  // start = stop
}

Image toneMappedSrgb(const Image& hdr, float exposure) {
  Image out(hdr.size());
  auto encode = [](float c) {
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1 / 2.4f) - 0.055f;
  };
  for (size_t i = 0; i < hdr.size(); i += 3) {
    Rgb c = flipToneMap({hdr[i], hdr[i + 1], hdr[i + 2]}, exposure, FlipToneMapper::Aces);
    out[i] = encode(c.x), out[i + 1] = encode(c.y), out[i + 2] = encode(c.z);
  }
  return out;
}

TEST(Flip, HdrIsTheMaximumOfLdrFlipOverExposures) {
  const int w = 32, h = 24;
  Image ref = noise(w, h, 11, 0, 6), test = ref;
  for (size_t i = 0; i < test.size(); i += 5) test[i] *= 1.3f;
  FlipHdrOptions opt;
  opt.startExposure = -3;
  opt.stopExposure = 1;
  opt.exposureCount = 3;  // -3, -1, 1
  FlipResult hdr = flipHdr(ref, test, w, h, opt);
  EXPECT_EQ(hdr.exposures.count, 3);
  std::vector<float> expected(size_t(w * h), 0.0f);
  for (float e : {-3.0f, -1.0f, 1.0f}) {
    FlipResult ldr = flipLdr(toneMappedSrgb(ref, e), toneMappedSrgb(test, e), w, h);
    for (size_t i = 0; i < expected.size(); ++i) expected[i] = std::max(expected[i], ldr.error[i]);
  }
  for (size_t i = 0; i < expected.size(); ++i) ASSERT_NEAR(hdr.error[i], expected[i], 1e-5f) << i;
  EXPECT_GT(hdr.stats.mean, 0.01);
}

TEST(Flip, HdrDefaultsAndIdenticalImages) {
  const int w = 32, h = 24;
  Image ref = noise(w, h, 5, 0, 20);
  FlipResult same = flipHdr(ref, ref, w, h);
  EXPECT_EQ(same.stats.max, 0.0);
  FlipExposures e = flipExposureRange(ref, w, h);
  EXPECT_EQ(same.exposures.start, e.start);
  EXPECT_EQ(same.exposures.stop, e.stop);
  EXPECT_EQ(same.exposures.count, e.count);
  EXPECT_GE(e.count, 2);
  FlipHdrOptions backwards;
  backwards.startExposure = 2;
  backwards.stopExposure = 1;
  EXPECT_THROW(flipHdr(ref, ref, w, h, backwards), std::logic_error);
}

}  // namespace
}  // namespace glint
