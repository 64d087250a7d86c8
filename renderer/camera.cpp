// glint — pinhole, orthographic and thin-lens cameras, static or moving.
#include "renderer/camera.h"

#include <cassert>
#include <cmath>
#include <string>

#include "geometry/error.h"
#include "geometry/sampling.h"

namespace glint {

Camera Camera::perspective(const AnimatedTransform& worldFromCamera, float yfov, int width,
                           int height, float znear, float zfar) {
  Camera c;
  c.projection_ = Projection::Perspective;
  c.halfHeight_ = std::tan(yfov / 2);
  c.halfWidth_ = c.halfHeight_ * float(width) / float(height);
  c.setCommon(worldFromCamera, width, height, znear, zfar);
  return c;
}

Camera Camera::orthographic(const AnimatedTransform& worldFromCamera, float ymag, int width,
                            int height, float znear, float zfar) {
  Camera c;
  c.projection_ = Projection::Orthographic;
  c.halfHeight_ = ymag;
  c.halfWidth_ = ymag * float(width) / float(height);
  c.setCommon(worldFromCamera, width, height, znear, zfar);
  return c;
}

void Camera::setCommon(const AnimatedTransform& worldFromCamera, int width, int height, float znear,
                       float zfar) {
  worldFromCamera_ = worldFromCamera;
  worldFromCamera0_ = worldFromCamera.at(0);
  moving_ = worldFromCamera.isAnimated();
  pinhole_ = !moving_ && !hasLens();
  width_ = width, height_ = height;
  znear_ = znear, zfar_ = zfar;
  filmToScreenX_ = 2.0f / float(width), filmToScreenY_ = 2.0f / float(height);
  origin_ = worldFromCamera0_.point({0, 0, 0});
  forward_ = normalize(worldFromCamera0_.vector({0, 0, -1}));
}

void Camera::setLens(const ThinLens& lens) {
  if (!(lens.radius >= 0) || !std::isfinite(lens.radius))
    throw InputError("thin lens: aperture radius must be finite and >= 0, got " +
                     std::to_string(lens.radius));
  if (lens.radius > 0 && (!(lens.focusDistance > 0) || !std::isfinite(lens.focusDistance)))
    throw InputError("thin lens: focus distance must be finite and > 0, got " +
                     std::to_string(lens.focusDistance));
  if (lens.blades != 0 && lens.blades < 3)
    throw InputError("thin lens: a polygonal aperture needs >= 3 blades, got " +
                     std::to_string(lens.blades));
  if (!std::isfinite(lens.rotation))
    throw InputError("thin lens: aperture rotation must be finite");
  lens_ = lens;
  pinhole_ = !moving_ && !hasLens();
  // ThinLens::rotation 0 means a vertex straight up.
  lensAngle0_ = kPi / 2 + lens.rotation;
}

// What a batch of perspective pinhole rays needs from the camera.
struct PinholeBatch {
  const std::array<std::array<float, 4>, 4>* worldFromCamera;
  Vec3f origin;
  float filmToScreenX, filmToScreenY, halfWidth, halfHeight, znear, zfar;
};

void pinholeRayBatch(const PinholeBatch& c, const float* filmX, const float* filmY, int n,
                     Ray* out);

// Structure of arrays, then one plain loop per step, so the square roots and divisions run
// 8 (AVX2) or 4 (SSE) rays at a time; the expressions are pinholeRayAt's, so the rays are too.
// A free function: Clang does not multiversion member functions (target_clones).
__attribute__((target_clones("avx2", "default"))) void pinholeRayBatch(const PinholeBatch& c,
                                                                       const float* filmX,
                                                                       const float* filmY, int n,
                                                                       Ray* out) {
  const auto& m = *c.worldFromCamera;
  constexpr int kMax = Camera::kMaxRayBatch;
  float dx[kMax], dy[kMax], dz[kMax], len[kMax];
  for (int i = 0; i < n; ++i) {
    const float sx = (filmX[i] * c.filmToScreenX - 1) * c.halfWidth;
    const float sy = (1 - filmY[i] * c.filmToScreenY) * c.halfHeight;
    dx[i] = m[0][0] * sx + m[0][1] * sy + m[0][2] * -1.0f;
    dy[i] = m[1][0] * sx + m[1][1] * sy + m[1][2] * -1.0f;
    dz[i] = m[2][0] * sx + m[2][1] * sy + m[2][2] * -1.0f;
  }
  for (int i = 0; i < n; ++i) len[i] = std::sqrt(dx[i] * dx[i] + dy[i] * dy[i] + dz[i] * dz[i]);
  for (int i = 0; i < n; ++i) dx[i] /= len[i], dy[i] /= len[i], dz[i] /= len[i];
  const bool finiteFar = !std::isinf(c.zfar);
  for (int i = 0; i < n; ++i) {
    Ray& r = out[i];
    r.o = c.origin;
    r.d = {dx[i], dy[i], dz[i]};
    r.tMin = c.znear * len[i];
    r.tMax = finiteFar ? c.zfar * len[i] : kInfinity;
    r.time = 0;
  }
}

void Camera::pinholeRays(const float* filmX, const float* filmY, int n, Ray* out) const {
  assert(pinhole_ && n <= kMaxRayBatch);
  // Fewer rays than one AVX2 vector (4 spp and below) go one at a time, inline: the vector
  // clone's loops would all run their scalar remainders through arrays on the stack, which
  // cost features_bench's 4-spp renders about 2% of their time against the inline path.
  if (projection_ != Projection::Perspective || n < 8) {
    for (int i = 0; i < n; ++i) out[i] = pinholeRay({filmX[i], filmY[i]}, 0.0f);
    return;
  }
  const PinholeBatch batch{&worldFromCamera0_.matrix().m,
                           origin_,
                           filmToScreenX_,
                           filmToScreenY_,
                           halfWidth_,
                           halfHeight_,
                           znear_,
                           zfar_};
  pinholeRayBatch(batch, filmX, filmY, n, out);
}

Ray Camera::lensOrMotionRay(const CameraSample& s) const {
  // The placement at the ray's time, computed as the static camera computes its own, so a
  // moving camera's ray equals the ray of a static camera placed where it is at that time.
  Transform xf = worldFromCamera0_;
  Vec3f origin = origin_, forward = forward_;
  if (moving_) {
    xf = worldFromCamera_.at(s.time);
    origin = xf.point({0, 0, 0});
    forward = normalize(xf.vector({0, 0, -1}));
  }
  if (!(lens_.radius > 0)) return pinholeRayAt(xf, origin, forward, s.pFilm, s.time);
  // Every ray of a film point passes through that point's image on the focus plane (depth f):
  // where the pinhole ray crosses it (perspective), or the film point pushed to depth f
  // (orthographic).
  const bool perspective = projection_ == Projection::Perspective;
  const float sx = (s.pFilm.x * filmToScreenX_ - 1) * halfWidth_;
  const float sy = (1 - s.pFilm.y * filmToScreenY_) * halfHeight_;
  const float f = lens_.focusDistance;
  Vec2f l = (lens_.blades >= 3 ? sampleRegularPolygon(s.pLens, lens_.blades, lensAngle0_)
                               : sampleConcentricDisk(s.pLens)) *
            lens_.radius;
  Vec3f pFocus = perspective ? Vec3f{sx * f, sy * f, -f} : Vec3f{sx, sy, -f};
  Vec3f pLens = perspective ? Vec3f{l.x, l.y, 0} : Vec3f{sx + l.x, sy + l.y, 0};
  // The camera-space direction spans depth f; its world length converts view depths to
  // distances along the unit ray.
  Vec3f d = xf.vector(pFocus - pLens);
  float len = length(d);
  Ray r;
  r.time = s.time;
  r.o = xf.point(pLens);
  r.d = d / len;
  r.tMin = znear_ * len / f;
  r.tMax = std::isinf(zfar_) ? kInfinity : zfar_ * len / f;
  return r;
}

}  // namespace glint
