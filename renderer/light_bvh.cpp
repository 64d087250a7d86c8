// glint — the light BVH sampler.
#include "renderer/light_bvh.h"

#include <algorithm>
#include <cmath>

namespace glint {

namespace {

float safeSqrt(float x) { return std::sqrt(std::max(0.0f, x)); }
// cos(max(0, a - b)) and sin(max(0, a - b)) from the sines and cosines of a and b.
float cosSubClamped(float sinA, float cosA, float sinB, float cosB) {
  return cosA > cosB ? 1.0f : cosA * cosB + sinA * sinB;
}
float sinSubClamped(float sinA, float cosA, float sinB, float cosB) {
  return cosA > cosB ? 0.0f : sinA * cosB - cosA * sinB;
}
// Rodrigues' rotation of v about the unit axis k by angle theta.
Vec3f rotate(Vec3f v, Vec3f k, float theta) {
  const float c = std::cos(theta), s = std::sin(theta);
  return v * c + cross(k, v) * s + k * (dot(k, v) * (1 - c));
}

}  // namespace

LightBounds unionOf(const LightBounds& a, const LightBounds& b) {
  if (!(a.phi > 0)) return b;
  if (!(b.phi > 0)) return a;
  LightBounds u;
  u.bounds = a.bounds;
  u.bounds.extend(b.bounds);
  u.phi = a.phi + b.phi;
  u.cosThetaE = std::min(a.cosThetaE, b.cosThetaE);
  u.twoSided = a.twoSided || b.twoSided;
  // The cone of normals holding both cones.
  const float thetaA = std::acos(std::clamp(a.cosThetaO, -1.0f, 1.0f));
  const float thetaB = std::acos(std::clamp(b.cosThetaO, -1.0f, 1.0f));
  const float thetaD = std::acos(std::clamp(dot(a.w, b.w), -1.0f, 1.0f));
  if (std::min(thetaD + thetaB, kPi) <= thetaA) {
    u.w = a.w, u.cosThetaO = a.cosThetaO;
  } else if (std::min(thetaD + thetaA, kPi) <= thetaB) {
    u.w = b.w, u.cosThetaO = b.cosThetaO;
  } else {
    const float thetaO = (thetaA + thetaD + thetaB) / 2;
    const Vec3f axis = cross(a.w, b.w);
    if (thetaO >= kPi || !(lengthSquared(axis) > 0)) {
      u.w = a.w, u.cosThetaO = -1;
    } else {
      u.w = normalize(rotate(a.w, normalize(axis), thetaO - thetaA));
      u.cosThetaO = std::cos(thetaO);
    }
  }
  return u;
}

float lightBoundsImportance(const LightBounds& b, const LightSampleContext& ctx) {
  const Vec3f pc = b.bounds.center();
  float d2 = lengthSquared(ctx.p - pc);
  // Not closer than half the box's size: inside or near the box every light may be close.
  d2 = std::max(d2, length(b.bounds.diagonal()) / 2);
  if (!(d2 > 0)) return b.phi > 0 ? 1e30f : 0.0f;  // a point light at the point itself
  const Vec3f wi = normalize(ctx.p - pc);
  float cosW = dot(b.w, wi);
  if (b.twoSided) cosW = std::abs(cosW);
  const float sinW = safeSqrt(1 - cosW * cosW);
  // The angle the box subtends from the point.
  float cosB = -1;
  const float r2 = lengthSquared(b.bounds.diagonal()) / 4;
  const float dc2 = lengthSquared(ctx.p - pc);
  if (dc2 > r2) cosB = safeSqrt(1 - r2 / dc2);
  const float sinB = safeSqrt(1 - cosB * cosB);
  const float sinO = safeSqrt(1 - b.cosThetaO * b.cosThetaO);
  const float cosX = cosSubClamped(sinW, cosW, sinO, b.cosThetaO);
  const float sinX = sinSubClamped(sinW, cosW, sinO, b.cosThetaO);
  const float cosP = cosSubClamped(sinX, cosX, sinB, cosB);
  if (cosP <= b.cosThetaE) return 0;
  float importance = b.phi * cosP / d2;
  if (ctx.onSurface()) {
    const float cosI = std::abs(dot(wi, ctx.n));
    const float sinI = safeSqrt(1 - cosI * cosI);
    importance *= cosSubClamped(sinI, cosI, sinB, cosB);
  }
  return std::max(importance, 0.0f);
}

BvhLightSampler::BvhLightSampler(const std::vector<std::unique_ptr<Light>>& lights) {
  trails_.assign(lights.size(), kInfinite);
  depths_.assign(lights.size(), 0);
  std::vector<std::pair<uint32_t, LightBounds>> items;
  for (uint32_t i = 0; i < lights.size(); ++i) {
    std::optional<LightBounds> b = lights[i]->bounds();
    if (!b) {
      infinite_.push_back(i);
    } else if (b->phi > 0) {
      items.emplace_back(i, *b);
    } else {
      trails_[i] = kInfinite - 1;  // emits nothing: never picked
    }
  }
  if (!items.empty()) build(items, 0, items.size(), 0, 0);
  distant_ = DistantLightPicker(lights, infinite_);
}

uint32_t BvhLightSampler::build(std::vector<std::pair<uint32_t, LightBounds>>& items, size_t begin,
                                size_t end, uint64_t trail, int depth) {
  const uint32_t index = uint32_t(nodes_.size());
  nodes_.emplace_back();
  // Median splits keep the depth at log2(lights), so trails fit in 64 bits.
  if (end - begin == 1) {
    nodes_[index].bounds = items[begin].second;
    nodes_[index].leaf = true;
    nodes_[index].light = items[begin].first;
    trails_[items[begin].first] = trail;
    depths_[items[begin].first] = uint8_t(depth);
    return index;
  }
  // Split at the median of the centroids along the widest axis.
  Bounds3f centroids;
  for (size_t i = begin; i < end; ++i) centroids.extend(items[i].second.bounds.center());
  const Vec3f extent = centroids.diagonal();
  const int axis =
      extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  const size_t mid = (begin + end) / 2;
  std::nth_element(items.begin() + ptrdiff_t(begin), items.begin() + ptrdiff_t(mid),
                   items.begin() + ptrdiff_t(end), [axis](const auto& a, const auto& b) {
                     return a.second.bounds.center()[axis] < b.second.bounds.center()[axis];
                   });
  build(items, begin, mid, trail, depth + 1);
  const uint32_t second = build(items, mid, end, trail | (1ull << depth), depth + 1);
  nodes_[index].child1 = second;
  nodes_[index].bounds = unionOf(nodes_[index + 1].bounds, nodes_[second].bounds);
  return index;
}

float BvhLightSampler::firstChildProbability(const Node& node,
                                             const LightSampleContext& ctx) const {
  const uint32_t c0 = uint32_t(&node - nodes_.data()) + 1;
  const float i0 = lightBoundsImportance(nodes_[c0].bounds, ctx);
  const float i1 = lightBoundsImportance(nodes_[node.child1].bounds, ctx);
  if (!(i0 + i1 > 0)) return -1;
  return i0 / (i0 + i1);
}

std::optional<SampledLight> BvhLightSampler::sample(const LightSampleContext& ctx, float u) const {
  // The tree counts as one more light beside the unbounded ones.
  const size_t groups = infinite_.size() + (nodes_.empty() ? 0 : 1);
  if (groups == 0) return std::nullopt;
  const float pInfinite = float(infinite_.size()) / float(groups);
  if (u < pInfinite) {
    std::optional<SampledLight> picked =
        distant_.sample(ctx, std::min(u / pInfinite, 0x1.fffffep-1f));
    if (picked) picked->p *= pInfinite;
    return picked;
  }
  u = std::min((u - pInfinite) / (1 - pInfinite), 0x1.fffffep-1f);
  float p = 1 - pInfinite;
  uint32_t n = 0;
  while (!nodes_[n].leaf) {
    const float p0 = firstChildProbability(nodes_[n], ctx);
    if (p0 < 0) return std::nullopt;
    if (u < p0) {
      u = std::min(u / p0, 0x1.fffffep-1f);
      p *= p0;
      n = n + 1;
    } else {
      u = std::min((u - p0) / (1 - p0), 0x1.fffffep-1f);
      p *= 1 - p0;
      n = nodes_[n].child1;
    }
  }
  if (!(p > 0) || !(lightBoundsImportance(nodes_[n].bounds, ctx) > 0)) return std::nullopt;
  return SampledLight{nodes_[n].light, p};
}

float BvhLightSampler::pmf(const LightSampleContext& ctx, uint32_t index) const {
  if (index >= trails_.size()) return 0;
  const size_t groups = infinite_.size() + (nodes_.empty() ? 0 : 1);
  if (trails_[index] == kInfinite)
    return float(infinite_.size()) / float(groups) * distant_.pmf(ctx, index);
  if (trails_[index] == kInfinite - 1) return 0;
  float p = 1.0f / float(groups);
  uint32_t n = 0;
  for (int d = 0; !nodes_[n].leaf; ++d) {
    const float p0 = firstChildProbability(nodes_[n], ctx);
    if (p0 < 0) return 0;
    if (trails_[index] & (1ull << d)) {
      p *= 1 - p0;
      n = nodes_[n].child1;
    } else {
      p *= p0;
      n = n + 1;
    }
  }
  return lightBoundsImportance(nodes_[n].bounds, ctx) > 0 ? p : 0.0f;
}

}  // namespace glint
