// glint — lights. A light answers four questions, one per kind of integrator that asks:
//   sampleLi  — from a receiving point, a direction towards the light and the radiance arriving
//               along it, with its solid-angle density (next-event estimation, Whitted);
//   pdfLi     — that density for a direction a BSDF sample found the light along (MIS);
//   Le        — radiance along a ray that escaped the scene (infinite lights);
//   sampleLe  — a ray leaving the light with its emitted radiance and densities (instant
//               radiosity's light paths);
// plus its total power and spatial bounds, which the light samplers use to pick lights.
//
// Surfaces that emit (emissive materials) are lights too: the builder makes one area light per
// emissive instance, and RenderScene::instanceLight maps a hit back to it. Their radiance at a
// hit comes from the material (Material::emitted), so textured emission looks the same whether
// it is seen directly or sampled.
#pragma once

#include <optional>

#include "geometry/interaction.h"

namespace glint {

enum class LightKind {
  DeltaPosition,   // point, spot, projective: all light from one point
  DeltaDirection,  // directional: all light from one direction
  Area,            // emitting surfaces: quads, disks, spheres, emissive meshes and shapes
  Infinite,        // environment: radiance from every direction at infinity
};

// The point that receives light: on a surface (n = geometric normal) or in a medium (n = 0).
struct LightSampleContext {
  Vec3f p;
  Vec3f pError;  // rounding-error bound of p, for the shadow ray's origin
  Vec3f n;       // unit geometric normal, or zero in a medium
  Vec3f ns;      // unit shading normal, or zero in a medium
  // In a medium: the unit direction the path arrives along (towards p) and the Henyey–Greenstein
  // asymmetry there, for light samplers that weigh a directional light by the phase function
  // (zero: not known, as for single scattering's samples of every light).
  Vec3f wo;
  float g = 0;
  float time = 0;

  LightSampleContext() = default;
  LightSampleContext(const SurfaceInteraction& si, float rayTime)
      : p(si.p), pError(si.pError), n(si.ng), ns(si.ns), time(rayTime) {}
  static LightSampleContext inMedium(Vec3f p, float rayTime, Vec3f wo = {}, float g = 0) {
    LightSampleContext c;
    c.p = p, c.wo = wo, c.g = g, c.time = rayTime;
    return c;
  }
  bool onSurface() const { return n.x != 0 || n.y != 0 || n.z != 0; }
};

struct LightSample {
  Rgb L;                  // radiance arriving at the receiving point along -wi (delta lights: the
                          // intensity over r^2, or the irradiance of a directional light)
  Vec3f wi;               // unit direction from the receiving point towards the light
  Vec3f pLight;           // the point on the light (finite lights), where the shadow ray ends
  Vec3f nLight;           // the light's unit surface normal there (area lights), else zero
  Vec3f pLightError;      // rounding-error bound of pLight (area lights), else zero
  float pdf = 1;          // solid-angle density of wi (delta lights: 1)
  bool infinite = false;  // the light is at infinity: shadow rays have no end point
  bool delta = true;      // point or direction: no BSDF sample can find it
};

// A ray leaving a light, for light paths (instant radiosity). The power it carries is
// L * |cos(n, d)| / (pdfPos * pdfDir) for area lights and L / (pdfPos * pdfDir) otherwise
// (point lights: pdfPos = 1; directional and infinite lights: pdfPos is over a disk of the
// scene's radius facing the direction).
struct LightLeSample {
  Ray ray;           // origin on the light, unit direction
  Vec3f n;           // the surface normal at the origin (area lights), else zero
  Rgb L;             // radiance (area, infinite), intensity (point, spot), or radiance of the
                     // directional light's beam
  float pdfPos = 1;  // area density of the origin
  float pdfDir = 1;  // solid-angle density of the direction
  // The power the ray carries (see above).
  Rgb beta() const {
    const float c = (n.x != 0 || n.y != 0 || n.z != 0) ? std::abs(dot(n, ray.d)) : 1.0f;
    return L * (c / (pdfPos * pdfDir));
  }
};

// Where a ray met an area light (for pdfLi).
struct LightHit {
  Vec3f p;            // the hit point
  Vec3f n;            // the light's unit geometric normal there
  uint32_t prim = 0;  // the primitive hit (a mesh light's triangle)
};

// What a light sampler needs to judge a light from afar (pbrt-v4's LightBounds): where it is,
// how much it emits, and the cone of directions it emits into.
struct LightBounds {
  Bounds3f bounds;
  float phi = 0;         // total power (luminance)
  Vec3f w{0, 0, 1};      // principal emission direction (unit)
  float cosThetaO = -1;  // cosine of the spread of surface normals around w (-1: all directions)
  float cosThetaE = 0;   // cosine of the emission angle beyond the normals (0: a hemisphere)
  bool twoSided = false;
};

// A light at infinity as light samplers weigh it: the luminance of the irradiance it gives a
// surface facing it (a directional light's irradiance; an environment's pi x its mean radiance,
// what a surface under a sky of that average receives) and, for a directional light, the
// direction towards it (zero: light from every direction), whose cosine with the receiving
// surface scales it.
struct DistantImportance {
  float irradiance = 0;
  Vec3f towards{0, 0, 0};
};

class Light {
 public:
  explicit Light(LightKind kind) : kind_(kind) {}
  virtual ~Light() = default;
  LightKind kind() const { return kind_; }
  bool isDelta() const {
    return kind_ == LightKind::DeltaPosition || kind_ == LightKind::DeltaDirection;
  }
  bool castsShadows() const { return castsShadows_; }

  // Light arriving at the receiving point; nullopt when none can (outside a cone, beyond the
  // range, a degenerate sample). `u` drives area and infinite lights; delta lights ignore it.
  virtual std::optional<LightSample> sampleLi(const LightSampleContext& ctx, Vec2f u) const = 0;
  // The solid-angle density with which sampleLi(ctx, ·) returns direction `wi` towards `hit`
  // (area lights; the hit is ignored by infinite lights). 0 for delta lights.
  virtual float pdfLi(const LightSampleContext& ctx, Vec3f wi, const LightHit& hit) const {
    (void)ctx, (void)wi, (void)hit;
    return 0;
  }
  // Infinite lights: the radiance arriving along an escaping ray of unit direction `d`.
  virtual Rgb Le(Vec3f d) const {
    (void)d;
    return {};
  }
  // A ray leaving the light: `uPos` picks the origin, `uDir` the direction.
  virtual std::optional<LightLeSample> sampleLe(Vec2f uPos, Vec2f uDir, float time) const = 0;
  // True when, at a surface, sampling the BSDF can find this light as well as sampling the
  // light can: radiance that is the same from every direction, so no density beats the
  // BSDF's own. The path tracer then leaves it to BSDF sampling at the vertices whose BSDF
  // samples nearly exactly (weight 1 for the BSDF samples that find it), as pbrt-v4's
  // `allowIncompletePDF` does everywhere; Whitted, without BSDF sampling, still samples it.
  virtual bool leftToBsdfSampling() const { return false; }
  // Total emitted power, in RGB (infinite and directional lights: through a disk of the scene's
  // radius, so call preprocess first).
  virtual Rgb phi() const = 0;
  // Lights at infinity (directional and environment lights, whose bounds() are nullopt): how
  // a receiving point weighs them against each other when it picks one (DistantLightPicker,
  // renderer/light_sampler.h).
  virtual DistantImportance distantImportance() const { return {luminance(phi()), {}}; }
  // Bounds for a light BVH; nullopt for infinite and directional lights, which are sampled
  // beside the tree.
  virtual std::optional<LightBounds> bounds() const { return std::nullopt; }
  // Called once the scene is built, with the bounds of its geometry (lights at infinity need
  // the scene's extent to emit light paths and report power).
  virtual void preprocess(const Bounds3f& sceneBounds) { (void)sceneBounds; }

 protected:
  LightKind kind_;
  bool castsShadows_ = true;
};

// A shadow ray from the receiving point to the light point of `ls` (or towards the infinite
// light), both ends moved off their surfaces by their error bounds.
Ray shadowRay(const LightSampleContext& ctx, const LightSample& ls);

// Isotropic point light: I / r^2, with glTF's optional range window
// clamp(1 - (r/range)^4, 0, 1)^2 (KHR_lights_punctual's recommended falloff).
class PointLight final : public Light {
 public:
  PointLight(Vec3f position, Rgb intensity, float range, bool castsShadows);
  std::optional<LightSample> sampleLi(const LightSampleContext& ctx, Vec2f u) const override;
  std::optional<LightLeSample> sampleLe(Vec2f uPos, Vec2f uDir, float time) const override;
  Rgb phi() const override { return intensity_ * (4 * kPi); }
  std::optional<LightBounds> bounds() const override;

 private:
  Vec3f position_;
  Rgb intensity_;
  float range_;
};

// Spot light: a point light shining down `direction`, full inside the inner cone and fading
// smoothly (smoothstep in cos) to zero at the outer cone.
class SpotLight final : public Light {
 public:
  SpotLight(Vec3f position, Vec3f direction, Rgb intensity, float innerAngle, float outerAngle,
            float range, bool castsShadows);
  std::optional<LightSample> sampleLi(const LightSampleContext& ctx, Vec2f u) const override;
  std::optional<LightLeSample> sampleLe(Vec2f uPos, Vec2f uDir, float time) const override;
  Rgb phi() const override;
  std::optional<LightBounds> bounds() const override;

 private:
  float falloff(float cosTheta) const;
  Vec3f position_, direction_;
  Rgb intensity_;
  float cosInner_, cosOuter_, range_;
};

// Directional light: irradiance E (on a surface facing it) from direction -`direction`.
class DirectionalLight final : public Light {
 public:
  DirectionalLight(Vec3f direction, Rgb irradiance, bool castsShadows);
  std::optional<LightSample> sampleLi(const LightSampleContext& ctx, Vec2f u) const override;
  std::optional<LightLeSample> sampleLe(Vec2f uPos, Vec2f uDir, float time) const override;
  Rgb phi() const override { return irradiance_ * (kPi * sceneRadius_ * sceneRadius_); }
  DistantImportance distantImportance() const override {
    return {luminance(irradiance_), -direction_};
  }
  void preprocess(const Bounds3f& sceneBounds) override;

 private:
  Vec3f direction_;  // unit, the way the light travels
  Rgb irradiance_;
  Vec3f sceneCenter_;
  float sceneRadius_ = 1;
};

// Uniform environment: radiance L from every direction (the furnace test's light). Samples
// cosine-weighted directions around the receiving surface's normal (uniform over the sphere
// in media), or is left to the BSDF's sampling (leftToBsdfSampling).
class UniformEnvironmentLight final : public Light {
 public:
  explicit UniformEnvironmentLight(Rgb radiance);
  std::optional<LightSample> sampleLi(const LightSampleContext& ctx, Vec2f u) const override;
  float pdfLi(const LightSampleContext& ctx, Vec3f wi, const LightHit& hit) const override;
  Rgb Le(Vec3f) const override { return radiance_; }
  std::optional<LightLeSample> sampleLe(Vec2f uPos, Vec2f uDir, float time) const override;
  Rgb phi() const override;
  DistantImportance distantImportance() const override { return {kPi * luminance(radiance_), {}}; }
  void preprocess(const Bounds3f& sceneBounds) override;
  bool leftToBsdfSampling() const override { return true; }

 private:
  Rgb radiance_;
  Vec3f sceneCenter_;
  float sceneRadius_ = 1;
};

}  // namespace glint
