// glint — the accelerator interface: closest-hit and any-hit queries over a GeometryScene.
//
// Backends are interchangeable and chosen by name (makeAccelerator); they are tested against
// each other. A hit records only what traversal knows (t, instance, primitive, barycentrics);
// surface details are computed once, for the final hit (computeSurfaceInteraction).
//
// Motion blur: every backend supports moving instances (Instance::motion animated). A ray is
// intersected with the scene as it is at ray.time (normalised shutter time, [0, 1]), each
// moving placement interpolated as AnimatedTransform::at does (Embree's quaternion-instance
// interpolation). Static scenes are built and traced exactly as without motion. Embree holds
// moving objects in its motion-blur BVH; the kd-trees keep them out of the tree and test them
// one by one at the ray's time (fine for a few, slow for many).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/ray.h"

namespace glint {

struct Hit {
  static constexpr uint32_t kInvalid = ~0u;
  float t = kInfinity;
  uint32_t instance = kInvalid;  // index into GeometryScene::instances
  uint32_t prim = kInvalid;      // triangle index within the instance's mesh, or the
                                 // ShapeHit::part of an analytic shape
  float u = 0, v = 0;            // triangle barycentrics: p = (1-u-v) p0 + u p1 + v p2
};

// What a backend's structure looks like, for `glint bench-accel` and the benchmarks. Fields a
// backend cannot know (Embree's internal BVH) stay 0.
struct AccelStats {
  uint64_t bytes = 0;  // nodes + leaf primitive lists (Embree: 0, not exposed)
  uint64_t nodes = 0;  // all nodes, interior and leaf
  uint64_t leaves = 0;
  uint64_t emptyLeaves = 0;
  uint32_t maxDepth = 0;
  double meanPrimsPerLeaf = 0;  // over non-empty leaves
  double sahCost = 0;           // expected cost of a random ray, the build's cost model
};

class Accelerator {
 public:
  virtual ~Accelerator() = default;
  virtual std::string name() const = 0;
  // Structure statistics (see AccelStats).
  virtual AccelStats stats() const { return {}; }
  // Finds the closest hit with t in [ray.tMin, ray.tMax]; false when there is none.
  virtual bool closestHit(const Ray& ray, Hit* hit) const = 0;
  // True when anything is hit with t in [ray.tMin, ray.tMax] (shadow rays).
  virtual bool anyHit(const Ray& ray) const = 0;

  // The closest hits of `count` rays that travel together (one pixel's camera samples):
  // hits[i].instance == Hit::kInvalid where ray i hits nothing. Every hits[i] is overwritten
  // whole (callers reuse the array). A backend may trace them as a
  // packet; its answers then equal closestHit's up to the floating-point rounding of its packet
  // kernel (Embree's differ in the last bits of t or u, v for about 1 hit in 2,000). The
  // default traces them one by one.
  virtual void closestHits(const Ray* rays, Hit* hits, int count) const {
    for (int i = 0; i < count; ++i)
      if (!closestHit(rays[i], &hits[i])) hits[i] = Hit{};
  }
};

// Hits far along their rays. Traversal finds a closest hit with a t rounded at the scale of the
// ray's origin and length (a float step of t at 1e4 is 1e-3, and Embree's triangle test is
// good to a few of them): of two faces closer together than that, a 4e-5 wall seen from 1e4
// units away, either may come first, and the wall's back face shaded from the front shows as a
// hole. A hit farther along its ray than kFarHit times its own largest coordinate is therefore
// found again on a short stretch of the same line around it, traced from an origin moved there
// in double, so that the faces' order is resolved at the float grid of the hit point. Rays
// from near their hits (all but camera rays from far away, and rays towards the world origin)
// never pay for it. Backends call refineFarHit on each closest hit they found.
constexpr float kFarHit = 64;

// The stretch of `ray`'s line to trace again around a hit at t, and the t offset of its
// origin; nothing when the hit is not far along its ray.
struct FarHitStretch {
  Ray ray;
  float shift = 0;
};
std::optional<FarHitStretch> farHitStretch(const Ray& ray, float t);

// Replaces *hit by the closest hit `trace` (a backend's unrefined closest-hit query) finds on
// the stretch, when the hit is far along its ray and the stretch has one.
template <class Trace>
void refineFarHit(const Ray& ray, Hit* hit, Trace&& trace) {
  const std::optional<FarHitStretch> stretch = farHitStretch(ray, hit->t);
  if (!stretch) return;
  Hit near;
  if (!trace(stretch->ray, &near)) return;  // the line moved off a silhouette: keep the first
  near.t += stretch->shift;
  if (near.t <= ray.tMax) *hit = near;
}

// Builds the backend called `name` over `scene`, which must outlive the accelerator.
// Throws InputError (geometry/error.h) for an unknown name and std::runtime_error if the build
// fails.
std::unique_ptr<Accelerator> makeAccelerator(const std::string& name, const GeometryScene& scene);

// The names makeAccelerator accepts.
std::vector<std::string> acceleratorNames();

}  // namespace glint
