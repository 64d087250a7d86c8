// glint — keyframe tracks and the node hierarchy, evaluated at any time.
#include "scenes/animation.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

namespace glint {

namespace {

// ---------------------------------------------------------------------------------------------
// Value types as vector spaces (quaternions as 4-vectors; callers renormalise)
// ---------------------------------------------------------------------------------------------

float weighted(const std::array<float, 4>& w, const std::array<float, 4>& v) {
  return w[0] * v[0] + w[1] * v[1] + w[2] * v[2] + w[3] * v[3];
}

template <class T>
struct Ops;

template <>
struct Ops<float> {
  static float sum(const std::array<float, 4>& w, const std::array<float, 4>& v) {
    return weighted(w, v);
  }
  static float lerp(float a, float b, float s) { return a + s * (b - a); }
  static float finish(float v) { return v; }
};

template <>
struct Ops<Vec2f> {
  static Vec2f sum(const std::array<float, 4>& w, const std::array<Vec2f, 4>& v) {
    return {weighted(w, {v[0].x, v[1].x, v[2].x, v[3].x}),
            weighted(w, {v[0].y, v[1].y, v[2].y, v[3].y})};
  }
  static Vec2f lerp(Vec2f a, Vec2f b, float s) { return a + (b - a) * s; }
  static Vec2f finish(Vec2f v) { return v; }
};

template <>
struct Ops<Vec3f> {
  static Vec3f sum(const std::array<float, 4>& w, const std::array<Vec3f, 4>& v) {
    return {weighted(w, {v[0].x, v[1].x, v[2].x, v[3].x}),
            weighted(w, {v[0].y, v[1].y, v[2].y, v[3].y}),
            weighted(w, {v[0].z, v[1].z, v[2].z, v[3].z})};
  }
  static Vec3f lerp(Vec3f a, Vec3f b, float s) { return a + (b - a) * s; }
  static Vec3f finish(Vec3f v) { return v; }
};

template <>
struct Ops<Quaternion> {
  static Quaternion sum(const std::array<float, 4>& w, const std::array<Quaternion, 4>& v) {
    return {weighted(w, {v[0].x, v[1].x, v[2].x, v[3].x}),
            weighted(w, {v[0].y, v[1].y, v[2].y, v[3].y}),
            weighted(w, {v[0].z, v[1].z, v[2].z, v[3].z}),
            weighted(w, {v[0].w, v[1].w, v[2].w, v[3].w})};
  }
  static Quaternion lerp(const Quaternion& a, const Quaternion& b, float s) {
    return slerp(a, b, s);
  }
  static Quaternion finish(const Quaternion& q) { return normalize(q); }
};

Quaternion negated(const Quaternion& q) { return {-q.x, -q.y, -q.z, -q.w}; }

// q or -q, whichever lies in the hemisphere of `reference` (both are the same rotation).
template <class T>
T alignedTo(const T& q, const T&) {
  return q;
}
template <>
Quaternion alignedTo(const Quaternion& q, const Quaternion& reference) {
  return dot(q, reference) < 0 ? negated(q) : q;
}

// Cubic Hermite basis on s in [0, 1]: weights of p0, m0·td, p1, m1·td.
std::array<float, 4> hermite(double s) {
  double s2 = s * s, s3 = s2 * s;
  return {float(2 * s3 - 3 * s2 + 1), float(s3 - 2 * s2 + s), float(-2 * s3 + 3 * s2),
          float(s3 - s2)};
}

template <class T>
T evaluateTrack(const Track<T>& track, double time) {
  using O = Ops<T>;
  const size_t n = track.times.size();
  assert(n > 0);
  const bool cubic = track.interpolation == Interpolation::CubicSpline;
  assert(track.values.size() == (cubic ? 3 * n : n));
  // The value of key k (CubicSpline stores in-tangent, value, out-tangent per key).
  auto value = [&](size_t k) -> const T& { return track.values[cubic ? 3 * k + 1 : k]; };

  if (n == 1 || time <= double(track.times.front())) return value(0);
  if (time >= double(track.times.back())) return value(n - 1);
  // Segment k: times[k] <= time < times[k + 1].
  size_t k = size_t(std::upper_bound(track.times.begin(), track.times.end(), time,
                                     [](double t, float key) { return t < double(key); }) -
                    track.times.begin()) -
             1;
  double t0 = track.times[k], t1 = track.times[k + 1];
  double td = t1 - t0;
  double s = (time - t0) / td;
  // Exactly on a key: that key's value, bit for bit.
  if (s <= 0) return value(k);

  switch (track.interpolation) {
    case Interpolation::Step:
      return value(k);
    case Interpolation::Linear:
      return O::lerp(value(k), value(k + 1), float(s));
    case Interpolation::CubicSpline: {
      // glTF 2.0, Appendix C: p(s) = h00 v_k + h10 td b_k + h01 v_k+1 + h11 td a_k+1, with b_k
      // the out-tangent of key k and a_k+1 the in-tangent of key k + 1.
      std::array<float, 4> w = hermite(s);
      w[1] *= float(td), w[3] *= float(td);
      return O::finish(O::sum(w, {track.values[3 * k + 1], track.values[3 * k + 2],
                                  track.values[3 * (k + 1) + 1], track.values[3 * (k + 1)]}));
    }
    case Interpolation::Smooth: {
      // Catmull-Rom for uneven key spacing: the tangent at a key is the slope between its
      // neighbours ((v_k+1 - v_k-1) / (t_k+1 - t_k-1)), one-sided at the first and last key.
      // Each neighbour is moved into the hemisphere of the one before it (quaternions).
      T p1 = value(k);
      T p2 = alignedTo(value(k + 1), p1);
      T p0 = k > 0 ? alignedTo(value(k - 1), p1) : p1;
      T p3 = k + 2 < n ? alignedTo(value(k + 2), p2) : p2;
      double tPrev = k > 0 ? track.times[k - 1] : t0;
      double tNext = k + 2 < n ? track.times[k + 2] : t1;
      // Tangents times td, as Hermite weights: m1·td = (p2 - p0)·td / (t1 - tPrev).
      float a = float(td / (t1 - tPrev)), b = float(td / (tNext - t0));
      std::array<float, 4> w = hermite(s);
      // p(s) = h00 p1 + h10 a (p2 - p0) + h01 p2 + h11 b (p3 - p1)
      std::array<float, 4> weights = {-w[1] * a, w[0] - w[3] * b, w[1] * a + w[2], w[3] * b};
      return O::finish(O::sum(weights, {p0, p1, p2, p3}));
    }
  }
  return value(k);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Tracks
// ---------------------------------------------------------------------------------------------

float evaluate(const Track<float>& track, double time) { return evaluateTrack(track, time); }
Vec2f evaluate(const Track<Vec2f>& track, double time) { return evaluateTrack(track, time); }
Vec3f evaluate(const Track<Vec3f>& track, double time) { return evaluateTrack(track, time); }
Quaternion evaluate(const Track<Quaternion>& track, double time) {
  return evaluateTrack(track, time);
}

const char* interpolationName(Interpolation interpolation) {
  switch (interpolation) {
    case Interpolation::Step:
      return "step";
    case Interpolation::Linear:
      return "linear";
    case Interpolation::CubicSpline:
      return "cubicspline";
    case Interpolation::Smooth:
      return "smooth";
  }
  return "linear";
}

// ---------------------------------------------------------------------------------------------
// Nodes
// ---------------------------------------------------------------------------------------------

Transform NodeDesc::localAt(double time) const {
  if (hasMatrix) return matrix;
  Vec3f t = translationTrack.empty() ? translation : evaluate(translationTrack, time);
  Vec3f s = scaleTrack.empty() ? scale : evaluate(scaleTrack, time);
  Transform r;
  if (!angleTrack.empty())
    r = Transform::rotate(evaluate(angleTrack, time), rotationAxis);
  else
    r = toTransform(rotationTrack.empty() ? rotation : evaluate(rotationTrack, time));
  return Transform::translate(t) * r * Transform::scale(s);
}

bool isAnimated(const std::vector<NodeDesc>& nodes, int node) {
  // Loaders build forests; the step limit only guards against a corrupt parent chain.
  for (size_t steps = 0; node >= 0 && steps <= nodes.size(); ++steps) {
    assert(size_t(node) < nodes.size());
    if (nodes[size_t(node)].hasTracks()) return true;
    node = nodes[size_t(node)].parent;
  }
  return false;
}

Transform worldFromNode(const std::vector<NodeDesc>& nodes, int node, double time) {
  Transform world;
  for (size_t steps = 0; node >= 0 && steps <= nodes.size(); ++steps) {
    assert(size_t(node) < nodes.size());
    world = nodes[size_t(node)].localAt(time) * world;
    node = nodes[size_t(node)].parent;
  }
  return world;
}

std::pair<double, double> animationRange(const std::vector<NodeDesc>& nodes) {
  double lo = kInfinity, hi = -kInfinity;
  auto add = [&](const auto& track) {
    if (track.empty()) return;
    lo = std::min(lo, double(track.startTime()));
    hi = std::max(hi, double(track.endTime()));
  };
  for (const NodeDesc& n : nodes) {
    add(n.translationTrack);
    add(n.rotationTrack);
    add(n.scaleTrack);
    add(n.angleTrack);
  }
  if (lo > hi) return {0.0, 0.0};
  return {lo, hi};
}

}  // namespace glint
