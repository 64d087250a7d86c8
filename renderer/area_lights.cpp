// glint — the area light over a placed shape or a triangle mesh.
#include "renderer/area_lights.h"

#include <algorithm>
#include <cmath>

#include "geometry/sampling.h"

namespace glint {

namespace {
bool isBlack(const Rgb& c) { return !(c.x > 0 || c.y > 0 || c.z > 0); }
}  // namespace

// --- Emission ---------------------------------------------------------------------------------

// The one place a light asks a material for its emission.
Rgb AreaEmission::at(Vec3f p, Vec3f n, Vec3f ns, Vec2f uv, Vec2f uv1, Vec3f wo) const {
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
  std::vector<float> areas(mesh_.indices.size() / 3);
  double total = 0;
  for (size_t t = 0; t < areas.size(); ++t) {
    const Vec3f p0 = pos[mesh_.indices[3 * t]], p1 = pos[mesh_.indices[3 * t + 1]],
                p2 = pos[mesh_.indices[3 * t + 2]];
    areas[t] = 0.5f * length(cross(p1 - p0, p2 - p0));
    total += areas[t];
  }
  triangles_ = DiscreteDistribution(areas);
  area_ = float(total);
  for (Vec3f p : pos) bounds_.extend(p);
  finish();
}

void AreaLight::finish() {
  // The power from the radiance averaged over a stratified grid of points: exact for constant
  // radiance, a good estimate for textures.
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
  *uv1 = mesh_.uvs1.empty() ? s.uv
                            : b0 * mesh_.uvs1[i0] + b1 * mesh_.uvs1[i1] + b2 * mesh_.uvs1[i2];
  s.pdf = 1 / area_;
  return s;
}

float AreaLight::pdfPoint(Vec3f ref, Vec3f p, Vec3f n) const {
  if (!(area_ > 0)) return 0;
  return shape_ ? shape_->pdf(ref, p, n) : 1 / area_;
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
  const float pdf =
      pdfPoint(referencePoint(ctx), hit.p, hit.n) * lengthSquared(hit.p - ctx.p) / cosLight;
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
