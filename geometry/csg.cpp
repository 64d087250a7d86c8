// glint — CSG trees: span lists combined by a sweep over boundary crossings.
#include "geometry/csg.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace glint {

namespace {

bool inside(CsgOperation op, bool a, bool b) {
  switch (op) {
    case CsgOperation::Union:
      return a || b;
    case CsgOperation::Intersection:
      return a && b;
    case CsgOperation::Difference:
    default:
      return a && !b;
  }
}

// The k-th crossing (enter, exit, enter, ...) of a sorted span list.
const Crossing& crossingAt(const Span* spans, size_t k) {
  return (k & 1) ? spans[k >> 1].exit : spans[k >> 1].enter;
}

// Two crossings are one event when their t values cannot be told apart given their rounding
// bounds and their surfaces' tolerances, and they lie on one surface (parallel normals): the
// crossings of two faces that meet at an edge are two events however near the edge the line
// passes, in the order of their t.
bool coincide(const Crossing& a, const Crossing& b) {
  return crossingsTie(a, b) && sameSurface(a, b);
}

// A leaf's surface tolerance in its object space (see the tie rule in csg.h): its placement's
// error pulled back through the inverse, and the written precision of its own numbers.
SurfaceTolerance toleranceOf(const Transform& treeFromLeaf, const TransformError& error) {
  // In tree space a leaf point x is off by at most E (|x|, 1) per axis; in object space by
  // |M^-1| E (|x|, 1). The float inverse is within a few ulps of the exact one (the 1e-5
  // covers it), and the whole bound is doubled: the written-precision terms are first order.
  // A face at coordinate X on axis k is itself written to kWrittenPrecision |X|, and parsed.
  constexpr float kSlack = 2 * (1 + 1e-5f);
  const auto& inv = treeFromLeaf.inverseMatrix().m;
  SurfaceTolerance t;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j) {
      float sum = 0;
      for (int i = 0; i < 3; ++i) sum += std::abs(inv[k][i]) * error.e[i][j];
      if (j == k) sum += kWrittenPrecision + kMachineEpsilon;
      t.m[k][j] = kSlack * sum;
    }
  return t;
}

// Whether two crossings that bound a result span (or a gap between two) are below the tree's
// resolution: their t values cannot be told apart by rounding, or they come from two different
// leaves and tie (the two leaves' faces meet within their tolerances there, and which of them the
// line crosses first is decided by rounding). A span between two faces of one leaf is that
// leaf's corner, as real as the plain solid's.
bool unresolved(const Crossing& a, const Crossing& b) {
  if (a.t == b.t || std::abs(a.t - b.t) <= a.tError + b.tError) return true;
  return (a.part >> 3) != (b.part >> 3) && crossingsTie(a, b);
}

// The stretch of the line a query must get right: the ray's [tMin, tMax], widened by far more
// than any crossing's error and tie width (a thousandth of the larger |t|, and of the root
// box's extent along the line). A subtree whose box misses it can only add crossings outside
// it, which no hit in [tMin, tMax] depends on: the operators act point by point along the line,
// ties join crossings within their widths, and a sliver dropped at the root is shorter than a
// width. So such a subtree is culled like one the whole line misses; for shadow rays, which
// end at the light, and closest-hit queries Embree has already shortened, that is most of the
// tree. Spans are still whole-line spans wherever the window reaches.
std::pair<float, float> queryWindow(const Ray& ray, const Bounds3f& root) {
  if (isUnbounded(root) || root.empty()) return {-kInfinity, kInfinity};
  const float extent = length(root.upper - root.lower) / std::max(length(ray.d), 1e-30f);
  auto widen = [&](float t, float sign) {
    if (std::isinf(t)) return t;
    return t + sign * 1e-3f * (std::abs(t) + extent);
  };
  return {widen(ray.tMin, -1), widen(ray.tMax, 1)};
}

}  // namespace

void combineSpans(CsgOperation op, const Span* a, size_t na, const Span* b, size_t nb,
                  std::vector<Span>& out) {
  const size_t ea = 2 * na, eb = 2 * nb;  // crossing counts
  size_t i = 0, j = 0;
  bool inA = false, inB = false, in = false;
  Crossing open;  // the enter crossing of the result span being built
  while (i < ea || j < eb) {
    // The earliest remaining crossing starts the event. The other list's next crossing joins
    // it when the two coincide: at most one crossing of each child per event. Two crossings of
    // one child are two events of that child's own (its span list is already resolved),
    // however wide their tolerances: where a ray clips an edge, a thin sliver must meet its
    // twin's two crossings pairwise, enter with enter and exit with exit, or one twin's sliver
    // would survive the other's. For the same reason the joining crossing goes to the first
    // child's *next* crossing instead when that one is nearer to it and coincides with it too.
    const bool aFirst = j >= eb || (i < ea && crossingAt(a, i).t <= crossingAt(b, j).t);
    const Span* firstList = aFirst ? a : b;
    const size_t firstIndex = aFirst ? i : j, firstCount = aFirst ? ea : eb;
    const Crossing& first = crossingAt(firstList, firstIndex);
    const Crossing* other = nullptr;
    if (aFirst ? j < eb : i < ea) other = aFirst ? &crossingAt(b, j) : &crossingAt(a, i);
    bool tie = other && coincide(*other, first);
    if (tie && firstIndex + 1 < firstCount) {
      const Crossing& rival = crossingAt(firstList, firstIndex + 1);
      if (std::abs(rival.t - other->t) < std::abs(first.t - other->t) && coincide(rival, *other))
        tie = false;
    }
    // The left-most child's crossing is the event's boundary (the tie rule's attribution).
    const Crossing* fromA = aFirst ? &first : (tie ? other : nullptr);
    const Crossing* fromB = aFirst ? (tie ? other : nullptr) : &first;
    if (fromA) inA = !inA, ++i;
    if (fromB) inB = !inB, ++j;
    bool now = inside(op, inA, inB);
    if (now == in) continue;
    const Crossing& boundary = fromA ? *fromA : *fromB;
    if (now) {
      open = boundary;
    } else {
      out.push_back(Span{open, boundary});
    }
    in = now;
  }
}

uint32_t CsgShape::addLeaf(std::unique_ptr<Shape> shape, const Transform& treeFromLeaf,
                           const TransformError& placementError) {
  assert(shape && shape->isSolid());
  const Shape* raw = shape.get();
  leaves_.push_back(Leaf{std::move(shape), PlacedShape(raw, treeFromLeaf),
                         toleranceOf(treeFromLeaf, placementError), false});
  Node node;
  node.leaf = uint32_t(leaves_.size() - 1);
  nodes_.push_back(std::move(node));
  return uint32_t(nodes_.size() - 1);
}

std::unique_ptr<Shape> CsgShape::clone() const {
  auto copy = std::make_unique<CsgShape>();
  copy->nodes_ = nodes_;
  copy->nodeBounds_ = nodeBounds_;
  copy->root_ = root_;
  copy->bounds_ = bounds_;
  for (const Leaf& leaf : leaves_) {
    std::unique_ptr<Shape> shape = leaf.shape->clone();
    const Shape* raw = shape.get();
    copy->leaves_.push_back(Leaf{std::move(shape), PlacedShape(raw, leaf.placed.placement()),
                                 leaf.tolerance, leaf.flipNormal});
  }
  return copy;
}

uint32_t CsgShape::addOperation(CsgOperation op, std::vector<uint32_t> children) {
  assert(children.size() >= 2);
  Node node;
  node.op = op;
  node.children = std::move(children);
  nodes_.push_back(std::move(node));
  return uint32_t(nodes_.size() - 1);
}

void CsgShape::finish(uint32_t root) {
  assert(root < nodes_.size());
  root_ = root;
  orient(root_, false);
  nodeBounds_.resize(nodes_.size());
  for (uint32_t n = 0; n < nodes_.size(); ++n) nodeBounds_[n] = nodeBounds(n, true);
  bounds_ = nodeBounds(root_, false);
}

void CsgShape::orient(uint32_t node, bool flip) {
  const Node& n = nodes_[node];
  if (n.leaf != kNone) {
    leaves_[n.leaf].flipNormal = flip;
    return;
  }
  for (size_t c = 0; c < n.children.size(); ++c) {
    // A subtracted solid's surfaces bound the result from the outside: their outward normals
    // point into the result, so they flip (twice flipped under nested differences).
    bool subtracted = n.op == CsgOperation::Difference && c > 0;
    orient(n.children[c], flip != subtracted);
  }
}

Bounds3f CsgShape::nodeBounds(uint32_t node, bool padded) const {
  const Node& n = nodes_[node];
  if (n.leaf != kNone) {
    if (!padded) return leaves_[n.leaf].placed.bounds();
    // Padded by the leaf's tolerance (twice its bound at the box's corners, taken to tree space):
    // a line that misses the leaf by less is a near miss (see leafSpan in
    // geometry/shapes/primitive_math.h), whose crossings the operators need.
    const Leaf& leaf = leaves_[n.leaf];
    Bounds3f b = leaf.placed.bounds();
    const Bounds3f ob = leaf.shape->bounds();
    if (isUnbounded(b) || isUnbounded(ob) || b.empty()) return b;
    float tau[3];
    for (int k = 0; k < 3; ++k) {
      const auto& row = leaf.tolerance.m[size_t(k)];
      tau[k] = row[3];
      for (int j = 0; j < 3; ++j)
        tau[k] += row[size_t(j)] * std::max(std::abs(ob.lower[j]), std::abs(ob.upper[j]));
    }
    const auto& m = leaf.placed.placement().matrix().m;
    for (int i = 0; i < 3; ++i) {
      float pad = 0;
      for (int k = 0; k < 3; ++k) pad += std::abs(m[i][k]) * tau[k];
      b.lower[i] -= 2 * pad, b.upper[i] += 2 * pad;
    }
    return b;
  }
  Bounds3f b = nodeBounds(n.children[0], padded);
  if (n.op == CsgOperation::Difference) return b;  // never larger than what is subtracted from
  for (size_t c = 1; c < n.children.size(); ++c) {
    Bounds3f cb = nodeBounds(n.children[c], padded);
    if (n.op == CsgOperation::Union) {
      b.extend(cb);
    } else {
      b.lower = max(b.lower, cb.lower);
      b.upper = min(b.upper, cb.upper);
    }
  }
  return b;
}

size_t CsgShape::evaluate(uint32_t node, const Ray& ray, Scratch& scratch) const {
  std::vector<Span>& out = scratch.spans;
  const Node& n = nodes_[node];
  // A subtree whose box the query's window misses contributes no spans (for a difference's
  // first child or an intersection's child that empties the whole node).
  if (segmentMissesBox(ray, scratch.invD, nodeBounds_[node], scratch.tLo, scratch.tHi)) return 0;
  if (n.leaf != kNone) {
    Span s;
    const Leaf& leaf = leaves_[n.leaf];
    if (!leaf.placed.span(ray, leaf.tolerance, &s)) return 0;
    uint32_t tag = n.leaf << 3;
    s.enter.part = tag | (s.enter.part & 7);
    s.exit.part = tag | (s.exit.part & 7);
    out.push_back(s);  // zero-length ones too: their crossings take part (see evaluateRoot)
    return 1;
  }
  // The first child's spans sit at [base, base + count); each further child is evaluated after
  // them, combined into the space after that, and the result moved down to `base`.
  const size_t base = out.size();
  size_t count = evaluate(n.children[0], ray, scratch);
  for (size_t c = 1; c < n.children.size(); ++c) {
    if (count == 0 && n.op != CsgOperation::Union) break;  // empty stays empty
    size_t other = evaluate(n.children[c], ray, scratch);
    if (other == 0) {  // an empty child leaves a union or difference as it was
      if (n.op == CsgOperation::Intersection) count = 0;
      out.resize(base + count);
      continue;
    }
    if (count == 0) {  // union with nothing so far: the child's spans, moved down
      std::copy(out.begin() + std::ptrdiff_t(base + count), out.end(),
                out.begin() + std::ptrdiff_t(base));
      count = other;
      out.resize(base + count);
      continue;
    }
    // combineSpans appends at most count + other spans: reserve first so the input pointers
    // stay valid while it does.
    out.reserve(out.size() + count + other);
    const size_t resultStart = out.size();
    combineSpans(n.op, out.data() + base, count, out.data() + base + count, other, out);
    const size_t resultCount = out.size() - resultStart;
    std::copy(out.begin() + std::ptrdiff_t(resultStart), out.end(),
              out.begin() + std::ptrdiff_t(base));
    out.resize(base + resultCount);
    count = resultCount;
  }
  out.resize(base + count);
  return count;
}

size_t CsgShape::evaluateRoot(const Ray& ray, float tLo, float tHi, Scratch& scratch) const {
  scratch.spans.clear();
  scratch.tLo = tLo, scratch.tHi = tHi;
  scratch.invD = reciprocalDirection(ray.d);
  if (root_ == kNone) return 0;
  const size_t n = evaluate(root_, ray, scratch);
  // The result regularised once, at the root: every sliver and crack took part in the operators
  // below (dropped earlier, a leaf's sliver at a seam lost the face it entered by, and the seam
  // bounded the result instead). A gap between two result spans whose crossings are below the
  // tree's resolution closes, then a span whose two ends are goes.
  size_t joined = 0;
  for (size_t k = 0; k < n; ++k) {
    const Span& s = scratch.spans[k];
    if (joined > 0 && unresolved(scratch.spans[joined - 1].exit, s.enter))
      scratch.spans[joined - 1].exit = s.exit;
    else
      scratch.spans[joined++] = s;
  }
  size_t kept = 0;
  for (size_t k = 0; k < joined; ++k) {
    const Span& s = scratch.spans[k];
    if (s.exit.t >= s.enter.t && !unresolved(s.enter, s.exit)) scratch.spans[kept++] = s;
  }
  scratch.spans.resize(kept);
  return kept;
}

std::vector<Span> CsgShape::spans(const Ray& ray) const {
  Scratch scratch;
  evaluateRoot(ray, -kInfinity, kInfinity, scratch);
  return scratch.spans;
}

CsgShape::Reorigined CsgShape::reoriginate(const Ray& ray) const {
  Reorigined r{ray, 0, 0};
  if (isUnbounded(bounds_) || bounds_.empty()) return r;
  // Where the line enters the root box (slab test; a line parallel to a slab leaves that
  // slab's entry at -inf). Only a start before it is moved: from inside the box, or for a ray
  // that starts near it, |t| is already of the tree's size.
  float entry = -kInfinity;
  for (int i = 0; i < 3; ++i) {
    if (ray.d[i] == 0) continue;
    const float t0 = (bounds_.lower[i] - ray.o[i]) / ray.d[i];
    const float t1 = (bounds_.upper[i] - ray.o[i]) / ray.d[i];
    entry = std::max(entry, std::min(t0, t1));
  }
  if (!(entry > 0) || !std::isfinite(entry)) return r;
  r.ray.o = ray.at(entry);
  r.shift = entry;
  // The moved origin is off the exact line by the rounding of o + t d, at most gamma(2) of
  // |o| + |t d| per axis; as a t along d that is at most this much (|d|^2 scaled).
  const Vec3f a = abs(ray.o) + abs(ray.d * entry);
  r.shiftError = gamma(2) * (a.x + a.y + a.z) / std::max(length(ray.d), 1e-30f) + gamma(1) * entry;
  r.ray.tMin = ray.tMin - entry;
  r.ray.tMax = ray.tMax - entry;
  return r;
}

bool CsgShape::intersect(const Ray& ray, ShapeHit* hit) const {
  // Per-thread storage: after the first few rays no query allocates.
  thread_local Scratch scratch;
  // The tree's crossings are found on the ray moved to the root box's entry, so that their t
  // values, error bounds and tie widths are those of a ray starting at the tree (see csg.h).
  const Reorigined r = reoriginate(ray);
  const auto [tLo, tHi] = queryWindow(r.ray, bounds_);
  const size_t n = evaluateRoot(r.ray, tLo, tHi, scratch);
  for (size_t k = 0; k < 2 * n; ++k) {
    const Crossing& c = crossingAt(scratch.spans.data(), k);
    if (std::isinf(c.t)) {
      if (c.t > 0) return false;
      continue;
    }
    const float t = c.t + r.shift;
    if (t > ray.tMax) return false;
    // Certainly beyond tMin given t's error bound (the Shape robustness contract).
    if (t - (c.tError + r.shiftError) > ray.tMin) {
      hit->t = t;
      hit->part = c.part;
      return true;
    }
  }
  return false;
}

ShapeSurface CsgShape::surface(const Ray& ray, const ShapeHit& hit, SurfaceDetails details) const {
  const Leaf& leaf = leaves_[hit.part >> 3];
  // The same moved ray intersect() found the hit on: the leaf works out the point from an
  // origin near it.
  const Reorigined r = reoriginate(ray);
  ShapeSurface s = leaf.placed.surface(r.ray, ShapeHit{hit.t - r.shift, hit.part & 7}, details);
  if (leaf.flipNormal) s.n = -s.n;
  return s;
}

}  // namespace glint
