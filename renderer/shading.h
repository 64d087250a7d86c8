// glint — a hit made ready to shade: its material, the surface details that material reads,
// and its textures, in one call (pbrt-v4's SurfaceInteraction::GetBSDF, which every
// integrator calls the same way). What each material's hits need is decided once per material
// (MaterialShading), not per hit.
#pragma once

#include <cmath>
#include <cstdint>
#include <new>
#include <type_traits>
#include <vector>

#include "renderer/scene.h"

namespace glint {

// What shading a material's hits needs, decided once per material (not per hit).
struct MaterialShading {
  SurfaceNeeds needs;
  bool objectSpace = false;  // object-space textures or snow: set objectFromWorld
  bool footprint = false;    // filtered textures or bump steps: set the pixel footprint
  bool unlit = false;
  bool transparent = false;  // may let light pass straight through (opacity < 1)
  bool emits = false;        // Material::emitted can be non-zero
  // Its inside absorbs (Material::absorption): a ray reaching its back face has crossed the
  // inside and is attenuated by the distance (closed surfaces; see ShadedHit::inside).
  bool absorbs = false;
  uint32_t flags = 0;
};

// One MaterialShading per material of `scene`, in the order of scene.materials().
std::vector<MaterialShading> materialShadings(const RenderScene& scene);

// Sets si.dpdx/dpdy and si.duvdx/duvdy for a ray of unit direction `d` whose pixel cone is
// `width` wide at the hit: two perpendicular cone radii projected onto the surface's tangent
// plane along d, then expressed in uv by least squares on dp/du and dp/dv (pbrt-v4's
// SurfaceInteraction::ComputeDifferentials).
void setPixelFootprint(SurfaceInteraction& si, Vec3f d, float width);

// Room for a moving object's frame at one ray's time, which a SurfaceInteraction may point to
// (si.objectFromWorld); constructed only when a hit needs it. A std::optional<Transform> in its
// place was zero-filled (128 bytes, `rep stos`) on every hit: a fifth of Whitted's own time per
// hit in features_bench's profile.
class MovingFrame {
 public:
  MovingFrame() {}
  MovingFrame(const MovingFrame&) = delete;
  MovingFrame& operator=(const MovingFrame&) = delete;
  const Transform* set(const Transform& t) {
    static_assert(std::is_trivially_destructible_v<Transform>);
    return new (&frame_) Transform(t);
  }

 private:
  union {
    Transform frame_;
  };
};

// A ray's hit made ready to shade, the one way every integrator shades a surface:
//
//   ShadedHit h(scene, shadings, ray, hit, cone);
//   if (h.shading.transparent && u >= h.opacity()) ...;  // pass straight through
//   const Bsdf bsdf = h.bsdf();
//
// It holds the hit's material and what that material needs (MaterialShading); the surface
// details at the hit (`si`), only the attributes the material reads, its object frame and pixel
// footprint when it reads them, its shading normal perturbed (bump, normal map, snow); and the
// texture lookups, each texture read once however many parameters read it. Built in place,
// neither copied nor moved: `si` may point to the moving frame held here, and the lookups read
// `si` (a VPL keeps a copy of `si` with the frame cleared).
class ShadedHit {
 public:
  // `shadings` is materialShadings(scene); `cone` is the ray's pixel cone (RayCone{} where
  // nothing reads a footprint), by value: two floats, and a caller's own cone (the path
  // tracer's, in its Path) stays out of memory.
  ShadedHit(const RenderScene& scene, const std::vector<MaterialShading>& shadings, const Ray& ray,
            const Hit& hit, RayCone cone)
      : ShadedHit(scene, shadings, scene.materialIndex(hit), ray, hit, cone) {}
  // The same for a hit whose material index the caller already has.
  ShadedHit(const RenderScene& scene, const std::vector<MaterialShading>& shadings,
            uint32_t materialIndex, const Ray& ray, const Hit& hit, RayCone cone);
  ShadedHit(const ShadedHit&) = delete;
  ShadedHit& operator=(const ShadedHit&) = delete;

 private:
  MovingFrame frame_;  // first: `si` is computed into it (a moving object's frame)

 public:
  const Material& material;
  const MaterialShading& shading;
  SurfaceInteraction si;
  TextureLookups lookups;
  // How far along the ray the hit is, in world units (the ray's direction need not be unit).
  const float distance;

  // The material's parameters at the hit, read once: the BSDF an integrator samples and
  // evaluates.
  Bsdf bsdf() { return material.bsdf(si, lookups); }
  float opacity() { return material.opacity(si, lookups); }
  Rgb emitted() { return material.emitted(si, lookups); }
  Rgb unlitRadiance() { return material.unlitRadiance(si, lookups); }
  Rgb albedo() { return material.albedo(si, lookups); }

  // The fraction of light that crossed the material's inside to reach this back face:
  // exp(-absorption * distance); 1 at front faces or for clear materials. Integrators apply it
  // to every segment that ends on a back face, which needs no record of which objects a path
  // is inside; the price is that nested or open volumes are not modelled.
  Rgb inside() const {
    if (!shading.absorbs || si.frontFace) return {1, 1, 1};
    const Rgb sigma = material.absorption();
    return {std::exp(-sigma.x * distance), std::exp(-sigma.y * distance),
            std::exp(-sigma.z * distance)};
  }
};

}  // namespace glint
