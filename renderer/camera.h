// glint — cameras: generate the ray through a point on the film.
//
// Camera space follows glTF: the camera looks down -Z with +Y up and +X right. Film
// coordinates are continuous pixels with (0,0) at the top-left corner of the image.
#pragma once

#include <cmath>

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

class Camera {
 public:
  enum class Projection { Perspective, Orthographic };

  // yfov in radians; the horizontal extent follows the image aspect (no stretching).
  static Camera perspective(const Transform& worldFromCamera, float yfov, int width, int height,
                            float znear, float zfar);
  // ymag = half the film height in world units; the width follows the image aspect.
  static Camera orthographic(const Transform& worldFromCamera, float ymag, int width, int height,
                             float znear, float zfar);

  // The world-space ray through film point `pFilm` at `time`, clipped to [znear, zfar] along
  // the view axis. Perspective rays have unit directions. Inline: runs once per camera sample.
  Ray generateRay(Vec2f pFilm, float time) const;

  Projection projection() const { return projection_; }
  Vec3f position() const { return origin_; }
  Vec3f forward() const { return forward_; }
  const Transform& worldFromCamera() const { return worldFromCamera_; }
  int width() const { return width_; }
  int height() const { return height_; }
  // The cone of one pixel's camera rays (a pinhole's spread, an orthographic pixel's width).
  RayCone pixelCone() const {
    const float pixel = 2 * halfHeight_ / float(height_);
    return projection_ == Projection::Perspective ? RayCone{0, pixel} : RayCone{pixel, 0};
  }

 private:
  Projection projection_ = Projection::Perspective;
  Transform worldFromCamera_;
  int width_ = 0, height_ = 0;
  float halfHeight_ = 1, halfWidth_ = 1;  // film half extents at distance 1 (or world, ortho)
  float znear_ = 0, zfar_ = kInfinity;
  float filmToScreenX_ = 1, filmToScreenY_ = 1;  // 2 / width, 2 / height
  Vec3f origin_, forward_{0, 0, -1};             // world-space eye point and view direction
};

inline Ray Camera::generateRay(Vec2f pFilm, float time) const {
  float sx = (pFilm.x * filmToScreenX_ - 1) * halfWidth_;
  float sy = (1 - pFilm.y * filmToScreenY_) * halfHeight_;
  Ray r;
  r.time = time;
  if (projection_ == Projection::Perspective) {
    // The direction through the film point at view depth 1; its world length converts view
    // depth to distance along the unit ray (znear/zfar are depths in camera space).
    Vec3f d = worldFromCamera_.vector({sx, sy, -1});
    float len = length(d);
    r.o = origin_;
    r.d = d / len;
    r.tMin = znear_ * len;
    r.tMax = std::isinf(zfar_) ? kInfinity : zfar_ * len;
  } else {
    r.o = worldFromCamera_.point({sx, sy, 0});
    r.d = forward_;
    r.tMin = znear_;
    r.tMax = zfar_;
  }
  return r;
}

}  // namespace glint
