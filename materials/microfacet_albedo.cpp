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
  const float* e = kTable;  // [f0][roughness][mu]
  std::vector<float> avg;  // [f0][roughness]
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
