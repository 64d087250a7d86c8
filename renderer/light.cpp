// glint — point, spot and directional lights, the uniform environment, and shadow rays.
#include "renderer/light.h"

#include <cmath>

#include "geometry/sampling.h"

namespace glint {

namespace {
float rangeWindow(float distance, float range) {
  if (range <= 0) return 1;
  float x = distance / range;
  float w = std::clamp(1 - x * x * x * x, 0.0f, 1.0f);
  return w * w;
}
float smoothStep(float a, float b, float x) {
  if (a == b) return x < a ? 0.0f : 1.0f;
  float t = std::clamp((x - a) / (b - a), 0.0f, 1.0f);
  return t * t * (3 - 2 * t);
}
// A delta-position light's sample towards `position`.
std::optional<LightSample> towardsPoint(const LightSampleContext& ctx, Vec3f position,
                                        Rgb intensity, float range, float* cosToLight, Vec3f axis) {
  Vec3f toLight = position - ctx.p;
  float r2 = lengthSquared(toLight);
  if (!(r2 > 0)) return std::nullopt;
  float r = std::sqrt(r2);
  Vec3f wi = toLight / r;
  if (cosToLight) *cosToLight = dot(-wi, axis);
  float window = rangeWindow(r, range);
  if (window == 0) return std::nullopt;
  LightSample s;
  s.L = intensity * (window / r2);
  s.wi = wi;
  s.pLight = position;
  return s;
}
// The disk of the scene's bounding sphere facing `d`, through which lights at infinity send
// their light paths: a uniform point on it, moved back out of the sphere.
Vec3f pointOnSceneDisk(Vec3f d, Vec3f center, float radius, Vec2f u) {
  const Frame f = Frame::fromZ(d);
  const Vec2f q = sampleConcentricDisk(u);
  return center + radius * (f.s * q.x + f.t * q.y - d);
}
void sceneSphere(const Bounds3f& b, Vec3f* center, float* radius) {
  if (b.empty()) {
    *center = {}, *radius = 1;
    return;
  }
  *center = b.center();
  *radius = std::max(length(b.diagonal()) * 0.5f, 1e-6f);
}
}  // namespace

Ray shadowRay(const LightSampleContext& ctx, const LightSample& ls) {
  // In a medium there is no surface to leave: the normal is zero and so is the offset.
  if (ls.infinite) return spawnRay(ctx.p, ctx.pError, ctx.n, ls.wi, ctx.time);
  // A point or spot light is reached exactly; an area light's point is left by its own error
  // bound, so the ray cannot report the light itself (see spawnRayToSurface).
  return spawnRayToSurface(ctx.p, ctx.pError, ctx.n, ls.pLight, ls.pLightError, ls.nLight,
                           ctx.time);
}

// --- Point ------------------------------------------------------------------------------------

PointLight::PointLight(Vec3f position, Rgb intensity, float range, bool castsShadows)
    : Light(LightKind::DeltaPosition), position_(position), intensity_(intensity), range_(range) {
  castsShadows_ = castsShadows;
}

std::optional<LightSample> PointLight::sampleLi(const LightSampleContext& ctx, Vec2f) const {
  return towardsPoint(ctx, position_, intensity_, range_, nullptr, {});
}

std::optional<LightLeSample> PointLight::sampleLe(Vec2f, Vec2f uDir, float time) const {
  LightLeSample s;
  s.ray = Ray{position_, sampleUniformSphere(uDir), 0, kInfinity, time};
  s.L = intensity_;
  s.pdfDir = kUniformSpherePdf;
  return s;
}

std::optional<LightBounds> PointLight::bounds() const {
  LightBounds b;
  b.bounds = Bounds3f{position_, position_};
  b.phi = 4 * kPi * luminance(intensity_);
  b.cosThetaO = -1;  // all directions
  b.cosThetaE = 0;
  return b;
}

// --- Spot -------------------------------------------------------------------------------------

SpotLight::SpotLight(Vec3f position, Vec3f direction, Rgb intensity, float innerAngle,
                     float outerAngle, float range, bool castsShadows)
    : Light(LightKind::DeltaPosition),
      position_(position),
      direction_(normalize(direction)),
      intensity_(intensity),
      cosInner_(std::cos(innerAngle)),
      cosOuter_(std::cos(outerAngle)),
      range_(range) {
  castsShadows_ = castsShadows;
}

float SpotLight::falloff(float cosTheta) const {
  return smoothStep(cosOuter_, cosInner_, cosTheta);
}

std::optional<LightSample> SpotLight::sampleLi(const LightSampleContext& ctx, Vec2f) const {
  float cosTheta = 0;
  std::optional<LightSample> s =
      towardsPoint(ctx, position_, intensity_, range_, &cosTheta, direction_);
  if (!s) return s;
  const float cone = falloff(cosTheta);
  if (cone == 0) return std::nullopt;
  s->L *= cone;
  return s;
}

std::optional<LightLeSample> SpotLight::sampleLe(Vec2f, Vec2f uDir, float time) const {
  // Uniform in the outer cone; the smooth falloff goes into L.
  const Vec3f local = sampleUniformCone(uDir, cosOuter_);
  const float cone = falloff(local.z);
  if (cone == 0) return std::nullopt;
  LightLeSample s;
  s.ray = Ray{position_, Frame::fromZ(direction_).fromLocal(local), 0, kInfinity, time};
  s.L = intensity_ * cone;
  s.pdfDir = uniformConePdf(cosOuter_);
  return s;
}

Rgb SpotLight::phi() const {
  // The integral of the smoothstep falloff over the sphere: 2 pi [(1 - cosInner) +
  // (cosInner - cosOuter) / 2], the smoothstep averaging one half over its band.
  return intensity_ * (2 * kPi * ((1 - cosInner_) + (cosInner_ - cosOuter_) * 0.5f));
}

std::optional<LightBounds> SpotLight::bounds() const {
  LightBounds b;
  b.bounds = Bounds3f{position_, position_};
  b.phi = luminance(phi());
  b.w = direction_;
  b.cosThetaO = 1;  // a point: one "normal"
  b.cosThetaE = cosOuter_;
  return b;
}

// --- Directional ------------------------------------------------------------------------------

DirectionalLight::DirectionalLight(Vec3f direction, Rgb irradiance, bool castsShadows)
    : Light(LightKind::DeltaDirection), direction_(normalize(direction)), irradiance_(irradiance) {
  castsShadows_ = castsShadows;
}

void DirectionalLight::preprocess(const Bounds3f& sceneBounds) {
  sceneSphere(sceneBounds, &sceneCenter_, &sceneRadius_);
}

std::optional<LightSample> DirectionalLight::sampleLi(const LightSampleContext&, Vec2f) const {
  LightSample s;
  s.L = irradiance_;
  s.wi = -direction_;
  s.infinite = true;
  return s;
}

std::optional<LightLeSample> DirectionalLight::sampleLe(Vec2f uPos, Vec2f, float time) const {
  LightLeSample s;
  s.ray = Ray{pointOnSceneDisk(direction_, sceneCenter_, sceneRadius_, uPos), direction_, 0,
              kInfinity, time};
  s.L = irradiance_;
  s.pdfPos = 1 / (kPi * sceneRadius_ * sceneRadius_);
  s.pdfDir = 1;
  return s;
}

// --- Uniform environment ----------------------------------------------------------------------

UniformEnvironmentLight::UniformEnvironmentLight(Rgb radiance)
    : Light(LightKind::Infinite), radiance_(radiance) {}

void UniformEnvironmentLight::preprocess(const Bounds3f& sceneBounds) {
  sceneSphere(sceneBounds, &sceneCenter_, &sceneRadius_);
}

std::optional<LightSample> UniformEnvironmentLight::sampleLi(const LightSampleContext& ctx,
                                                             Vec2f u) const {
  LightSample s;
  if (ctx.onSurface()) {
    const Vec3f local = sampleCosineHemisphere(u);
    s.wi = Frame::fromZ(ctx.ns).fromLocal(local);
    s.pdf = cosineHemispherePdf(local.z);
  } else {
    s.wi = sampleUniformSphere(u);
    s.pdf = kUniformSpherePdf;
  }
  if (!(s.pdf > 0)) return std::nullopt;
  s.L = radiance_;
  s.infinite = true;
  s.delta = false;
  return s;
}

float UniformEnvironmentLight::pdfLi(const LightSampleContext& ctx, Vec3f wi,
                                     const LightHit&) const {
  if (!ctx.onSurface()) return kUniformSpherePdf;
  return cosineHemispherePdf(dot(ctx.ns, wi));
}

std::optional<LightLeSample> UniformEnvironmentLight::sampleLe(Vec2f uPos, Vec2f uDir,
                                                               float time) const {
  // Light arriving from direction -d: a uniform direction, then a uniform point on the scene
  // disk facing it.
  const Vec3f d = -sampleUniformSphere(uDir);
  LightLeSample s;
  s.ray = Ray{pointOnSceneDisk(d, sceneCenter_, sceneRadius_, uPos), d, 0, kInfinity, time};
  s.L = radiance_;
  s.pdfPos = 1 / (kPi * sceneRadius_ * sceneRadius_);
  s.pdfDir = kUniformSpherePdf;
  return s;
}

Rgb UniformEnvironmentLight::phi() const {
  // Radiance L from every direction, each through the scene's disk of area pi r^2.
  return radiance_ * (4 * kPi * kPi * sceneRadius_ * sceneRadius_);
}

}  // namespace glint
