// glint — quad, disk, sphere, triangle-mesh and shape-surface area lights.
#include "renderer/area_lights.h"

#include <algorithm>
#include <cmath>

#include "geometry/sampling.h"

namespace glint {

namespace {
bool isBlack(const Rgb& c) { return !(c.x > 0 || c.y > 0 || c.z > 0); }
// The light's cone of normals for a flat emitter: one normal, emitting into its hemisphere.
LightBounds flatBounds(const Bounds3f& b, Vec3f n, float phi, bool twoSided) {
  LightBounds lb;
  lb.bounds = b;
  lb.phi = phi;
  lb.w = n;
  lb.cosThetaO = 1;
  lb.cosThetaE = 0;
  lb.twoSided = twoSided;
  return lb;
}
}  // namespace

// --- Emission ---------------------------------------------------------------------------------

Rgb AreaEmission::at(Vec3f p, Vec3f n, Vec3f ns, Vec2f uv, Vec3f wo) const {
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
  si.frontFace = c >= 0;
  si.objectFromWorld = &objectFromWorld;
  si.instance = instance;
  return material->emitted(si);
}

// --- Area sampling ----------------------------------------------------------------------------

void AreaLight::finish() {
  // A stratified grid: exact for constant radiance, a good estimate for textures.
  constexpr int kGrid = 16;
  Rgb sum;
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i) {
      const AreaPoint a = samplePoint({(float(i) + 0.5f) / kGrid, (float(j) + 0.5f) / kGrid});
      sum += emission_.at(a.p, a.n, a.ns, a.uv, a.n);
    }
  const Rgb mean = sum * (1.0f / float(kGrid * kGrid));
  phi_ = mean * (kPi * area_ * (emission_.twoSided ? 2.0f : 1.0f));
}

std::optional<LightSample> AreaLight::sampleLi(const LightSampleContext& ctx, Vec2f u) const {
  if (!(area_ > 0)) return std::nullopt;
  const AreaPoint a = samplePoint(u);
  const Vec3f toLight = a.p - ctx.p;
  const float d2 = lengthSquared(toLight);
  if (!(d2 > 0)) return std::nullopt;
  const Vec3f wi = toLight / std::sqrt(d2);
  const float cosLight = std::abs(dot(a.n, wi));
  if (!(cosLight > 0)) return std::nullopt;
  LightSample s;
  s.L = emission_.at(a.p, a.n, a.ns, a.uv, -wi);
  if (isBlack(s.L)) return std::nullopt;
  s.wi = wi;
  s.pLight = a.p;
  s.nLight = a.n;
  s.pLightError = a.pError;
  s.pdf = d2 * areaDensity(a.n) / cosLight;
  s.delta = false;
  if (!std::isfinite(s.pdf)) return std::nullopt;
  return s;
}

float AreaLight::pdfLi(const LightSampleContext& ctx, Vec3f wi, const LightHit& hit) const {
  const float cosLight = std::abs(dot(hit.n, wi));
  const float pdf = lengthSquared(hit.p - ctx.p) * areaDensity(hit.n) / cosLight;
  return std::isfinite(pdf) ? pdf : 0.0f;
}

std::optional<LightLeSample> AreaLight::sampleLe(Vec2f uPos, Vec2f uDir, float time) const {
  if (!(area_ > 0)) return std::nullopt;
  const AreaPoint a = samplePoint(uPos);
  // Two-sided: the first half of uDir.x picks the normal's side, the second the other.
  Vec3f n = a.n;
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
  s.ray = spawnRay(a.p, a.pError, n, Frame::fromZ(n).fromLocal(local), time);
  s.n = n;
  s.L = emission_.at(a.p, a.n, a.ns, a.uv, s.ray.d);
  if (isBlack(s.L)) return std::nullopt;
  s.pdfPos = areaDensity(a.n);
  s.pdfDir = pdfDir;
  return s;
}

// --- Quad -------------------------------------------------------------------------------------

QuadLight::QuadLight(Vec3f corner, Vec3f edgeU, Vec3f edgeV, const AreaEmission& emission)
    : AreaLight(emission), corner_(corner), edgeU_(edgeU), edgeV_(edgeV) {
  const Vec3f c = cross(edgeU, edgeV);
  area_ = length(c);
  normal_ = area_ > 0 ? c / area_ : Vec3f{0, 0, 1};
  finish();
}

AreaPoint QuadLight::samplePoint(Vec2f u) const {
  AreaPoint a;
  const Vec3f du = edgeU_ * u.x, dv = edgeV_ * u.y;
  a.p = corner_ + du + dv;
  a.pError = gamma(6) * (abs(corner_) + abs(du) + abs(dv));
  a.n = a.ns = normal_;
  a.uv = u;
  return a;
}

std::optional<LightBounds> QuadLight::bounds() const {
  Bounds3f b;
  for (Vec3f p : {corner_, corner_ + edgeU_, corner_ + edgeV_, corner_ + edgeU_ + edgeV_})
    b.extend(p);
  return flatBounds(b, normal_, luminance(phi_), emission_.twoSided);
}

// --- Disk -------------------------------------------------------------------------------------

DiskLight::DiskLight(Vec3f center, Vec3f axisX, Vec3f axisZ, const AreaEmission& emission)
    : AreaLight(emission), center_(center), axisX_(axisX), axisZ_(axisZ) {
  const Vec3f c = cross(axisZ, axisX);
  area_ = kPi * length(c);
  normal_ = area_ > 0 ? normalize(c) : Vec3f{0, 1, 0};
  finish();
}

AreaPoint DiskLight::samplePoint(Vec2f u) const {
  // A linear map of the unit disk keeps uniform points uniform.
  const Vec2f q = sampleConcentricDisk(u);
  AreaPoint a;
  const Vec3f dx = axisX_ * q.x, dz = axisZ_ * q.y;
  a.p = center_ + dx + dz;
  a.pError = gamma(6) * (abs(center_) + abs(dx) + abs(dz));
  a.n = a.ns = normal_;
  a.uv = {q.x * 0.5f + 0.5f, q.y * 0.5f + 0.5f};
  return a;
}

std::optional<LightBounds> DiskLight::bounds() const {
  // The box of the ellipse: center +- sqrt(axisX_i^2 + axisZ_i^2) per axis.
  const Vec3f e{std::sqrt(axisX_.x * axisX_.x + axisZ_.x * axisZ_.x),
                std::sqrt(axisX_.y * axisX_.y + axisZ_.y * axisZ_.y),
                std::sqrt(axisX_.z * axisX_.z + axisZ_.z * axisZ_.z)};
  return flatBounds(Bounds3f{center_ - e, center_ + e}, normal_, luminance(phi_),
                    emission_.twoSided);
}

// --- Sphere -----------------------------------------------------------------------------------

namespace {
// The cone a sphere subtends from a point outside it: cos and (1 - cos) of its half-angle,
// the latter as sin^2 / (1 + cos), which keeps its precision for distant spheres (where
// 1 - cos would cancel to nothing in float).
void sphereCone(float d2, float r, float* cosMax, float* oneMinusCosMax) {
  const float sin2Max = r * r / d2;
  *cosMax = std::sqrt(std::max(0.0f, 1 - sin2Max));
  *oneMinusCosMax = sin2Max / (1 + *cosMax);
}
}  // namespace

SphereLight::SphereLight(Vec3f center, float radius, const AreaEmission& emission)
    : AreaLight(emission), center_(center), radius_(radius) {
  area_ = 4 * kPi * radius * radius;
  finish();
}

AreaPoint SphereLight::pointAt(Vec3f n) const {
  AreaPoint a;
  a.p = center_ + radius_ * n;
  a.pError = gamma(5) * abs(a.p);
  a.n = a.ns = n;
  // The sphere shape's uv, in the object frame.
  const Vec3f o = normalize(emission_.objectFromWorld.vector(n));
  float phi = std::atan2(o.z, o.x);
  if (phi < 0) phi += 2 * kPi;
  a.uv = {phi / (2 * kPi), std::acos(std::clamp(o.y, -1.0f, 1.0f)) / kPi};
  return a;
}

AreaPoint SphereLight::samplePoint(Vec2f u) const { return pointAt(sampleUniformSphere(u)); }

namespace {
// The squared distance from the sphere's centre to the receiving point, moved towards the
// centre past its rounding error: a point on the sphere itself (a surface of the light lit by
// the rest of it, as inside a glowing enclosure) then counts as inside whichever way its
// coordinates rounded, rather than seeing a degenerate hemisphere "cone" half of the time.
float receiverDistanceSquared(const LightSampleContext& ctx, Vec3f center) {
  const Vec3f p = ctx.onSurface() ? offsetRayOrigin(ctx.p, ctx.pError, ctx.n, center - ctx.p)
                                  : ctx.p;
  return lengthSquared(p - center);
}
}  // namespace

std::optional<LightSample> SphereLight::sampleLi(const LightSampleContext& ctx, Vec2f u) const {
  const float d2 = receiverDistanceSquared(ctx, center_);
  if (d2 <= radius_ * radius_) return AreaLight::sampleLi(ctx, u);  // inside: by area
  // Outside: a uniform direction in the subtended cone, then the point it first meets on the
  // sphere, found from the angle alpha at the centre rather than by intersecting a ray (which
  // is inaccurate at the cone's edge).
  float cosMax, oneMinusCosMax;
  sphereCone(d2, radius_, &cosMax, &oneMinusCosMax);
  // With t = 1 - cos(theta) uniform in [0, 1 - cosMax], sin^2 = t (2 - t) without cancellation.
  const float t = u.x * oneMinusCosMax;
  const float cosTheta = 1 - t, sin2Theta = t * (2 - t);
  const float sin2Max = radius_ * radius_ / d2, sinMax = std::sqrt(sin2Max);
  const float cosAlpha = sin2Theta / sinMax +
                         cosTheta * std::sqrt(std::max(0.0f, 1 - sin2Theta / sin2Max));
  const float sinAlpha = std::sqrt(std::max(0.0f, 1 - cosAlpha * cosAlpha));
  const float phi = 2 * kPi * u.y;
  const Vec3f w{sinAlpha * std::cos(phi), sinAlpha * std::sin(phi), cosAlpha};
  const Frame frame = Frame::fromZ(normalize(center_ - ctx.p));
  const AreaPoint a = pointAt(frame.fromLocal(-w));
  const Vec3f toLight = a.p - ctx.p;
  const float dist = length(toLight);
  if (!(dist > 0)) return std::nullopt;
  LightSample s;
  s.wi = toLight / dist;
  s.L = emission_.at(a.p, a.n, a.ns, a.uv, -s.wi);
  if (isBlack(s.L)) return std::nullopt;
  s.pLight = a.p;
  s.nLight = a.n;
  s.pLightError = a.pError;
  s.pdf = 1 / (2 * kPi * oneMinusCosMax);
  s.delta = false;
  return s;
}

float SphereLight::pdfLi(const LightSampleContext& ctx, Vec3f wi, const LightHit& hit) const {
  const float d2 = receiverDistanceSquared(ctx, center_);
  if (d2 <= radius_ * radius_) return AreaLight::pdfLi(ctx, wi, hit);
  float cosMax, oneMinusCosMax;
  sphereCone(d2, radius_, &cosMax, &oneMinusCosMax);
  return 1 / (2 * kPi * oneMinusCosMax);
}

std::optional<LightBounds> SphereLight::bounds() const {
  LightBounds lb;
  const Vec3f r{radius_, radius_, radius_};
  lb.bounds = Bounds3f{center_ - r, center_ + r};
  lb.phi = luminance(phi_);
  lb.cosThetaO = -1;  // normals in every direction
  lb.cosThetaE = 0;
  lb.twoSided = emission_.twoSided;
  return lb;
}

// --- Triangle mesh ----------------------------------------------------------------------------

TriangleMeshLight::TriangleMeshLight(std::vector<Vec3f> positions, std::vector<uint32_t> indices,
                                     std::vector<Vec3f> normals, std::vector<Vec2f> uvs,
                                     const AreaEmission& emission)
    : AreaLight(emission),
      positions_(std::move(positions)),
      normals_(std::move(normals)),
      indices_(std::move(indices)),
      uvs_(std::move(uvs)) {
  std::vector<float> areas(indices_.size() / 3);
  double total = 0;
  for (size_t t = 0; t < areas.size(); ++t) {
    const Vec3f p0 = positions_[indices_[3 * t]], p1 = positions_[indices_[3 * t + 1]],
                p2 = positions_[indices_[3 * t + 2]];
    areas[t] = 0.5f * length(cross(p1 - p0, p2 - p0));
    total += areas[t];
  }
  triangles_ = DiscreteDistribution(areas);
  area_ = float(total);
  finish();
}

AreaPoint TriangleMeshLight::samplePoint(Vec2f u) const {
  float p = 0, ux = 0;
  const uint32_t t = triangles_.sample(u.x, &p, &ux);
  const uint32_t i0 = indices_[3 * t], i1 = indices_[3 * t + 1], i2 = indices_[3 * t + 2];
  // Uniform barycentrics: b0 = 1 - sqrt(u), b1 = v sqrt(u).
  const float su = std::sqrt(ux);
  const float b0 = 1 - su, b1 = u.y * su, b2 = 1 - b0 - b1;
  const Vec3f p0 = positions_[i0], p1 = positions_[i1], p2 = positions_[i2];
  AreaPoint a;
  a.p = b0 * p0 + b1 * p1 + b2 * p2;
  a.pError = gamma(6) * (abs(b0 * p0) + abs(b1 * p1) + abs(b2 * p2));
  const Vec3f c = cross(p1 - p0, p2 - p0);
  a.n = lengthSquared(c) > 0 ? normalize(c) : Vec3f{0, 0, 1};
  a.ns = a.n;
  if (!normals_.empty()) {
    const Vec3f ns = b0 * normals_[i0] + b1 * normals_[i1] + b2 * normals_[i2];
    if (lengthSquared(ns) > 0) a.ns = normalize(ns);
  }
  a.uv = uvs_.empty() ? Vec2f{b1, b2} : b0 * uvs_[i0] + b1 * uvs_[i1] + b2 * uvs_[i2];
  return a;
}

std::optional<LightBounds> TriangleMeshLight::bounds() const {
  LightBounds lb;
  Bounds3f b;
  Vec3f sum;
  for (Vec3f p : positions_) b.extend(p);
  for (size_t t = 0; t + 2 < indices_.size(); t += 3)
    sum += cross(positions_[indices_[t + 1]] - positions_[indices_[t]],
                 positions_[indices_[t + 2]] - positions_[indices_[t]]);
  lb.bounds = b;
  lb.phi = luminance(phi_);
  lb.twoSided = emission_.twoSided;
  lb.cosThetaE = 0;
  // The cone of normals around their area-weighted mean (all directions when they cancel).
  lb.cosThetaO = -1;
  if (lengthSquared(sum) > 0) {
    lb.w = normalize(sum);
    float cosMin = 1;
    for (size_t t = 0; t + 2 < indices_.size(); t += 3) {
      const Vec3f c = cross(positions_[indices_[t + 1]] - positions_[indices_[t]],
                            positions_[indices_[t + 2]] - positions_[indices_[t]]);
      if (lengthSquared(c) > 0) cosMin = std::min(cosMin, dot(normalize(c), lb.w));
    }
    lb.cosThetaO = cosMin;
  }
  return lb;
}

// --- Shape surfaces ---------------------------------------------------------------------------

float SurfacePart::area() const {
  switch (kind) {
    case Kind::Parallelogram:
      return length(cross(edgeU, edgeV));
    case Kind::Disk:
      return kPi * radius * radius;
    case Kind::CylinderSide:
      return 2 * kPi * radius * height;
    case Kind::ConeSide:
      return kPi * radius * std::sqrt(radius * radius + height * height);
    case Kind::Sphere:
      return 4 * kPi * radius * radius;
  }
  return 0;
}

namespace {

// A uniform point of `part` in object space: position, outward unit normal, uv.
void samplePart(const SurfacePart& part, Vec2f u, Vec3f* p, Vec3f* n, Vec2f* uv) {
  using Kind = SurfacePart::Kind;
  const float phi = 2 * kPi * u.y;  // the round parts' angle, from +X towards +Z
  const float c = std::cos(phi), s = std::sin(phi);
  switch (part.kind) {
    case Kind::Parallelogram:
      *p = part.origin + part.edgeU * u.x + part.edgeV * u.y;
      *n = part.normal;
      *uv = u;
      return;
    case Kind::Disk: {
      const float r = part.radius * std::sqrt(u.x);
      *p = part.origin + Vec3f{r * c, 0, r * s};
      *n = part.normal;
      *uv = {r * c / (2 * part.radius) + 0.5f, r * s / (2 * part.radius) + 0.5f};
      return;
    }
    case Kind::CylinderSide:
      *p = part.origin + Vec3f{part.radius * c, part.height * u.x, part.radius * s};
      *n = {c, 0, s};
      *uv = {u.y, u.x};
      return;
    case Kind::ConeSide: {
      // Area grows linearly with the distance from the apex: that distance ∝ sqrt(u).
      const float t = std::sqrt(u.x);  // 0 at the apex, 1 at the base
      const float r = part.radius * t, y = part.height * (1 - t);
      *p = part.origin + Vec3f{r * c, y, r * s};
      *n = normalize(Vec3f{part.height * c, part.radius, part.height * s});
      *uv = {u.y, 1 - t};
      return;
    }
    case Kind::Sphere: {
      const Vec3f d = sampleUniformSphere(u);
      *p = part.origin + d * part.radius;
      *n = d;
      float a = std::atan2(d.z, d.x);
      if (a < 0) a += 2 * kPi;
      *uv = {a / (2 * kPi), std::acos(std::clamp(d.y, -1.0f, 1.0f)) / kPi};
      return;
    }
  }
}

float determinant3(const Transform& t) {
  const auto& m = t.matrix().m;
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

// M^T v for the linear part M of t.
Vec3f transposeTimes(const Transform& t, Vec3f v) {
  const auto& m = t.matrix().m;
  return {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z,
          m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
          m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z};
}

}  // namespace

ShapeSurfaceLight::ShapeSurfaceLight(std::vector<SurfacePart> parts,
                                     const Transform& worldFromObject,
                                     const AreaEmission& emission)
    : AreaLight(emission), parts_(std::move(parts)), world_(worldFromObject) {
  std::vector<float> areas;
  for (const SurfacePart& part : parts_) {
    areas.push_back(part.area());
    objectArea_ += areas.back();
  }
  byArea_ = DiscreteDistribution(areas);
  det_ = std::abs(determinant3(world_));
  // The world area, A_obj E[J] over object-uniform points (a stratified grid: exact under a
  // similarity, within a fraction of a percent otherwise). It only scales the power phi, which
  // guides the light sampler; the densities above are exact.
  if (objectArea_ > 0 && det_ > 0) {
    constexpr int kGrid = 64;
    double sum = 0;
    for (int j = 0; j < kGrid; ++j)
      for (int i = 0; i < kGrid; ++i) {
        const AreaPoint a = samplePoint({(float(i) + 0.5f) / kGrid, (float(j) + 0.5f) / kGrid});
        sum += 1 / double(areaDensity(a.n));
      }
    area_ = float(sum / (kGrid * kGrid));
  }
  for (const SurfacePart& part : parts_) {
    Bounds3f b;
    switch (part.kind) {
      case SurfacePart::Kind::Parallelogram:
        for (Vec3f q : {part.origin, part.origin + part.edgeU, part.origin + part.edgeV,
                        part.origin + part.edgeU + part.edgeV})
          b.extend(q);
        break;
      case SurfacePart::Kind::Sphere:
        b = {part.origin - Vec3f{part.radius, part.radius, part.radius},
             part.origin + Vec3f{part.radius, part.radius, part.radius}};
        break;
      default:  // disks and sides: the box around the part's cylinder
        b = {part.origin - Vec3f{part.radius, 0, part.radius},
             part.origin + Vec3f{part.radius, part.height, part.radius}};
    }
    bounds_.extend(world_.bounds(b));
  }
  finish();
}

AreaPoint ShapeSurfaceLight::samplePoint(Vec2f u) const {
  AreaPoint a;
  if (parts_.empty()) return a;
  float pmf = 0, ux = 0;
  const SurfacePart& part = parts_[byArea_.sample(u.x, &pmf, &ux)];
  Vec3f p, n;
  samplePart(part, {std::min(ux, 0x1.fffffep-1f), u.y}, &p, &n, &a.uv);
  // Trigonometric and square-root points: a few ulps of the object-space coordinates.
  a.p = world_.point(p, gamma(8) * abs(p), &a.pError);
  a.n = a.ns = normalize(world_.normal(n));
  return a;
}

float ShapeSurfaceLight::areaDensity(Vec3f n) const {
  if (!(objectArea_ > 0) || !(det_ > 0)) return 0;
  return length(transposeTimes(world_, n)) / (objectArea_ * det_);
}

std::optional<LightBounds> ShapeSurfaceLight::bounds() const {
  LightBounds lb;
  lb.bounds = bounds_;
  lb.phi = luminance(phi_);
  lb.cosThetaO = -1;  // normals in every direction
  lb.cosThetaE = 0;
  lb.twoSided = emission_.twoSided;
  return lb;
}

}  // namespace glint
