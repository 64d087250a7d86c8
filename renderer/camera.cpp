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
  return c;
}

Ray Camera::generateRay(Vec2f pFilm, float time) const {
  float sx = (2 * pFilm.x / float(width_) - 1) * halfWidth_;
  float sy = (1 - 2 * pFilm.y / float(height_)) * halfHeight_;
  Ray r;
  r.time = time;
  if (projection_ == Projection::Perspective) {
    Vec3f d = normalize(Vec3f{sx, sy, -1});
    float invDepth = 1 / -d.z;  // distance along the ray per unit of view depth
    r.o = worldFromCamera_.point({0, 0, 0});
    r.d = normalize(worldFromCamera_.vector(d));
    // Any scale in the camera transform is removed by normalizing; depths are in world units.
    r.tMin = znear_ * invDepth;
    r.tMax = std::isinf(zfar_) ? kInfinity : zfar_ * invDepth;
  } else {
    r.o = worldFromCamera_.point({sx, sy, 0});
    r.d = normalize(worldFromCamera_.vector({0, 0, -1}));
    r.tMin = znear_;
    r.tMax = zfar_;
  }
  return r;
}

}  // namespace glint
