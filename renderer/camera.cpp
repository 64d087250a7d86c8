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

}  // namespace glint
