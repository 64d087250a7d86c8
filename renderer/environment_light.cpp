// glint — piecewise-constant distributions and the image environment light.
#include "renderer/environment_light.h"

#include <algorithm>
#include <cmath>

#include "geometry/sampling.h"

namespace glint {

namespace {
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

// The direction of map coordinates uv in the map's own frame (before any rotation): the
// centre column looks down -Z, u grows towards +X, the top row is +Y.
Vec3f mapDirection(Vec2f uv) {
  const float theta = kPi * uv.y, phi = 2 * kPi * (uv.x - 0.5f);
  const float sinTheta = std::sin(theta);
  return {sinTheta * std::sin(phi), std::cos(theta), -sinTheta * std::cos(phi)};
}
}  // namespace

// --- Piecewise-constant distributions ---------------------------------------------------------

PiecewiseConstant1D::PiecewiseConstant1D(const std::vector<float>& f) : func_(f) {
  const size_t n = func_.size();
  for (float& v : func_) v = (std::isfinite(v) && v > 0) ? v : 0.0f;
  cdf_.assign(n + 1, 0.0);
  for (size_t i = 0; i < n; ++i) cdf_[i + 1] = cdf_[i] + double(func_[i]) / double(n);
  integral_ = float(cdf_[n]);
  uniform_ = !(cdf_[n] > 0);
  for (size_t i = 1; i <= n; ++i) cdf_[i] = uniform_ ? double(i) / double(n) : cdf_[i] / cdf_[n];
}

float PiecewiseConstant1D::sample(float u, float* pdf, size_t* cell) const {
  const size_t n = func_.size();
  const auto it = std::upper_bound(cdf_.begin() + 1, cdf_.end(), double(u));
  size_t i = std::min(size_t(it - cdf_.begin()) - 1, n - 1);
  while (i > 0 && cdf_[i + 1] == cdf_[i]) --i;  // skip empty cells at a boundary
  const double width = cdf_[i + 1] - cdf_[i];
  const double t = width > 0 ? (double(u) - cdf_[i]) / width : 0.5;
  *pdf = uniform_ ? 1.0f : func_[i] / integral_;
  *cell = i;
  return std::min(float((double(i) + std::clamp(t, 0.0, 1.0)) / double(n)), kOneMinusEpsilon);
}

float PiecewiseConstant1D::pdf(float x) const {
  const size_t n = func_.size();
  if (n == 0 || !(x >= 0 && x < 1)) return 0;
  const size_t i = std::min(size_t(x * float(n)), n - 1);
  return uniform_ ? 1.0f : func_[i] / integral_;
}

Distribution2D::Distribution2D(const std::vector<float>& f, int nu, int nv) {
  std::vector<float> rowIntegrals(static_cast<size_t>(nv));
  for (int v = 0; v < nv; ++v) {
    rows_.emplace_back(
        std::vector<float>(f.begin() + ptrdiff_t(v) * nu, f.begin() + ptrdiff_t(v + 1) * nu));
    rowIntegrals[size_t(v)] = rows_.back().integral();
  }
  marginal_ = PiecewiseConstant1D(rowIntegrals);
}

Vec2f Distribution2D::sample(Vec2f u, float* pdf) const {
  float pdfV = 0, pdfU = 0;
  size_t row = 0, cell = 0;
  const float v = marginal_.sample(u.y, &pdfV, &row);
  const float x = rows_[row].sample(u.x, &pdfU, &cell);
  *pdf = pdfU * pdfV;
  return {x, v};
}

float Distribution2D::pdf(Vec2f p) const {
  if (!(p.y >= 0 && p.y < 1)) return 0;
  const size_t row = std::min(size_t(p.y * float(rows_.size())), rows_.size() - 1);
  return marginal_.pdf(p.y) * rows_[row].pdf(p.x);
}

// --- Image environment ------------------------------------------------------------------------

ImageEnvironmentLight::ImageEnvironmentLight(int width, int height, std::vector<Rgb> pixels,
                                             float scale, float rotation)
    : Light(LightKind::Infinite),
      width_(width),
      height_(height),
      pixels_(std::move(pixels)),
      scale_(scale),
      cosRot_(std::cos(rotation)),
      sinRot_(std::sin(rotation)) {
  // The sampling density per pixel cell: the largest luminance of the pixels the bilinear
  // lookup blends anywhere in the cell (the cell and its 8 neighbours, wrapping in u), times
  // sin(theta) because the map's rows shrink towards the poles. Le is bilinear, so its support
  // reaches half a pixel into the neighbours of every bright pixel; taking the maximum keeps
  // the density non-zero wherever Le is (MIS and the estimate stay unbiased) at the price of a
  // density a little wider than the light.
  std::vector<float> lum(size_t(width) * size_t(height));
  for (size_t i = 0; i < lum.size(); ++i) lum[i] = std::max(0.0f, luminance(pixels_[i]));
  std::vector<float> f(lum.size());
  for (int y = 0; y < height; ++y) {
    const float sinTheta = std::sin(kPi * (float(y) + 0.5f) / float(height));
    for (int x = 0; x < width; ++x) {
      float m = 0;
      for (int dy = -1; dy <= 1; ++dy) {
        const int yy = std::clamp(y + dy, 0, height - 1);
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = (x + dx + width) % width;
          m = std::max(m, lum[size_t(yy) * size_t(width) + size_t(xx)]);
        }
      }
      f[size_t(y) * size_t(width) + size_t(x)] = m * sinTheta;
    }
  }
  distribution_ = Distribution2D(f, width, height);
}

void ImageEnvironmentLight::preprocess(const Bounds3f& b) {
  if (b.empty()) {
    sceneCenter_ = {}, sceneRadius_ = 1;
    return;
  }
  sceneCenter_ = b.center();
  sceneRadius_ = std::max(length(b.diagonal()) * 0.5f, 1e-6f);
}

Vec2f ImageEnvironmentLight::uvOf(Vec3f d) const {
  // Into the map's frame: undo the rotation about +Y.
  const Vec3f m{cosRot_ * d.x - sinRot_ * d.z, d.y, sinRot_ * d.x + cosRot_ * d.z};
  float u = 0.5f + std::atan2(m.x, -m.z) / (2 * kPi);
  const float v = std::acos(std::clamp(m.y, -1.0f, 1.0f)) / kPi;
  if (u >= 1) u -= 1;
  return {std::clamp(u, 0.0f, kOneMinusEpsilon), std::clamp(v, 0.0f, kOneMinusEpsilon)};
}

Vec3f ImageEnvironmentLight::directionOf(Vec2f uv) const {
  const Vec3f m = mapDirection(uv);
  return {cosRot_ * m.x + sinRot_ * m.z, m.y, -sinRot_ * m.x + cosRot_ * m.z};
}

Rgb ImageEnvironmentLight::pixel(Vec2f uv) const {
  // Bilinear between pixel centres: wraps around in u (the seam at the back), clamps in v
  // (the poles).
  const float fx = uv.x * float(width_) - 0.5f, fy = uv.y * float(height_) - 0.5f;
  const float x0f = std::floor(fx), y0f = std::floor(fy);
  const float tx = fx - x0f, ty = fy - y0f;
  const int x0 = (int(x0f) + width_) % width_, x1 = (x0 + 1) % width_;
  const int y0 = std::clamp(int(y0f), 0, height_ - 1),
            y1 = std::clamp(int(y0f) + 1, 0, height_ - 1);
  auto at = [&](int x, int y) { return pixels_[size_t(y) * size_t(width_) + size_t(x)]; };
  const Rgb top = at(x0, y0) * (1 - tx) + at(x1, y0) * tx;
  const Rgb bottom = at(x0, y1) * (1 - tx) + at(x1, y1) * tx;
  return (top * (1 - ty) + bottom * ty) * scale_;
}

float ImageEnvironmentLight::pdfOf(Vec2f uv) const {
  const float sinTheta = std::sin(kPi * uv.y);
  if (!(sinTheta > 0)) return 0;
  return distribution_.pdf(uv) / (2 * kPi * kPi * sinTheta);
}

Rgb ImageEnvironmentLight::Le(Vec3f d) const { return pixel(uvOf(d)); }

std::optional<LightSample> ImageEnvironmentLight::sampleLi(const LightSampleContext&,
                                                           Vec2f u) const {
  float pdfUv = 0;
  const Vec2f uv = distribution_.sample(u, &pdfUv);
  const float sinTheta = std::sin(kPi * uv.y);
  if (!(pdfUv > 0 && sinTheta > 0)) return std::nullopt;
  LightSample s;
  s.wi = directionOf(uv);
  // The density from the direction's own cell, so sampleLi and pdfLi agree to the last bit.
  s.pdf = pdfOf(uvOf(s.wi));
  if (!(s.pdf > 0) || !std::isfinite(s.pdf)) return std::nullopt;
  s.L = Le(s.wi);
  s.infinite = true;
  s.delta = false;
  return s;
}

float ImageEnvironmentLight::pdfLi(const LightSampleContext&, Vec3f wi, const LightHit&) const {
  return pdfOf(uvOf(wi));
}

std::optional<LightLeSample> ImageEnvironmentLight::sampleLe(Vec2f uPos, Vec2f uDir,
                                                             float time) const {
  auto li = sampleLi({}, uDir);
  if (!li) return std::nullopt;
  const Vec3f d = -li->wi;
  const Frame f = Frame::fromZ(d);
  const Vec2f q = sampleConcentricDisk(uPos);
  LightLeSample s;
  s.ray = Ray{sceneCenter_ + sceneRadius_ * (f.s * q.x + f.t * q.y - d), d, 0, kInfinity, time};
  s.L = li->L;
  s.pdfPos = 1 / (kPi * sceneRadius_ * sceneRadius_);
  s.pdfDir = li->pdf;
  return s;
}

DistantImportance ImageEnvironmentLight::distantImportance() const {
  // phi() is 4 pi x the mean radiance x pi r^2; pi x the mean radiance is the irradiance.
  return {luminance(phi()) / (4 * kPi * sceneRadius_ * sceneRadius_), {}};
}

Rgb ImageEnvironmentLight::phi() const {
  // Each pixel's radiance over its solid angle, through the scene's disk.
  Rgb sum;
  for (int y = 0; y < height_; ++y) {
    const float dOmega = (2 * kPi / float(width_)) * (kPi / float(height_)) *
                         std::sin(kPi * (float(y) + 0.5f) / float(height_));
    for (int x = 0; x < width_; ++x)
      sum += pixels_[size_t(y) * size_t(width_) + size_t(x)] * dOmega;
  }
  return sum * (scale_ * kPi * sceneRadius_ * sceneRadius_);
}

// --- The studio -------------------------------------------------------------------------------

namespace {

// 0 below e0, 1 above e1, smooth in between.
float smoothstep(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3 - 2 * t);
}

// A round light of angular radius `radius` (radians) about unit `axis`, with a soft edge.
float disc(Vec3f d, Vec3f axis, float radius, float edge) {
  const float angle = std::acos(std::clamp(dot(d, axis), -1.0f, 1.0f));
  return 1 - smoothstep(radius - edge, radius + edge, angle);
}

float studioRadiance(Vec3f d) {
  constexpr float kDegree = kPi / 180;
  // Sky: 0.45 at the horizon to 0.75 at the zenith; floor 0.15; 6 degrees of blend between.
  const float sky = 0.45f + 0.3f * std::max(d.y, 0.0f);
  const float aboveHorizon = smoothstep(-0.05f, 0.05f, d.y);
  float L = 0.15f * (1 - aboveHorizon) + sky * aboveHorizon;
  // Key: a softbox of 12 degrees radius, 40 degrees up, front left.
  static const Vec3f key = normalize(Vec3f{-0.55f, 0.65f, 0.5f});
  L += 10.0f * disc(d, key, 12 * kDegree, 1.5f * kDegree);
  // Rim: 7 degrees radius, 20 degrees up, behind right.
  static const Vec3f rim = normalize(Vec3f{0.7f, 0.35f, -0.6f});
  L += 4.0f * disc(d, rim, 7 * kDegree, 1.5f * kDegree);
  return L;
}

}  // namespace

std::vector<Rgb> studioEnvironment(int width, int height) {
  // The map as ImageEnvironmentLight reads it (centre towards -Z, u towards +X, row 0 up),
  // sampled at pixel centres, then scaled so the cosine-weighted integral over the upper
  // hemisphere (irradiance of a surface facing +Y) is pi.
  std::vector<float> L(size_t(width) * size_t(height));
  double irradiance = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Vec2f uv{(float(x) + 0.5f) / float(width), (float(y) + 0.5f) / float(height)};
      const Vec3f d = mapDirection(uv);
      const float v = studioRadiance(d);
      L[size_t(y) * size_t(width) + size_t(x)] = v;
      const double dOmega = (2 * kPi / width) * (kPi / height) * std::sin(kPi * uv.y);
      if (d.y > 0) irradiance += double(v) * d.y * dOmega;
    }
  const float scale = float(kPi / irradiance);
  std::vector<Rgb> pixels(L.size());
  for (size_t i = 0; i < L.size(); ++i) pixels[i] = Rgb{L[i], L[i], L[i]} * scale;
  return pixels;
}

}  // namespace glint
