// glint — cameras: generate the ray through a point on the film, a point on the lens, at a time.
//
// Camera space follows glTF: the camera looks down -Z with +Y up and +X right. Film
// coordinates are continuous pixels with (0,0) at the top-left corner of the image.
//
// For the scene builder:
//   Camera c = Camera::perspective(worldFromCamera, yfov, width, height, znear, zfar);
//   Camera c = Camera::orthographic(worldFromCamera, ymag, width, height, znear, zfar);
//   c.setLens(ThinLens{radius, focusDistance, blades, rotation});  // depth of field only
// with worldFromCamera an AnimatedTransform (a Transform when static). Set Feature::Lens when
// c.hasLens() and Feature::MotionBlur when anything moves, the camera included: the render loop
// samples time only under MotionBlur, so without it a moving camera stays where it is at
// shutter open.
#pragma once

#include <cassert>
#include <cmath>

#include "geometry/motion.h"
#include "geometry/ray.h"

namespace glint {

// A cone around a ray that covers one pixel (Akenine-Möller et al. 2019, "Texture Level of
// Detail Strategies for Real-Time Ray Tracing"): width at the ray origin plus spread angle.
// Texture filtering and bump-map steps read the pixel footprint from it at each hit; mirror
// and glass bounces carry the cone on, widened by the distance travelled.
struct RayCone {
  float width = 0;   // world-space width at the ray's origin
  float spread = 0;  // radians per unit distance

  float widthAt(float distance) const { return width + spread * distance; }
};

// A thin lens in front of the film. Lengths are in camera-space units, which are world units
// for the rigid placements glTF and the sidecar give cameras.
struct ThinLens {
  float radius = 0;         // aperture radius; 0 = pinhole (exactly the pinhole rays)
  float focusDistance = 0;  // depth of the plane in focus along the view axis; > 0 with a lens
  int blades = 0;           // 0 = round aperture; >= 3 = regular polygon (bokeh shape)
  // Polygon orientation in radians: 0 puts a vertex straight up (+Y); positive turns
  // counter-clockwise as the bokeh of a point behind the focus plane appears on the image.
  float rotation = 0;
};

// What one camera ray is made of: uniform samples that the camera warps itself.
struct CameraSample {
  Vec2f pFilm;              // continuous pixel coordinates
  Vec2f pLens{0.5f, 0.5f};  // in [0,1)^2, warped onto the aperture; (0.5, 0.5) is its centre
  float time = 0;           // normalised shutter time in [0,1]: 0 = open, 1 = close
};

class Camera {
 public:
  enum class Projection { Perspective, Orthographic };

  // yfov in radians; the horizontal extent follows the image aspect (no stretching). A moving
  // placement (worldFromCamera.isAnimated()) is evaluated at each ray's time; a static one is
  // evaluated once here.
  static Camera perspective(const AnimatedTransform& worldFromCamera, float yfov, int width,
                            int height, float znear, float zfar);
  static Camera perspective(const Transform& worldFromCamera, float yfov, int width, int height,
                            float znear, float zfar) {
    return perspective(AnimatedTransform(worldFromCamera), yfov, width, height, znear, zfar);
  }
  // ymag = half the film height in world units; the width follows the image aspect.
  static Camera orthographic(const AnimatedTransform& worldFromCamera, float ymag, int width,
                             int height, float znear, float zfar);
  static Camera orthographic(const Transform& worldFromCamera, float ymag, int width, int height,
                             float znear, float zfar) {
    return orthographic(AnimatedTransform(worldFromCamera), ymag, width, height, znear, zfar);
  }

  // Adds (or, with radius 0, removes) a thin lens; both projections take one. Throws InputError
  // for a negative or non-finite radius, a focus distance that is not positive and finite while
  // radius > 0, or 1-2 blades: the scene builder validates first.
  void setLens(const ThinLens& lens);
  const ThinLens& lens() const { return lens_; }
  bool hasLens() const { return lens_.radius > 0; }
  bool isMoving() const { return moving_; }

  // The world-space ray of `sample`, clipped to [znear, zfar] along the view axis (depths
  // measured from the lens plane). Perspective and lens rays have unit directions. Without a
  // lens the lens sample is ignored and the ray is the pinhole ray bit for bit; a static camera
  // ignores the time except to stamp it on the ray. Inline for a static pinhole (once per camera
  // sample); a lens or a moving placement goes out of line.
  Ray generateRay(const CameraSample& sample) const;
  // The ray through the centre of the lens.
  Ray generateRay(Vec2f pFilm, float time) const;
  // True for a static camera without a lens: then pinholeRay() is generateRay() without its
  // one test, for loops that decide once per image (the render loop's plain path).
  bool isStaticPinhole() const { return pinhole_; }
  [[gnu::always_inline]] Ray pinholeRay(Vec2f pFilm, float time) const;
  // pinholeRay at time 0 for n <= kMaxRayBatch film points (filmX[i], filmY[i]), written lane
  // by lane so the compiler computes the rays' lengths several at a time: one square root and
  // one division per ray, in sequence, were a fifth of the render loop's own time on the
  // cheapest scenes. The same rays as pinholeRay, bit for bit (tested); fewer than 8 are made
  // one at a time.
  static constexpr int kMaxRayBatch = 16;
  void pinholeRays(const float* filmX, const float* filmY, int n, Ray* out) const;

  Projection projection() const { return projection_; }
  // Placement at shutter open (time 0).
  Vec3f position() const { return origin_; }
  Vec3f forward() const { return forward_; }
  const Transform& worldFromCamera() const { return worldFromCamera0_; }
  const AnimatedTransform& animatedWorldFromCamera() const { return worldFromCamera_; }
  int width() const { return width_; }
  int height() const { return height_; }
  // The cone of one pixel's camera rays (a pinhole's spread, an orthographic pixel's width).
  // With a lens it is unchanged: for one lens point, the rays through a pixel form exactly
  // this cone with its apex on the lens (perspective) or this pixel-wide beam (orthographic).
  // The defocus blur itself comes from averaging over lens samples; widening the cone by the
  // circle of confusion as well would filter textures twice.
  RayCone pixelCone() const {
    const float pixel = 2 * halfHeight_ / float(height_);
    return projection_ == Projection::Perspective ? RayCone{0, pixel} : RayCone{pixel, 0};
  }

 private:
  void setCommon(const AnimatedTransform& worldFromCamera, int width, int height, float znear,
                 float zfar);
  // The pinhole (or orthographic) ray for the placement xf, whose eye and view direction
  // are `origin` and `forward`.
  // Always inlined: it runs once per camera sample on the plain path.
  [[gnu::always_inline]] Ray pinholeRayAt(const Transform& xf, Vec3f origin, Vec3f forward,
                                          Vec2f pFilm, float time) const;
  // Everything else, out of line: a lens, a moving placement or both.
  Ray lensOrMotionRay(const CameraSample& s) const;

  Projection projection_ = Projection::Perspective;
  AnimatedTransform worldFromCamera_;
  Transform worldFromCamera0_;  // at time 0; the only one used when static
  bool moving_ = false;
  bool pinhole_ = true;  // static and without a lens: the inline fast path
  int width_ = 0, height_ = 0;
  float halfHeight_ = 1, halfWidth_ = 1;  // film half extents at distance 1 (or world, ortho)
  float znear_ = 0, zfar_ = kInfinity;
  float filmToScreenX_ = 1, filmToScreenY_ = 1;  // 2 / width, 2 / height
  Vec3f origin_, forward_{0, 0, -1};             // world-space eye point and view direction
  ThinLens lens_;
  float lensAngle0_ = 0;  // angle of the aperture polygon's first vertex from +X
};

inline Ray Camera::pinholeRayAt(const Transform& xf, Vec3f origin, Vec3f forward, Vec2f pFilm,
                                float time) const {
  float sx = (pFilm.x * filmToScreenX_ - 1) * halfWidth_;
  float sy = (1 - pFilm.y * filmToScreenY_) * halfHeight_;
  Ray r;
  r.time = time;
  if (projection_ == Projection::Perspective) {
    // The direction through the film point at view depth 1; its world length converts view
    // depth to distance along the unit ray (znear/zfar are depths in camera space).
    Vec3f d = xf.vector({sx, sy, -1});
    float len = length(d);
    r.o = origin;
    r.d = d / len;
    r.tMin = znear_ * len;
    r.tMax = std::isinf(zfar_) ? kInfinity : zfar_ * len;
  } else {
    r.o = xf.point({sx, sy, 0});
    r.d = forward;
    r.tMin = znear_;
    r.tMax = zfar_;
  }
  return r;
}

inline Ray Camera::pinholeRay(Vec2f pFilm, float time) const {
  assert(pinhole_);
  return pinholeRayAt(worldFromCamera0_, origin_, forward_, pFilm, time);
}

inline Ray Camera::generateRay(const CameraSample& s) const {
  if (pinhole_) return pinholeRay(s.pFilm, s.time);
  return lensOrMotionRay(s);
}

inline Ray Camera::generateRay(Vec2f pFilm, float time) const {
  if (pinhole_) return pinholeRay(pFilm, time);
  return lensOrMotionRay({pFilm, {0.5f, 0.5f}, time});
}

}  // namespace glint
