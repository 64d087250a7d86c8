// glint — pinhole and orthographic cameras.
#include "renderer/camera.h"

#include <cmath>

namespace glint {

Camera Camera::perspective(const Transform& worldFromCamera, float yfov, int width, int height,
                           float znear, float zfar) {
  Camera c;
  c.projection_ = Projection::Perspective;
  c.worldFromCamera_ = worldFromCamera;
  c.width_ = width, c.height_ = height;
  c.halfHeight_ = std::tan(yfov / 2);
  c.halfWidth_ = c.halfHeight_ * float(width) / float(height);
  c.znear_ = znear, c.zfar_ = zfar;
  c.filmToScreenX_ = 2.0f / float(width), c.filmToScreenY_ = 2.0f / float(height);
  c.origin_ = worldFromCamera.point({0, 0, 0});
  c.forward_ = normalize(worldFromCamera.vector({0, 0, -1}));
  return c;
}

Camera Camera::orthographic(const Transform& worldFromCamera, float ymag, int width, int height,
                            float znear, float zfar) {
  Camera c;
  c.projection_ = Projection::Orthographic;
  c.worldFromCamera_ = worldFromCamera;
  c.width_ = width, c.height_ = height;
  c.halfHeight_ = ymag;
  c.halfWidth_ = ymag * float(width) / float(height);
  c.znear_ = znear, c.zfar_ = zfar;
  c.filmToScreenX_ = 2.0f / float(width), c.filmToScreenY_ = 2.0f / float(height);
  c.origin_ = worldFromCamera.point({0, 0, 0});
  c.forward_ = normalize(worldFromCamera.vector({0, 0, -1}));
  return c;
}

Ray Camera::generateRay(Vec2f pFilm, float time) const {
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
