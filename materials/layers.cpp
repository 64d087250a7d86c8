// glint — sheen, thin films and dispersion (see layers.h).
#include "materials/layers.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace glint {

namespace {

float mixf(float a, float b, float t) { return a + (b - a) * t; }

// Estevez and Kulla's fit of the Charlie distribution's Smith Lambda, in two halves joined at
// cos = 0.5 (their eq. 3 and its mirror).
float sheenLambdaHelper(float x, float alpha) {
  const float r = (1 - alpha) * (1 - alpha);
  const float a = mixf(21.5473f, 25.3245f, r), b = mixf(3.82987f, 3.32435f, r),
              c = mixf(0.19823f, 0.16801f, r), d = mixf(-1.97760f, -1.27393f, r),
              e = mixf(-4.32054f, -4.85967f, r);
  return a / (1 + b * std::pow(x, c)) + d * x + e;
}

float sheenLambda(float cosTheta, float alpha) {
  if (cosTheta < 0.5f) return std::exp(sheenLambdaHelper(cosTheta, alpha));
  return std::exp(2 * sheenLambdaHelper(0.5f, alpha) - sheenLambdaHelper(1 - cosTheta, alpha));
}

constexpr int kSheenTable = 32;  // entries per axis: sqrt(cos(wo)) and sheenRoughness in [0, 1]

// E(cos(wo)) by quadrature: wi on a 96 x 48 midpoint grid, uniform in cos(theta_i) (which
// keeps samples near the horizon, where a smooth sheen reflects most) and in azimuth over the
// half circle (the integrand is symmetric about the plane of wo and the normal).
float integrateSheenAlbedo(float cosO, float alpha) {
  constexpr int kZ = 96, kPhi = 48;
  const float sinO = std::sqrt(std::max(0.0f, 1 - cosO * cosO));
  const Vec3f wo{sinO, 0, cosO};
  const float lambdaO = sheenLambda(cosO, alpha);
  double sum = 0;
  for (int i = 0; i < kZ; ++i) {
    const float z = (i + 0.5f) / kZ, r = std::sqrt(std::max(0.0f, 1 - z * z));
    // V's part that depends on wi alone, times cos(theta_i) (which cancels its 1 / cos).
    const float v = 1 / ((1 + lambdaO + sheenLambda(z, alpha)) * 4 * cosO);
    double row = 0;
    for (int j = 0; j < kPhi; ++j) {
      const float phi = kPi * (j + 0.5f) / kPhi;
      const Vec3f h = normalize(wo + Vec3f{r * std::cos(phi), r * std::sin(phi), z});
      row += sheenD(h.z, alpha);
    }
    sum += row * v;
  }
  // dw = dz dphi over the hemisphere: (1 / kZ) (2 pi / (2 kPhi)) per cell, both halves.
  return float(sum * 2 * kPi / (double(kZ) * kPhi));
}

struct SheenTable {
  std::array<float, kSheenTable * kSheenTable> e;  // [roughness][sqrt(cos)]
  SheenTable() {
    for (int j = 0; j < kSheenTable; ++j) {
      const float roughness = float(j) / (kSheenTable - 1);
      const float alpha = std::max(roughness * roughness, kMinSheenAlpha);
      for (int i = 0; i < kSheenTable; ++i) {
        const float x = float(i) / (kSheenTable - 1);
        const float cosO = std::max(x * x, 1e-4f);
        e[size_t(j * kSheenTable + i)] = std::min(integrateSheenAlbedo(cosO, alpha), 1.0f);
      }
    }
  }
};

// One Airy sum for one polarisation: amplitudes r12 (air-film), r23 (film-substrate).
float airy(float r12, float r23, float cosDelta) {
  const float cross = 2 * r12 * r23 * cosDelta;
  return (r12 * r12 + r23 * r23 + cross) / (1 + r12 * r12 * r23 * r23 + cross);
}

}  // namespace

float sheenD(float cosH, float alpha) {
  alpha = std::max(alpha, kMinSheenAlpha);
  const float inv = 1 / alpha;
  const float sin2 = std::max(0.0f, 1 - cosH * cosH);
  return (2 + inv) * std::pow(sin2, 0.5f * inv) / (2 * kPi);
}

float sheenBrdf(float cosO, float cosI, float cosH, float alpha) {
  if (!(cosO > 0) || !(cosI > 0)) return 0;
  alpha = std::max(alpha, kMinSheenAlpha);
  const float V = 1 / ((1 + sheenLambda(cosO, alpha) + sheenLambda(cosI, alpha)) * 4 * cosO * cosI);
  return sheenD(cosH, alpha) * V;
}

float sheenAlbedo(float cosO, float sheenRoughness) {
  static const SheenTable table;  // built once, on first use (thread-safe)
  const float x = std::sqrt(std::clamp(cosO, 0.0f, 1.0f)) * (kSheenTable - 1);
  const float y = std::clamp(sheenRoughness, 0.0f, 1.0f) * (kSheenTable - 1);
  const int i = std::min(int(x), kSheenTable - 2), j = std::min(int(y), kSheenTable - 2);
  const float fx = x - float(i), fy = y - float(j);
  auto at = [&](int a, int b) { return table.e[size_t(b * kSheenTable + a)]; };
  return mixf(mixf(at(i, j), at(i + 1, j), fx), mixf(at(i, j + 1), at(i + 1, j + 1), fx), fy);
}

float thinFilmReflectance(float cosI, float filmIor, float substrateIor, float thicknessNm,
                          float lambdaNm) {
  cosI = std::clamp(cosI, 0.0f, 1.0f);
  const float sin2I = 1 - cosI * cosI;
  const float n2 = filmIor, n3 = substrateIor;
  const float sin2Film = sin2I / (n2 * n2);
  if (sin2Film >= 1) return 1;
  const float sin2Sub = sin2I / (n3 * n3);
  if (sin2Sub >= 1) return 1;
  const float cos2 = std::sqrt(1 - sin2Film), cos3 = std::sqrt(1 - sin2Sub);
  // Amplitude coefficients, one convention for both interfaces (incident medium first).
  const float rs12 = (cosI - n2 * cos2) / (cosI + n2 * cos2);
  const float rp12 = (n2 * cosI - cos2) / (n2 * cosI + cos2);
  const float rs23 = (n2 * cos2 - n3 * cos3) / (n2 * cos2 + n3 * cos3);
  const float rp23 = (n3 * cos2 - n2 * cos3) / (n3 * cos2 + n2 * cos3);
  // Phase difference between successive reflections: the optical path 2 n d cos(theta_film).
  const float cosDelta = std::cos(4 * kPi * n2 * thicknessNm * cos2 / lambdaNm);
  return std::clamp(0.5f * (airy(rs12, rs23, cosDelta) + airy(rp12, rp23, cosDelta)), 0.0f, 1.0f);
}

Rgb thinFilmFresnel(float cosI, float filmIor, Rgb substrateIor, float thicknessNm) {
  static constexpr float kBands[3][3] = {
      {596.7f, 630.0f, 663.3f}, {513.3f, 540.0f, 566.7f}, {433.3f, 460.0f, 486.7f}};
  Rgb r;
  for (int c = 0; c < 3; ++c) {
    float sum = 0;
    for (float lambda : kBands[c])
      sum += thinFilmReflectance(cosI, filmIor, substrateIor[c], thicknessNm, lambda);
    r[c] = sum / 3;
  }
  return r;
}

float iorFromF0(float f0) {
  const float s = std::sqrt(std::clamp(f0, 0.0f, 0.9999f));
  return (1 + s) / (1 - s);
}

float dispersedIor(float ior, float dispersion, float lambdaNm) {
  if (!(dispersion > 0)) return ior;
  const float abbe = 20 / dispersion;
  return std::max(1.0f, ior + (ior - 1) / abbe * (523655.0f / (lambdaNm * lambdaNm) - 1.5168f));
}

}  // namespace glint
