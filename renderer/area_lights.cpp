// glint — the area light over a placed shape or a triangle mesh.
#include "renderer/area_lights.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "geometry/sampling.h"

namespace glint {

namespace {
bool isBlack(const Rgb& c) { return !(c.x > 0 || c.y > 0 || c.z > 0); }
// What a triangle's share of light samples follows: the mean of its channels (never 0 where
// any channel emits, unlike luminance for a pure blue).
float luminanceWeight(const Rgb& c) {
  const float w = (std::max(c.x, 0.0f) + std::max(c.y, 0.0f) + std::max(c.z, 0.0f)) / 3;
  return std::isfinite(w) ? w : 0.0f;
}
}  // namespace

// --- Emission ---------------------------------------------------------------------------------

// The one place a light asks a material for its emission.
Rgb AreaEmission::at(Vec3f p, Vec3f n, Vec3f ns, Vec2f uv, Vec2f uv1, Vec3f wo, Vec2f duvdx,
                     Vec2f duvdy) const {
  const float c = dot(n, wo);
  if (!twoSided && !(c > 0)) return {};
  if (!material) return radiance;
  // The minimal interaction a camera ray would have produced there, so textured emission
  // looks the same sampled as seen.
  SurfaceInteraction si;
  si.p = p;
  si.ng = c >= 0 ? n : -n;
  si.ns = dot(ns, si.ng) >= 0 ? ns : -ns;
  si.wo = wo;
  si.uv = uv;
  si.uv1 = uv1;
  si.duvdx = si.duv1dx = duvdx;
  si.duvdy = si.duv1dy = duvdy;
  si.frontFace = c >= 0;
  si.objectFromWorld = &objectFromWorld;
  si.instance = instance;
  return material->emitted(si);
}

// --- Construction -----------------------------------------------------------------------------

AreaLight::AreaLight(const PlacedShape& shape, const AreaEmission& emission,
                     std::unique_ptr<Shape> owned)
    : Light(LightKind::Area), owned_(std::move(owned)), shape_(shape), emission_(emission) {
  area_ = shape_->area();
  bounds_ = shape_->bounds();
  finish();
}

AreaLight::AreaLight(EmissiveMesh mesh, const AreaEmission& emission)
    : Light(LightKind::Area), mesh_(std::move(mesh)), emission_(emission) {
  const auto& pos = mesh_.positions;
  const size_t count = mesh_.indices.size() / 3;
  triangleAreas_.resize(count);
  double total = 0;
  for (size_t t = 0; t < count; ++t) {
    const Vec3f p0 = pos[mesh_.indices[3 * t]], p1 = pos[mesh_.indices[3 * t + 1]],
                p2 = pos[mesh_.indices[3 * t + 2]];
    triangleAreas_[t] = 0.5f * length(cross(p1 - p0, p2 - p0));
    total += triangleAreas_[t];
  }
  area_ = float(total);
  for (Vec3f p : pos) bounds_.extend(p);
  // Each triangle's mean radiance (each on its own: the same whatever the thread count).
  std::vector<Rgb> radiance(count, emission_.radiance);
  if (emission_.material)
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t t = r.begin(); t < r.end(); ++t)
                          radiance[t] = meanRadiance(uint32_t(t));
                      });
  Rgb power;
  double weighted = 0;
  for (size_t t = 0; t < count; ++t) {
    power += radiance[t] * triangleAreas_[t];
    weighted += double(luminanceWeight(radiance[t])) * triangleAreas_[t];
  }
  // Triangles drawn by emitted power; a floor of 1/1000 of the mesh's mean keeps every
  // triangle drawable, in case its few lookups missed a speck of emission inside it.
  const float floor = total > 0 ? float(1e-3 * weighted / total) : 0.0f;
  std::vector<float> weights(count);
  for (size_t t = 0; t < count; ++t)
    weights[t] = triangleAreas_[t] * (luminanceWeight(radiance[t]) + floor);
  triangles_ = DiscreteDistribution(weights);
  phi_ = power * (kPi * (emission_.twoSided ? 2.0f : 1.0f));
}

// Lookups at the centroids of the four triangles that halving the edges makes, each filtered
// over about its own part, averaged. Exact for constant emission.
Rgb AreaLight::meanRadiance(uint32_t t) const {
  const uint32_t i[3] = {mesh_.indices[3 * t], mesh_.indices[3 * t + 1], mesh_.indices[3 * t + 2]};
  const Vec3f p[3] = {mesh_.positions[i[0]], mesh_.positions[i[1]], mesh_.positions[i[2]]};
  const Vec3f c = cross(p[1] - p[0], p[2] - p[0]);
  if (!(lengthSquared(c) > 0)) return {};
  const Vec3f n = normalize(c);
  auto uvAt = [&](const std::vector<Vec2f>& uvs, const float b[3]) {
    return uvs.empty() ? Vec2f{b[1], b[2]} : b[0] * uvs[i[0]] + b[1] * uvs[i[1]] + b[2] * uvs[i[2]];
  };
  const float corners[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const Vec2f uv0 = uvAt(mesh_.uvs, corners[0]);
  // Footprints of a quarter edge: a filtered lookup reaches about twice its footprint, so
  // this covers the lookup's own part without reaching far into the neighbours'.
  const Vec2f duvdx = 0.25f * (uvAt(mesh_.uvs, corners[1]) - uv0);
  const Vec2f duvdy = 0.25f * (uvAt(mesh_.uvs, corners[2]) - uv0);
  constexpr float kCentroids[4][3] = {{2 / 3.0f, 1 / 6.0f, 1 / 6.0f},
                                      {1 / 6.0f, 2 / 3.0f, 1 / 6.0f},
                                      {1 / 6.0f, 1 / 6.0f, 2 / 3.0f},
                                      {1 / 3.0f, 1 / 3.0f, 1 / 3.0f}};
  Rgb sum;
  for (const auto& b : kCentroids) {
    const Vec3f at = b[0] * p[0] + b[1] * p[1] + b[2] * p[2];
    Vec3f ns = n;
    if (!mesh_.normals.empty()) {
      const Vec3f v =
          b[0] * mesh_.normals[i[0]] + b[1] * mesh_.normals[i[1]] + b[2] * mesh_.normals[i[2]];
      if (lengthSquared(v) > 0) ns = normalize(v);
    }
    const Vec2f uv = uvAt(mesh_.uvs, b);
    const Vec2f uv1 = mesh_.uvs1.empty() ? uv : uvAt(mesh_.uvs1, b);
    sum += emission_.at(at, n, ns, uv, uv1, n, duvdx, duvdy);
  }
  return sum * 0.25f;
}

void AreaLight::finish() {
  // A shape's power from the radiance averaged over a stratified grid of points: exact for
  // constant radiance, a good estimate for textures.
  constexpr int kGrid = 16;
  Rgb sum;
  if (area_ > 0)
    for (int j = 0; j < kGrid; ++j)
      for (int i = 0; i < kGrid; ++i) {
        Vec3f ns;
        Vec2f uv1;
        if (auto a = samplePoint(nullptr, {(float(i) + 0.5f) / kGrid, (float(j) + 0.5f) / kGrid},
                                 &ns, &uv1))
          sum += emission_.at(a->p, a->n, ns, a->uv, uv1, a->n);
      }
  const Rgb mean = sum * (1.0f / float(kGrid * kGrid));
  phi_ = mean * (kPi * area_ * (emission_.twoSided ? 2.0f : 1.0f));
}

std::unique_ptr<AreaLight> makeShapeLight(std::unique_ptr<Shape> shape,
                                          const Transform& worldFromObject,
                                          const AreaEmission& emission) {
  const PlacedShape placed(shape.get(), worldFromObject);
  return std::make_unique<AreaLight>(placed, emission, std::move(shape));
}

// --- Points on the surface --------------------------------------------------------------------

std::optional<ShapeSample> AreaLight::samplePoint(const Vec3f* ref, Vec2f u, Vec3f* ns,
                                                  Vec2f* uv1) const {
  if (!(area_ > 0)) return std::nullopt;
  if (shape_) {
    std::optional<ShapeSample> s = ref ? shape_->sample(*ref, u) : shape_->sample(u);
    if (s) *ns = s->n, *uv1 = s->uv;
    return s;
  }
  float pmf = 0, ux = 0;
  const uint32_t t = triangles_.sample(u.x, &pmf, &ux);
  if (!(triangleAreas_[t] > 0)) return std::nullopt;
  const uint32_t i0 = mesh_.indices[3 * t], i1 = mesh_.indices[3 * t + 1],
                 i2 = mesh_.indices[3 * t + 2];
  // Uniform barycentrics: b0 = 1 - sqrt(u), b1 = v sqrt(u).
  const float su = std::sqrt(ux);
  const float b0 = 1 - su, b1 = u.y * su, b2 = 1 - b0 - b1;
  const Vec3f p0 = mesh_.positions[i0], p1 = mesh_.positions[i1], p2 = mesh_.positions[i2];
  ShapeSample s;
  s.p = b0 * p0 + b1 * p1 + b2 * p2;
  s.pError = gamma(6) * (abs(b0 * p0) + abs(b1 * p1) + abs(b2 * p2));
  const Vec3f c = cross(p1 - p0, p2 - p0);
  s.n = lengthSquared(c) > 0 ? normalize(c) : Vec3f{0, 0, 1};
  *ns = s.n;
  if (!mesh_.normals.empty()) {
    const Vec3f n = b0 * mesh_.normals[i0] + b1 * mesh_.normals[i1] + b2 * mesh_.normals[i2];
    if (lengthSquared(n) > 0) *ns = normalize(n);
  }
  s.uv = mesh_.uvs.empty() ? Vec2f{b1, b2}
                           : b0 * mesh_.uvs[i0] + b1 * mesh_.uvs[i1] + b2 * mesh_.uvs[i2];
  *uv1 =
      mesh_.uvs1.empty() ? s.uv : b0 * mesh_.uvs1[i0] + b1 * mesh_.uvs1[i1] + b2 * mesh_.uvs1[i2];
  s.pdf = pmf / triangleAreas_[t];
  return s;
}

float AreaLight::pdfPoint(Vec3f ref, Vec3f p, Vec3f n, uint32_t prim) const {
  if (!(area_ > 0)) return 0;
  if (shape_) return shape_->pdf(ref, p, n);
  if (prim >= triangleAreas_.size() || !(triangleAreas_[prim] > 0)) return 0;
  return triangles_.pmf(prim) / triangleAreas_[prim];
}

Vec3f AreaLight::referencePoint(const LightSampleContext& ctx) const {
  if (!shape_ || !ctx.onSurface()) return ctx.p;
  return offsetRayOrigin(ctx.p, ctx.pError, ctx.n, bounds_.center() - ctx.p);
}

// --- Light interface --------------------------------------------------------------------------

std::optional<LightSample> AreaLight::sampleLi(const LightSampleContext& ctx, Vec2f u) const {
  const Vec3f ref = referencePoint(ctx);
  Vec3f ns;
  Vec2f uv1;
  const std::optional<ShapeSample> a = samplePoint(&ref, u, &ns, &uv1);
  if (!a || !(a->pdf > 0)) return std::nullopt;
  const Vec3f toLight = a->p - ctx.p;
  const float d2 = lengthSquared(toLight);
  if (!(d2 > 0)) return std::nullopt;
  const Vec3f wi = toLight / std::sqrt(d2);
  const float cosLight = std::abs(dot(a->n, wi));
  if (!(cosLight > 0)) return std::nullopt;
  LightSample s;
  s.L = emission_.at(a->p, a->n, ns, a->uv, uv1, -wi);
  if (isBlack(s.L)) return std::nullopt;
  s.wi = wi;
  s.pLight = a->p;
  s.nLight = a->n;
  s.pLightError = a->pError;
  s.pdf = a->pdf * d2 / cosLight;
  s.delta = false;
  if (!std::isfinite(s.pdf)) return std::nullopt;
  return s;
}

float AreaLight::pdfLi(const LightSampleContext& ctx, Vec3f wi, const LightHit& hit) const {
  const float cosLight = std::abs(dot(hit.n, wi));
  const float pdf = pdfPoint(referencePoint(ctx), hit.p, hit.n, hit.prim) *
                    lengthSquared(hit.p - ctx.p) / cosLight;
  return std::isfinite(pdf) ? pdf : 0.0f;
}

std::optional<LightLeSample> AreaLight::sampleLe(Vec2f uPos, Vec2f uDir, float time) const {
  Vec3f ns;
  Vec2f uv1;
  const std::optional<ShapeSample> a = samplePoint(nullptr, uPos, &ns, &uv1);
  if (!a || !(a->pdf > 0)) return std::nullopt;
  // Two-sided: the first half of uDir.x picks the normal's side, the second the other.
  Vec3f n = a->n;
  float sidePdf = 1;
  if (emission_.twoSided) {
    sidePdf = 0.5f;
    if (uDir.x < 0.5f) {
      uDir.x = std::min(uDir.x * 2, 0x1.fffffep-1f);
    } else {
      uDir.x = std::min((uDir.x - 0.5f) * 2, 0x1.fffffep-1f);
      n = -n;
    }
  }
  const Vec3f local = sampleCosineHemisphere(uDir);
  const float pdfDir = cosineHemispherePdf(local.z) * sidePdf;
  if (!(pdfDir > 0)) return std::nullopt;
  LightLeSample s;
  s.ray = spawnRay(a->p, a->pError, n, Frame::fromZ(n).fromLocal(local), time);
  s.n = n;
  s.L = emission_.at(a->p, a->n, ns, a->uv, uv1, s.ray.d);
  if (isBlack(s.L)) return std::nullopt;
  s.pdfPos = a->pdf;
  s.pdfDir = pdfDir;
  return s;
}

std::optional<LightBounds> AreaLight::bounds() const {
  LightBounds lb;
  lb.bounds = bounds_;
  lb.phi = luminance(phi_);
  lb.twoSided = emission_.twoSided;
  lb.cosThetaE = 0;
  lb.cosThetaO = -1;  // normals in every direction unless found narrower below
  if (shape_) {
    const Vec3f n = shape_->flatNormal();
    if (lengthSquared(n) > 0) lb.w = n, lb.cosThetaO = 1;
    return lb;
  }
  // A mesh: the cone of normals around their area-weighted mean (all when they cancel).
  const auto& pos = mesh_.positions;
  const auto& idx = mesh_.indices;
  Vec3f sum;
  for (size_t t = 0; t + 2 < idx.size(); t += 3)
    sum += cross(pos[idx[t + 1]] - pos[idx[t]], pos[idx[t + 2]] - pos[idx[t]]);
  if (lengthSquared(sum) > 0) {
    lb.w = normalize(sum);
    float cosMin = 1;
    for (size_t t = 0; t + 2 < idx.size(); t += 3) {
      const Vec3f c = cross(pos[idx[t + 1]] - pos[idx[t]], pos[idx[t + 2]] - pos[idx[t]]);
      if (lengthSquared(c) > 0) cosMin = std::min(cosMin, dot(normalize(c), lb.w));
    }
    lb.cosThetaO = cosMin;
  }
  return lb;
}

}  // namespace glint
