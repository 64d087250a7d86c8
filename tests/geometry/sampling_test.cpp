// Tests for the square-to-disk and square-to-polygon warps: uniform density (chi-square against
// exact cell areas), continuity over the whole square, boundary to boundary, pdfs.
#include "geometry/sampling.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "chi2.h"

namespace glint {
namespace {

using Warp = std::function<Vec2f(Vec2f)>;

// ---- chi-square ------------------------------------------------------------------------------

// The p-value of Pearson's statistic for observed counts against expected counts. Cells
// expected to hold fewer than 5 samples are pooled into one, as the test requires.
double chi2PValue(const std::vector<double>& observed, const std::vector<double>& expected) {
  double chi2 = 0, pooledObs = 0, pooledExp = 0;
  int cells = 0;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] < 5) {
      pooledObs += observed[i], pooledExp += expected[i];
      continue;
    }
    chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    ++cells;
  }
  if (pooledExp >= 5) {
    chi2 += (pooledObs - pooledExp) * (pooledObs - pooledExp) / pooledExp;
    ++cells;
  }
  return test::chi2SurvivalFunction(chi2, cells - 1);
}

// Fixed seeds make every chi-square test deterministic; the threshold is the chance that a
// correct warp would have failed with some other seed.
constexpr double kSignificance = 1e-3;

std::vector<Vec2f> uniformSquare(int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Vec2f> pts(static_cast<size_t>(n));
  for (Vec2f& p : pts) p = {u(rng), u(rng)};
  return pts;
}

// The unit disk cut into equal-area cells: `rings` rings of equal area (edges at sqrt(k/rings))
// times `sectors` sectors.
double diskPValue(const Warp& warp, int rings, int sectors, int perCell, uint32_t seed) {
  const int cells = rings * sectors;
  std::vector<double> observed(size_t(cells), 0), expected(size_t(cells), perCell);
  for (Vec2f u : uniformSquare(cells * perCell, seed)) {
    Vec2f p = warp(u);
    float r2 = p.x * p.x + p.y * p.y;
    int ring = std::min(int(r2 * float(rings)), rings - 1);
    float phi = std::atan2(p.y, p.x) + kPi;  // [0, 2 pi]
    int sector = std::min(int(phi / (2 * kPi) * float(sectors)), sectors - 1);
    observed[size_t(ring * sectors + sector)] += 1;
  }
  return chi2PValue(observed, expected);
}

TEST(Sampling, ConcentricDiskIsUniformChiSquare) {
  Warp concentric = [](Vec2f u) { return sampleConcentricDisk(u); };
  double p = diskPValue(concentric, 8, 16, 400, 1);
  EXPECT_GT(p, kSignificance);
  // The same test catches a map that is not area-preserving: the naive polar map r = u
  // crowds the centre.
  Warp naivePolar = [](Vec2f u) {
    return Vec2f{u.x * std::cos(2 * kPi * u.y), u.x * std::sin(2 * kPi * u.y)};
  };
  EXPECT_LT(diskPValue(naivePolar, 8, 16, 400, 1), 1e-12);
  // ... and the correct polar map r = sqrt(u) passes it, so the cells are right.
  Warp polar = [](Vec2f u) {
    float r = std::sqrt(u.x);
    return Vec2f{r * std::cos(2 * kPi * u.y), r * std::sin(2 * kPi * u.y)};
  };
  EXPECT_GT(diskPValue(polar, 8, 16, 400, 2), kSignificance);
  EXPECT_FLOAT_EQ(concentricDiskPdf(), 1 / kPi);
}

TEST(Sampling, ConcentricPolarFormMatchesTheCartesianMap) {
  const int n = 64;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      Vec2f u{float(i) / n, float(j) / n};
      float r, theta;
      sampleConcentricPolar(u, &r, &theta);
      Vec2f p = sampleConcentricDisk(u);
      EXPECT_GE(r, 0);
      EXPECT_NEAR(r * std::cos(theta), p.x, 1e-6f) << u.x << " " << u.y;
      EXPECT_NEAR(r * std::sin(theta), p.y, 1e-6f) << u.x << " " << u.y;
    }
}

// ---- continuity ------------------------------------------------------------------------------

// The largest |warp(a) - warp(b)| / |a - b| over neighbouring points a, b of an n x n grid
// covering the closed square: horizontal, vertical and both diagonal neighbours, so the
// concentric map's wedge seams (the diagonals) and the centre are crossed everywhere.
double maxStretch(const Warp& warp, int n) {
  std::vector<Vec2f> img(size_t((n + 1) * (n + 1)));
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) img[size_t(j * (n + 1) + i)] = warp({float(i) / n, float(j) / n});
  auto at = [&](int i, int j) { return img[size_t(j * (n + 1) + i)]; };
  double worst = 0;
  const int di[4] = {1, 0, 1, 1}, dj[4] = {0, 1, 1, -1};
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      for (int k = 0; k < 4; ++k) {
        int i2 = i + di[k], j2 = j + dj[k];
        if (i2 > n || j2 < 0 || j2 > n) continue;
        Vec2f a = at(i, j), b = at(i2, j2);
        double dist = std::hypot(double(a.x) - b.x, double(a.y) - b.y);
        double step = std::hypot(double(di[k]), double(dj[k])) / n;
        worst = std::max(worst, dist / step);
      }
  return worst;
}

// The concentric map's Jacobian has its largest singular value on the diagonals: 1.38 per unit
// of [-1,1]^2, so 2.77 per unit of [0,1]^2 (finite differences on the grid see 2.63). A tear
// shows as a jump of order one across a grid step of 1/512: a stretch in the hundreds.
constexpr double kDiskStretch = 2.8;
// The polygon map follows the disk's, bent at the sector seams; measured at most 3.04 over
// 3-12 blades and several rotations.
constexpr double kPolygonStretch = 3.5;

TEST(Sampling, ConcentricDiskIsContinuousAcrossTheWholeSquare) {
  Warp concentric = [](Vec2f u) { return sampleConcentricDisk(u); };
  EXPECT_LT(maxStretch(concentric, 512), kDiskStretch);
  // A wedge convention flipped in the upper and lower wedges tears the map along the diagonals:
  // the test sees it.
  Warp torn = [](Vec2f u) {
    float ox = 2 * u.x - 1, oy = 2 * u.y - 1;
    if (ox == 0 && oy == 0) return Vec2f{0, 0};
    float r, theta;
    if (std::abs(ox) > std::abs(oy))
      r = ox, theta = (kPi / 4) * (oy / ox);
    else
      r = oy, theta = kPi / 2 + (kPi / 4) * (ox / oy);
    return Vec2f{r * std::cos(theta), r * std::sin(theta)};
  };
  EXPECT_GT(maxStretch(torn, 512), 50);
}

TEST(Sampling, ConcentricDiskMapsBoundaryToBoundaryAndInteriorInside) {
  const int n = 1024;
  for (int i = 0; i <= n; ++i) {
    float t = float(i) / n;
    for (Vec2f u : {Vec2f{0, t}, Vec2f{1, t}, Vec2f{t, 0}, Vec2f{t, 1}}) {
      Vec2f p = sampleConcentricDisk(u);
      EXPECT_NEAR(std::hypot(p.x, p.y), 1, 1e-6f) << u.x << " " << u.y;
    }
  }
  // The square's centre goes to the disk's; the rest of the interior strictly inside.
  Vec2f c = sampleConcentricDisk({0.5f, 0.5f});
  EXPECT_EQ(c.x, 0);
  EXPECT_EQ(c.y, 0);
  for (int j = 1; j < 64; ++j)
    for (int i = 1; i < 64; ++i) {
      Vec2f p = sampleConcentricDisk({i / 64.0f, j / 64.0f});
      EXPECT_LT(std::hypot(p.x, p.y), 1 - 1 / 64.0f);
    }
}

// ---- regular polygon -------------------------------------------------------------------------

std::vector<Vec2f> polygonVertices(int n, float angle0) {
  std::vector<Vec2f> v;
  for (int k = 0; k < n; ++k) {
    float a = angle0 + 2 * kPi * float(k) / float(n);
    v.push_back({std::cos(a), std::sin(a)});
  }
  return v;
}

double shoelaceArea(const std::vector<Vec2f>& poly) {
  double a = 0;
  for (size_t i = 0; i < poly.size(); ++i) {
    Vec2f p = poly[i], q = poly[(i + 1) % poly.size()];
    a += double(p.x) * q.y - double(q.x) * p.y;
  }
  return std::abs(a) / 2;
}

// Signed distance of p inside the (counter-clockwise, convex) polygon: > 0 inside.
double insideMargin(const std::vector<Vec2f>& poly, Vec2f p) {
  double m = 1e30;
  for (size_t i = 0; i < poly.size(); ++i) {
    Vec2f a = poly[i], b = poly[(i + 1) % poly.size()];
    double ex = b.x - a.x, ey = b.y - a.y;
    double cross = ex * (double(p.y) - a.y) - ey * (double(p.x) - a.x);
    m = std::min(m, cross / std::hypot(ex, ey));
  }
  return m;
}

// Sutherland–Hodgman: the part of `subject` inside the convex counter-clockwise `clip`.
std::vector<Vec2f> clipConvex(std::vector<Vec2f> subject, const std::vector<Vec2f>& clip) {
  for (size_t e = 0; e < clip.size() && !subject.empty(); ++e) {
    Vec2f a = clip[e], b = clip[(e + 1) % clip.size()];
    auto side = [&](Vec2f p) {
      return double(b.x - a.x) * (double(p.y) - a.y) - double(b.y - a.y) * (double(p.x) - a.x);
    };
    std::vector<Vec2f> out;
    for (size_t i = 0; i < subject.size(); ++i) {
      Vec2f p = subject[i], q = subject[(i + 1) % subject.size()];
      double sp = side(p), sq = side(q);
      if (sp >= 0) out.push_back(p);
      if ((sp >= 0) != (sq >= 0)) {
        float t = float(sp / (sp - sq));
        out.push_back(p + (q - p) * t);
      }
    }
    subject = std::move(out);
  }
  return subject;
}

// Grid cells over [-1,1]^2, each expected to hold N * area(cell ∩ polygon) / area(polygon):
// exact areas by clipping, independent of how the warp is built.
double polygonPValue(const Warp& warp, int n, float angle0, int samples, uint32_t seed) {
  const int g = 24;
  const std::vector<Vec2f> poly = polygonVertices(n, angle0);
  const double area = shoelaceArea(poly);
  std::vector<double> observed(size_t(g * g), 0), expected(size_t(g * g), 0);
  for (int j = 0; j < g; ++j)
    for (int i = 0; i < g; ++i) {
      float x0 = -1 + 2.0f * i / g, x1 = -1 + 2.0f * (i + 1) / g;
      float y0 = -1 + 2.0f * j / g, y1 = -1 + 2.0f * (j + 1) / g;
      auto part = clipConvex({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, poly);
      expected[size_t(j * g + i)] = part.size() >= 3 ? samples * shoelaceArea(part) / area : 0;
    }
  for (Vec2f u : uniformSquare(samples, seed)) {
    Vec2f p = warp(u);
    int i = std::clamp(int((p.x + 1) / 2 * g), 0, g - 1);
    int j = std::clamp(int((p.y + 1) / 2 * g), 0, g - 1);
    observed[size_t(j * g + i)] += 1;
  }
  return chi2PValue(observed, expected);
}

TEST(Sampling, RegularPolygonIsUniformChiSquare) {
  uint32_t seed = 10;
  for (int n : {3, 5, 6, 8})
    for (float angle0 : {0.0f, 0.3f, kPi / 2}) {
      Warp polygon = [=](Vec2f u) { return sampleRegularPolygon(u, n, angle0); };
      EXPECT_GT(polygonPValue(polygon, n, angle0, 100000, ++seed), kSignificance)
          << n << " blades, angle " << angle0;
    }
  // A map that is uniform in the scale instead of its square crowds the centre: rejected.
  Warp crowded = [](Vec2f u) {
    float r, theta;
    sampleConcentricPolar(u, &r, &theta);
    Vec2f p = sampleRegularPolygon(u, 6, 0);
    return r > 0 ? p * r : p;  // scale r -> r^2
  };
  EXPECT_LT(polygonPValue(crowded, 6, 0, 100000, 99), 1e-12);
}

TEST(Sampling, RegularPolygonSamplesStayInsideAndPdfIsOneOverArea) {
  for (int n : {3, 4, 5, 7, 9})
    for (float angle0 : {0.0f, 1.0f, -2.5f}) {
      const std::vector<Vec2f> poly = polygonVertices(n, angle0);
      EXPECT_NEAR(regularPolygonPdf(n) * shoelaceArea(poly), 1, 1e-5) << n;
      for (Vec2f u : uniformSquare(20000, uint32_t(n))) {
        Vec2f p = sampleRegularPolygon(u, n, angle0);
        ASSERT_GT(insideMargin(poly, p), -1e-6) << n << " blades: " << p.x << " " << p.y;
      }
      // The square's boundary goes to the polygon's, its centre to the polygon's centre.
      for (int i = 0; i <= 256; ++i) {
        float t = i / 256.0f;
        for (Vec2f u : {Vec2f{0, t}, Vec2f{1, t}, Vec2f{t, 0}, Vec2f{t, 1}})
          EXPECT_NEAR(insideMargin(poly, sampleRegularPolygon(u, n, angle0)), 0, 1e-5);
      }
      Vec2f c = sampleRegularPolygon({0.5f, 0.5f}, n, angle0);
      EXPECT_EQ(c.x, 0);
      EXPECT_EQ(c.y, 0);
    }
}

TEST(Sampling, RegularPolygonIsContinuousAcrossTheWholeSquare) {
  for (int n : {3, 5, 8}) {
    Warp polygon = [=](Vec2f u) { return sampleRegularPolygon(u, n, 0.4f); };
    EXPECT_LT(maxStretch(polygon, 512), kPolygonStretch) << n << " blades";
  }
}

}  // namespace
}  // namespace glint
