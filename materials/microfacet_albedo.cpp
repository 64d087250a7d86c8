// glint — GGX albedo tables for energy compensation (see microfacet_albedo.h).
#include "materials/microfacet_albedo.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <vector>

#include "materials/scattering.h"

namespace glint {

namespace {

constexpr int kMu = kAlbedoTableMu, kRough = kAlbedoTableRoughness, kF0 = kAlbedoTableF0;

constexpr float kTable[] = {
#include "materials/microfacet_albedo_table.inc"
};
static_assert(std::size(kTable) == size_t(kF0 * kRough * kMu));
constexpr int kAverageSteps = 512;
constexpr int kFresnelAverageEntries = 256;

// The relative index whose normal-incidence reflectance is x^2, and back; x = 1 stands for
// F = 1.
float etaFromSqrtF0(float x) { return (1 + x) / (1 - x); }
float sqrtF0FromEta(float eta) {
  if (!(eta > 0)) return 0;
  if (eta < 1) eta = 1 / eta;
  return std::isfinite(eta) ? (eta - 1) / (eta + 1) : 1.0f;
}

// A coordinate t in [0, 1] on an axis of n entries: the lower index and the weight of the next.
struct AxisPosition {
  int i;
  float w;
};
AxisPosition axis(float t, int n) {
  const float x = std::clamp(t, 0.0f, 1.0f) * float(n - 1);
  const int i = std::min(int(x), n - 2);
  return {i, x - float(i)};
}

struct AlbedoTables {
  const float* e = kTable;        // [f0][roughness][mu]
  std::vector<float> avg;         // [f0][roughness]
  std::vector<float> fresnelAvg;  // [f0], finer

  float at(int f, int r, int m) const { return e[(f * kRough + r) * kMu + m]; }

  float lookup(float cosO, float roughness, float x) const {
    const AxisPosition m = axis(std::sqrt(std::max(cosO, 0.0f)), kMu);
    const AxisPosition r = axis(roughness, kRough);
    const AxisPosition f = axis(x, kF0);
    auto plane = [&](int fi) {
      const float a = at(fi, r.i, m.i) + (at(fi, r.i, m.i + 1) - at(fi, r.i, m.i)) * m.w;
      const float b =
          at(fi, r.i + 1, m.i) + (at(fi, r.i + 1, m.i + 1) - at(fi, r.i + 1, m.i)) * m.w;
      return a + (b - a) * r.w;
    };
    const float lo = plane(f.i);
    return lo + (plane(f.i + 1) - lo) * f.w;
  }

  float lookupAverage(float roughness, float x) const {
    const AxisPosition r = axis(roughness, kRough);
    const AxisPosition f = axis(x, kF0);
    auto row = [&](int fi) {
      const float* a = &avg[size_t(fi * kRough)];
      return a[r.i] + (a[r.i + 1] - a[r.i]) * r.w;
    };
    const float lo = row(f.i);
    return lo + (row(f.i + 1) - lo) * f.w;
  }

  // The multiple-scattering lobe's density in mu, per roughness row: msPdf[r][k] mu over bin
  // k of kMsBins (uniform in sqrt(mu)), normalised; msCdf[r][k] the bins' running shares
  // (msCdf[r][kMsBins] = 1); msMass[r] = int (1 - E(mu)) mu dmu.
  static constexpr int kMsBins = 64;
  std::vector<float> msPdf, msCdf, msMass;

  void buildMultipleScattering() {
    msPdf.assign(size_t(kRough * kMsBins), 0);
    msCdf.assign(size_t(kRough * (kMsBins + 1)), 0);
    msMass.assign(size_t(kRough), 0);
    for (int r = 0; r < kRough; ++r) {
      const float roughness = float(r) / (kRough - 1);
      double total = 0;
      std::vector<double> bin(kMsBins);
      for (int k = 0; k < kMsBins; ++k) {
        // Bins uniform in sqrt(mu), as the table is: 1 - E rises steeply near the horizon,
        // most steeply for smooth surfaces. 8 midpoints in mu per bin.
        const double lo = double(k) / kMsBins, hi = double(k + 1) / kMsBins;
        const double a = lo * lo, b = hi * hi;
        double sum = 0;
        for (int j = 0; j < 8; ++j) {
          const float mu = float(a + (b - a) * (j + 0.5) / 8);
          sum += std::max(0.0f, 1 - lookup(mu, roughness, 1)) * mu;
        }
        bin[size_t(k)] = sum * (b - a) / 8;
        total += bin[size_t(k)];
      }
      msMass[size_t(r)] = float(total);
      float* pdf = &msPdf[size_t(r * kMsBins)];
      float* cdf = &msCdf[size_t(r * (kMsBins + 1))];
      double running = 0;
      for (int k = 0; k < kMsBins; ++k) {
        // Within a bin [a, b] of mu the density goes as mu (the cosine in the lobe), so that
        // only 1 - E is left to vary inside it: pdf(mu) = share 2 mu / (b^2 - a^2).
        const double lo = double(k) / kMsBins, hi = double(k + 1) / kMsBins;
        const double a = lo * lo, b = hi * hi;
        const double share = total > 0 ? bin[size_t(k)] / total : b * b - a * a;
        pdf[k] = float(share * 2 / (b * b - a * a));  // times mu: the density per unit mu
        running += share;
        cdf[k + 1] = float(running);
      }
      cdf[kMsBins] = 1;
    }
  }

  // The two rows around `roughness` and the probability of the lower one (their masses
  // weighted by the interpolation weights: the mixture is then proportional to the
  // interpolated 1 - E).
  struct MsRows {
    int lo;
    float pLo;
  };
  MsRows msRows(float roughness) const {
    const AxisPosition r = axis(roughness, kRough);
    const float a = (1 - r.w) * msMass[size_t(r.i)], b = r.w * msMass[size_t(r.i + 1)];
    return {r.i, a + b > 0 ? a / (a + b) : 1 - r.w};
  }
  float rowPdf(int r, float mu) const {
    const int k = std::min(int(std::sqrt(mu) * kMsBins), kMsBins - 1);
    return msPdf[size_t(r * kMsBins + k)] * mu;
  }

  AlbedoTables() : avg(size_t(kF0 * kRough)) {
    // The averages of the interpolated rows (what a lookup at mu_i returns), by the midpoint
    // rule in mu.
    for (int f = 0; f < kF0; ++f) {
      const float x = float(f) / (kF0 - 1);
      for (int r = 0; r < kRough; ++r) {
        const float roughness = float(r) / (kRough - 1);
        double sum = 0;
        for (int k = 0; k < kAverageSteps; ++k) {
          const float mu = (k + 0.5f) / kAverageSteps;
          sum += lookup(mu, roughness, x) * mu;
        }
        avg[size_t(f * kRough + r)] = float(2 * sum / kAverageSteps);
      }
    }
    buildMultipleScattering();
    // The smooth interface's average Fresnel reflectance, finely.
    fresnelAvg.resize(kFresnelAverageEntries);
    constexpr int kSteps = 2048;
    for (int f = 0; f < kFresnelAverageEntries; ++f) {
      const float x = float(f) / (kFresnelAverageEntries - 1);
      if (f == kFresnelAverageEntries - 1) {
        fresnelAvg[size_t(f)] = 1;
        continue;
      }
      const float eta = etaFromSqrtF0(x);
      double sum = 0;
      for (int k = 0; k < kSteps; ++k) {
        const float mu = (k + 0.5f) / kSteps;
        sum += fresnelDielectric(mu, eta) * mu;
      }
      fresnelAvg[size_t(f)] = float(2 * sum / kSteps);
    }
  }
};

const AlbedoTables& tables() {
  static const AlbedoTables t;
  return t;
}

float clampRoughness(float roughness) {
  return std::isfinite(roughness) ? std::clamp(roughness, 0.0f, 1.0f) : 1.0f;
}

}  // namespace

float ggxAlbedo(float cosO, float roughness) {
  return tables().lookup(cosO, clampRoughness(roughness), 1);
}

float ggxAverageAlbedo(float roughness) {
  return tables().lookupAverage(clampRoughness(roughness), 1);
}

float multipleScatteringPdf(float mu, float roughness) {
  if (!(mu > 0)) return 0;
  const AlbedoTables& t = tables();
  const AlbedoTables::MsRows rows = t.msRows(clampRoughness(roughness));
  mu = std::min(mu, 1.0f);
  const float density =
      rows.pLo * t.rowPdf(rows.lo, mu) + (1 - rows.pLo) * t.rowPdf(rows.lo + 1, mu);
  return density * (0.5f * kInvPi);  // per unit mu, over 2 pi of azimuth
}

float sampleMultipleScatteringCos(float roughness, float u, float* pdf) {
  const AlbedoTables& t = tables();
  roughness = clampRoughness(roughness);
  const AlbedoTables::MsRows rows = t.msRows(roughness);
  // The row, then the bin by its cumulative share, then mu uniformly inside the bin.
  int r = rows.lo;
  if (u < rows.pLo) {
    u /= rows.pLo;
  } else {
    u = (u - rows.pLo) / (1 - rows.pLo);
    ++r;
  }
  u = std::clamp(u, 0.0f, 0x1.fffffep-1f);
  const float* cdf = &t.msCdf[size_t(r * (AlbedoTables::kMsBins + 1))];
  const int k = int(std::upper_bound(cdf + 1, cdf + AlbedoTables::kMsBins, u) - (cdf + 1));
  const float width = cdf[k + 1] - cdf[k];
  const float within = width > 0 ? (u - cdf[k]) / width : 0.5f;
  // Density proportional to mu inside the bin [a, b]: mu = sqrt(a^2 + within (b^2 - a^2)).
  const float lo = float(k) / AlbedoTables::kMsBins, hi = float(k + 1) / AlbedoTables::kMsBins;
  const float a = lo * lo, b = hi * hi;
  const float mu = std::clamp(std::sqrt(a * a + within * (b * b - a * a)), 1e-6f, 1.0f);
  *pdf = multipleScatteringPdf(mu, roughness);
  return mu;
}

float ggxDielectricAlbedo(float cosO, float roughness, float eta) {
  return tables().lookup(cosO, clampRoughness(roughness), sqrtF0FromEta(eta));
}

float ggxDielectricAverageAlbedo(float roughness, float eta) {
  return tables().lookupAverage(clampRoughness(roughness), sqrtF0FromEta(eta));
}

float dielectricFresnelAverage(float eta) {
  const AxisPosition f = axis(sqrtF0FromEta(eta), kFresnelAverageEntries);
  const std::vector<float>& a = tables().fresnelAvg;
  return a[size_t(f.i)] + (a[size_t(f.i + 1)] - a[size_t(f.i)]) * f.w;
}

}  // namespace glint
