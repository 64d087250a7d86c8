// glint — kd-tree backends: primitives, the shared tree bookkeeping, robust traversal, and the
// SAH builder of Wald & Havran, "On building fast kd-Trees for Ray Tracing, and on doing that
// in O(N log N)" (IEEE Symposium on Interactive Ray Tracing 2006). The median builder is in
// kdtree_median.cpp.
#include "geometry/accel/kdtree.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "geometry/error.h"

namespace glint {

// ---------------------------------------------------------------------------------------------
// Primitives
// ---------------------------------------------------------------------------------------------

namespace {

// Zero-area triangles are never hit, so they are left out of the tree. The cross product in
// double is exact for repeated vertices and for collinear ones on a coarse grid; a float
// test would let rounding make a sliver of a line out of an exactly collinear triangle.
bool zeroArea(const std::array<Vec3f, 3>& t) {
  double e1[3], e2[3];
  for (int k = 0; k < 3; ++k) e1[k] = double(t[1][k]) - t[0][k], e2[k] = double(t[2][k]) - t[0][k];
  return e1[1] * e2[2] - e1[2] * e2[1] == 0 && e1[2] * e2[0] - e1[0] * e2[2] == 0 &&
         e1[0] * e2[1] - e1[1] * e2[0] == 0;
}

}  // namespace

void KdPrimitives::gather(const GeometryScene& scene, const UnboundedShapes& unbounded) {
  std::vector<Vec3f> world;  // one instance's vertices, transformed once
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    if (inst.isShape() || inst.moves()) continue;
    const TriangleMesh& mesh = scene.meshes[inst.mesh];
    if (mesh.deforms()) continue;
    const bool identity = inst.worldFromObject.isIdentity();
    if (!identity) {
      world.resize(mesh.positions.size());
      for (size_t v = 0; v < world.size(); ++v)
        world[v] = inst.worldFromObject.point(mesh.positions[v]);
    }
    const std::vector<Vec3f>& p = identity ? mesh.positions : world;
    // The front of a placed triangle is its object-space winding's normal carried by the
    // placement; a mirroring placement turns the world-space winding over.
    const int8_t cull = !mesh.singleSided                                     ? 0
                        : identity || !inst.worldFromObject.swapsHandedness() ? 1
                                                                              : -1;
    for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
      std::array<Vec3f, 3> tri{p[mesh.indices[3 * t]], p[mesh.indices[3 * t + 1]],
                               p[mesh.indices[3 * t + 2]]};
      if (!isFinite(tri[0]) || !isFinite(tri[1]) || !isFinite(tri[2]) || zeroArea(tri)) continue;
      Bounds3f b;
      for (const Vec3f& v : tri) b.extend(v);
      triangles.push_back(tri);
      triCull.push_back(cull);
      triInstance.push_back(i);
      triPrim.push_back(t);
      bounds.push_back(b);
    }
  }
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    if (!inst.isShape() || inst.moves() || unbounded.contains(i)) continue;
    PlacedShape placed = scene.placedShape(i);
    Bounds3f b = placed.bounds();
    if (b.empty() || !isFinite(b.lower) || !isFinite(b.upper)) continue;
    shapes.push_back(placed);
    shapeInstance.push_back(i);
    bounds.push_back(b);
  }
  if (bounds.size() > KdNode::kMaxPayload)
    throw FailureError("kd-tree: " + std::to_string(bounds.size()) +
                       " primitives, more than its 30-bit indices hold (--accel embree holds "
                       "more)");
}

void KdPrimitives::gatherDeforming(const TriangleMesh& mesh) {
  timeSteps = uint32_t(mesh.positionSteps.size());
  for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
    const uint32_t i0 = mesh.indices[3 * t], i1 = mesh.indices[3 * t + 1],
                   i2 = mesh.indices[3 * t + 2];
    Bounds3f b;
    bool finite = true;
    for (const std::vector<Vec3f>& p : mesh.positionSteps) {
      for (uint32_t v : {i0, i1, i2}) {
        finite = finite && isFinite(p[v]);
        b.extend(p[v]);
      }
    }
    if (!finite) continue;
    // A triangle with no area at one step may have some at another: only the middle pose
    // (`triangles`, used for nothing but this list's length) is kept as it is.
    triangles.push_back({mesh.positions[i0], mesh.positions[i1], mesh.positions[i2]});
    for (const std::vector<Vec3f>& p : mesh.positionSteps)
      triangleSteps.push_back({p[i0], p[i1], p[i2]});
    triCull.push_back(mesh.singleSided ? 1 : 0);
    triInstance.push_back(0);
    triPrim.push_back(t);
    bounds.push_back(b);
  }
  if (bounds.size() > KdNode::kMaxPayload)
    throw FailureError("kd-tree: " + std::to_string(bounds.size()) +
                       " primitives, more than its 30-bit indices hold (--accel embree holds "
                       "more)");
}

std::array<Vec3f, 3> KdPrimitives::triangleAt(uint32_t id, float time) const {
  const auto [k, f] = timeStepBlend(time, timeSteps);
  const std::array<Vec3f, 3>& a = triangleSteps[size_t(id) * timeSteps + k];
  const std::array<Vec3f, 3>& b = triangleSteps[size_t(id) * timeSteps + k + 1];
  return {(1 - f) * a[0] + f * b[0], (1 - f) * a[1] + f * b[1], (1 - f) * a[2] + f * b[2]};
}

namespace {

Bounds3f intersectBounds(const Bounds3f& a, const Bounds3f& b) {
  return {max(a.lower, b.lower), min(a.upper, b.upper)};
}

// Sutherland–Hodgman clipping of a convex polygon against one axis-aligned plane, keeping
// the side `keepBelow` (x[axis] <= plane) or above. Points made on the plane get exactly the
// plane's coordinate on that axis, so clipped bounds never poke through the cell's faces.
int clipPolygon(const Vec3f* in, int n, Vec3f* out, int axis, float plane, bool keepBelow) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3f& a = in[i];
    const Vec3f& b = in[(i + 1) % n];
    const float da = keepBelow ? plane - a[axis] : a[axis] - plane;  // >= 0: inside
    const float db = keepBelow ? plane - b[axis] : b[axis] - plane;
    if (da >= 0) out[m++] = a;
    if ((da >= 0) != (db >= 0)) {
      const float s = (plane - a[axis]) / (b[axis] - a[axis]);
      Vec3f p = a + (b - a) * s;
      p[axis] = plane;
      out[m++] = p;
    }
  }
  return m;
}

}  // namespace

Bounds3f KdPrimitives::clippedBounds(uint32_t id, const Bounds3f& box) const {
  const Bounds3f& b = bounds[id];
  Bounds3f inBox = intersectBounds(b, box);
  // A deforming triangle sweeps a volume: its bounds over the shutter are all we know.
  if (inBox.empty() || !isTriangle(id) || timeSteps > 1) return inBox;
  // Perfect splits (Wald & Havran section 4.3): the bounds of the triangle clipped to the
  // cell. At most 3 + 6 vertices after six planes.
  Vec3f bufA[9], bufB[9];
  Vec3f* cur = bufA;
  Vec3f* next = bufB;
  int n = 3;
  for (int k = 0; k < 3; ++k) cur[k] = triangles[id][k];
  for (int axis = 0; axis < 3 && n > 0; ++axis) {
    if (b.lower[axis] < box.lower[axis]) {  // only planes that cut the triangle's bounds
      n = clipPolygon(cur, n, next, axis, box.lower[axis], false);
      std::swap(cur, next);
    }
    if (n > 0 && b.upper[axis] > box.upper[axis]) {
      n = clipPolygon(cur, n, next, axis, box.upper[axis], true);
      std::swap(cur, next);
    }
  }
  // An empty result may be rounding in a sliver: fall back to the plain box overlap, which is
  // conservative.
  if (n == 0) return inBox;
  Bounds3f clipped;
  for (int k = 0; k < n; ++k) clipped.extend(cur[k]);
  // Intersection points carry a few ulps of error in the non-clipped coordinates: widen by
  // a bound on it (relative to the triangle's extent), then stay inside the exact overlap.
  for (int axis = 0; axis < 3; ++axis) {
    float slack = gamma(6) * std::max(std::abs(b.lower[axis]), std::abs(b.upper[axis]));
    clipped.lower[axis] -= slack;
    clipped.upper[axis] += slack;
  }
  return intersectBounds(clipped, inBox);
}

// ---------------------------------------------------------------------------------------------
// Tree bookkeeping (stats and the SAH cost of the built tree)
// ---------------------------------------------------------------------------------------------

namespace {

// Half the surface area: every SAH ratio is a quotient of two, so the factor 2 cancels.
double halfArea(const Bounds3f& b) {
  Vec3f d = b.diagonal();
  if (d.x < 0 || d.y < 0 || d.z < 0) return 0;
  return double(d.x) * d.y + double(d.y) * d.z + double(d.z) * d.x;
}

}  // namespace

int KdTree::maxDepthFor(uint32_t primCount) {
  int depth = int(std::lround(8 + 1.3 * std::log2(std::max(1u, primCount))));
  return std::min(depth, kMaxDepth);
}

void KdTree::addLeaf(const uint32_t* prims, uint32_t count, const Bounds3f& box, int depth) {
  if (count > KdNode::kMaxPayload || nodes.size() >= KdNode::kMaxNodes)
    throw FailureError(
        "kd-tree: more nodes or leaf primitives than its indices hold "
        "(--accel embree holds more)");
  if (count == 1) {
    nodes.push_back(KdNode::leaf(1, prims[0]));
  } else {
    nodes.push_back(KdNode::leaf(count, uint32_t(leafPrims.size())));
    leafPrims.insert(leafPrims.end(), prims, prims + count);
  }
  ++stats.leaves;
  if (count == 0) ++stats.emptyLeaves;
  leafPrimRefs_ += count;
  stats.maxDepth = std::max(stats.maxDepth, uint32_t(depth));
  areaCost_ += double(cost.intersection) * count * halfArea(box);
}

uint32_t KdTree::addInterior(const Bounds3f& box, int depth) {
  if (nodes.size() >= KdNode::kMaxNodes)
    throw FailureError(
        "kd-tree: more nodes than its 28-bit indices hold (--accel embree holds "
        "more)");
  nodes.emplace_back();
  stats.maxDepth = std::max(stats.maxDepth, uint32_t(depth));
  areaCost_ += double(cost.traversal) * halfArea(box);
  return uint32_t(nodes.size() - 1);
}

void KdTree::setInterior(uint32_t node, int axis, float split) {
  nodes[node] = KdNode::interior(axis, split, uint32_t(nodes.size()));
}

void KdTree::append(const KdTree& sub) {
  const uint32_t nodeBase = uint32_t(nodes.size()), leafBase = uint32_t(leafPrims.size());
  if (size_t(nodeBase) + sub.nodes.size() >= KdNode::kMaxNodes)
    throw FailureError(
        "kd-tree: more nodes than its 28-bit indices hold (--accel embree holds "
        "more)");
  for (KdNode n : sub.nodes) {
    if (!n.isLeaf())
      n = KdNode::interior(n.axis(), n.split(), n.aboveChild() + nodeBase);
    else if (n.primCount() != 1)  // a single primitive is stored inline
      n = KdNode::leaf(n.primCount(), n.word + leafBase);
    nodes.push_back(n);
  }
  leafPrims.insert(leafPrims.end(), sub.leafPrims.begin(), sub.leafPrims.end());
  stats.leaves += sub.stats.leaves;
  stats.emptyLeaves += sub.stats.emptyLeaves;
  stats.maxDepth = std::max(stats.maxDepth, sub.stats.maxDepth);
  areaCost_ += sub.areaCost_;
  leafPrimRefs_ += sub.leafPrimRefs_;
}

// A shadow ray leaving a surface crosses about four empty cells for every one holding
// something (the SAH cuts empty space off around the surface, and most shadow rays escape):
// visiting each cost a node read and a pop. With the flags, the parent's step skips them.
void KdTree::markEmptyChildren() {
  auto empty = [&](uint32_t i) { return nodes[i].isLeaf() && nodes[i].primCount() == 0; };
  for (uint32_t i = 0; i < nodes.size(); ++i) {
    KdNode& n = nodes[i];
    if (n.isLeaf()) continue;
    n.bits &= ~(KdNode::kBelowEmpty | KdNode::kAboveEmpty);
    if (empty(i + 1)) n.bits |= KdNode::kBelowEmpty;
    if (empty(n.aboveChild())) n.bits |= KdNode::kAboveEmpty;
  }
}

void KdTree::finish() {
  markEmptyChildren();
  stats.nodes = nodes.size();
  stats.bytes = nodes.size() * sizeof(KdNode) + leafPrims.size() * sizeof(uint32_t);
  uint64_t full = stats.leaves - stats.emptyLeaves;
  stats.meanPrimsPerLeaf = full ? double(leafPrimRefs_) / double(full) : 0;
  // The expected cost of a ray through the root cell (no empty-space bonus: that is a build
  // heuristic, not a cost). A degenerate root (a point or a line) has no area to normalize
  // by: its tree is one leaf, costed as if every ray reached it.
  double root = halfArea(bounds);
  stats.sahCost = root > 0 ? areaCost_ / root : double(cost.intersection) * leafPrimRefs_;
}

void KdTree::packLeaves(const KdPrimitives& prims) {
  leafRecords.clear();
  leafRecords.reserve(leafPrimRefs_);
  const bool deforming = prims.timeSteps > 1;
  for (KdNode& node : nodes) {
    if (!node.isLeaf()) continue;
    const uint32_t count = node.primCount();
    const uint32_t* ids = count == 1 ? &node.word : leafPrims.data() + node.word;
    const uint32_t first = uint32_t(leafRecords.size());
    for (uint32_t i = 0; i < count; ++i) {
      const uint32_t id = ids[i];
      if (prims.isTriangle(id))
        leafRecords.push_back(KdLeafPrim::make(
            id, prims.triCull[id], deforming ? std::array<Vec3f, 3>{} : prims.triangles[id]));
      else
        leafRecords.push_back(KdLeafPrim::make(id, 0, {}));
    }
    node = KdNode::leaf(count, first);
  }
  if (leafRecords.size() > KdNode::kMaxPayload)
    throw FailureError(
        "kd-tree: more leaf primitives than its 30-bit indices hold (--accel "
        "embree holds more)");
  leafPrims = {};
  stats.bytes = nodes.size() * sizeof(KdNode) + leafRecords.size() * sizeof(KdLeafPrim);
}

// ---------------------------------------------------------------------------------------------
// The SAH builder (Wald & Havran 2006)
// ---------------------------------------------------------------------------------------------
//
// Steps, by the paper's names:
//   * Events (section 4.2): each primitive, clipped to the cell, gives per axis a start and
//     an end event at its bounds, or one planar event when it is flat on that axis. Three
//     lists, one per axis, sorted by (position, type) with end < planar < start.
//   * Sweep / FindPlane (section 4.2, Algorithm 4): one pass over each sorted list counts
//     N_L, N_P, N_R at every candidate plane and evaluates the SAH, putting the planar
//     primitives on whichever side is cheaper.
//   * Termination (section 3.3): make a leaf when no split is cheaper than the leaf
//     (KI * N) or at the maximum depth.
//   * Classify (section 5.1, Algorithm 5): one pass over the split axis' events marks each
//     primitive LeftOnly, RightOnly or Both.
//   * Splice (section 5.2): the events of one-sided primitives are copied to the children in
//     order, so the children's lists stay sorted without sorting; only the straddlers (Both)
//     are clipped to each child cell (perfect splits, section 4.3), their new events sorted
//     (few: about sqrt(N) per node) and merged in. Every level is linear, the whole O(N log N).
namespace {

enum EventType : uint32_t { kEnd = 0, kPlanar = 1, kStart = 2 };

struct Event {
  float pos;
  uint32_t key;  // primitive << 2 | type
  uint32_t prim() const { return key >> 2; }
  uint32_t type() const { return key & 3; }
};
// By position, then type (end < planar < start, which the sweep relies on), then primitive:
// a total order, so every sort (serial or parallel) gives the same lists and the same tree.
bool operator<(const Event& a, const Event& b) {
  if (a.pos != b.pos) return a.pos < b.pos;
  if ((a.key & 3) != (b.key & 3)) return (a.key & 3) < (b.key & 3);
  return a.key < b.key;
}

// A cell's events and how many primitives they describe.
struct EventLists {
  std::vector<Event> axis[3];
  uint32_t count = 0;
};

enum Side : uint8_t { kBoth, kLeftOnly, kRightOnly };

struct SplitPlane {
  double cost = std::numeric_limits<double>::infinity();
  int axis = -1;
  float pos = 0;
  bool planarLeft = true;  // where the primitives lying in the plane go
};

void addEvents(std::vector<Event>* lists, uint32_t prim, const Bounds3f& b) {
  for (int k = 0; k < 3; ++k) {
    if (b.lower[k] == b.upper[k]) {
      lists[k].push_back({b.lower[k], prim << 2 | kPlanar});
    } else {
      lists[k].push_back({b.lower[k], prim << 2 | kStart});
      lists[k].push_back({b.upper[k], prim << 2 | kEnd});
    }
  }
}

class SahBuilder {
 public:
  SahBuilder(const KdPrimitives& prims, KdTree* tree)
      : prims_(prims), tree_(*tree), cost_(tree->cost), side_(prims.size(), kBoth) {}

  // The whole tree. The top levels are split here, one after another; below `kTaskDepth` (or
  // for small cells) each cell becomes a task that an independent builder finishes in
  // parallel; the subtrees are then stitched in depth-first order. The result is the same
  // tree for any number of threads: tasks never share state and are emitted in order.
  void build() {
    auto root = acquire();
    for (uint32_t id = 0; id < prims_.size(); ++id) {
      tree_.bounds.extend(prims_.bounds[id]);
      addEvents(root->axis, id, prims_.bounds[id]);
    }
    root->count = prims_.size();
    // The only full sort of the build: afterwards lists stay sorted (Splice).
    for (auto& list : root->axis) tbb::parallel_sort(list.begin(), list.end());
    maxDepth_ = KdTree::maxDepthFor(prims_.size());
    tree_.nodes.reserve(8 * size_t(prims_.size()) + 1);  // typical: 7 nodes per primitive
    int top = plan(std::move(root), tree_.bounds, 0);
    tbb::parallel_for(size_t(0), tasks_.size(), [&](size_t t) {
      Task& task = tasks_[t];
      task.tree.cost = tree_.cost;
      SahBuilder sub(prims_, &task.tree);
      sub.maxDepth_ = maxDepth_;
      sub.buildNode(std::move(task.events), task.box, task.depth);
    });
    emit(top);
  }

 private:
  // Vectors keep their capacity across nodes: no per-node heap traffic once warm.
  std::unique_ptr<EventLists> acquire() {
    if (pool_.empty()) return std::make_unique<EventLists>();
    auto lists = std::move(pool_.back());
    pool_.pop_back();
    return lists;
  }
  void release(std::unique_ptr<EventLists> lists) {
    for (auto& l : lists->axis) l.clear();
    pool_.push_back(std::move(lists));
  }

  // The SAH cost of splitting `box` at `pos` on `axis` (section 3): lambda (KT + KI (P_L N_L
  // + P_R N_R)), with the hit probabilities P = area(child) / area(box). The empty-space
  // bonus lambda applies only when the empty child has volume: cutting off a flat empty cell
  // gains nothing, and rewarding it would make no-op splits look cheaper than a leaf.
  double splitCost(double pl, double pr, uint32_t nl, uint32_t nr, bool leftThick,
                   bool rightThick) const {
    double c = cost_.traversal + cost_.intersection * (pl * nl + pr * nr);
    if ((nl == 0 && leftThick) || (nr == 0 && rightThick)) c *= cost_.emptyBonus;
    return c;
  }

  // FindPlane (Algorithm 4): the sweep over each axis' sorted events.
  SplitPlane findPlane(const EventLists& ev, const Bounds3f& box) const {
    SplitPlane best;
    const double area = halfArea(box);
    if (!(area > 0)) return best;
    const double invArea = 1 / area;
    const Vec3f d = box.diagonal();
    for (int k = 0; k < 3; ++k) {
      if (!(d[k] > 0)) continue;  // a flat cell cannot be split across its thickness
      const double a = d[(k + 1) % 3], b = d[(k + 2) % 3];
      const double cap = a * b, ring = a + b;
      const std::vector<Event>& e = ev.axis[k];
      uint32_t nl = 0, nr = ev.count;
      for (size_t i = 0; i < e.size();) {
        const float p = e[i].pos;
        uint32_t ends = 0, planars = 0, starts = 0;
        while (i < e.size() && e[i].pos == p && e[i].type() == kEnd) ++ends, ++i;
        while (i < e.size() && e[i].pos == p && e[i].type() == kPlanar) ++planars, ++i;
        while (i < e.size() && e[i].pos == p && e[i].type() == kStart) ++starts, ++i;
        nr -= planars + ends;
        const double left = double(p) - box.lower[k], right = double(box.upper[k]) - p;
        if (left >= 0 && right >= 0) {
          const double pl = (cap + left * ring) * invArea, pr = (cap + right * ring) * invArea;
          double cl = splitCost(pl, pr, nl + planars, nr, left > 0, right > 0);
          double cr = splitCost(pl, pr, nl, nr + planars, left > 0, right > 0);
          if (cl < best.cost) best = {cl, k, p, true};
          if (cr < best.cost) best = {cr, k, p, false};
        }
        nl += starts + planars;
      }
    }
    return best;
  }

  void buildNode(std::unique_ptr<EventLists> ev, const Bounds3f& box, int depth) {
    SplitPlane plane;
    if (depth < maxDepth_ && ev->count > 0) plane = findPlane(*ev, box);
    // Termination (section 3.3): split only when cheaper than intersecting everything.
    if (plane.axis < 0 || !(plane.cost < double(cost_.intersection) * ev->count)) {
      leafBuffer_.clear();
      for (const Event& e : ev->axis[0])
        if (e.type() != kEnd) leafBuffer_.push_back(e.prim());
      tree_.addLeaf(leafBuffer_.data(), uint32_t(leafBuffer_.size()), box, depth);
      release(std::move(ev));
      return;
    }
    Bounds3f leftBox = box, rightBox = box;
    leftBox.upper[plane.axis] = plane.pos;
    rightBox.lower[plane.axis] = plane.pos;
    auto left = acquire(), right = acquire();
    classify(*ev, plane);
    splice(*ev, plane.axis, leftBox, rightBox, left.get(), right.get());
    release(std::move(ev));  // before recursing: the pool reuses it for the children

    const uint32_t node = tree_.addInterior(box, depth);
    buildNode(std::move(left), leftBox, depth + 1);
    tree_.setInterior(node, plane.axis, plane.pos);
    buildNode(std::move(right), rightBox, depth + 1);
  }

  // Classify (Algorithm 5): one pass over the split axis' events.
  void classify(const EventLists& ev, const SplitPlane& plane) {
    for (const Event& e : ev.axis[0])
      if (e.type() != kEnd) side_[e.prim()] = kBoth;
    for (const Event& e : ev.axis[plane.axis]) {
      switch (e.type()) {
        case kEnd:
          if (e.pos <= plane.pos) side_[e.prim()] = kLeftOnly;
          break;
        case kStart:
          if (e.pos >= plane.pos) side_[e.prim()] = kRightOnly;
          break;
        default:  // planar
          if (e.pos < plane.pos || (e.pos == plane.pos && plane.planarLeft))
            side_[e.prim()] = kLeftOnly;
          else
            side_[e.prim()] = kRightOnly;
      }
    }
  }

  // Splice (section 5.2): sorted one-sided events are kept in order, straddlers re-generated
  // against each child cell (perfect splits), sorted and merged in.
  void splice(const EventLists& ev, int axis, const Bounds3f& leftBox, const Bounds3f& rightBox,
              EventLists* left, EventLists* right) {
    uint32_t nl = 0, nr = 0;
    straddlers_.clear();
    for (const Event& e : ev.axis[axis]) {
      if (e.type() == kEnd) continue;
      switch (side_[e.prim()]) {
        case kLeftOnly:
          ++nl;
          break;
        case kRightOnly:
          ++nr;
          break;
        default:
          straddlers_.push_back(e.prim());
      }
    }
    for (int k = 0; k < 3; ++k) {
      keptLeft_[k].clear(), keptRight_[k].clear();
      newLeft_[k].clear(), newRight_[k].clear();
      for (const Event& e : ev.axis[k]) {
        const uint8_t s = side_[e.prim()];
        if (s == kLeftOnly)
          keptLeft_[k].push_back(e);
        else if (s == kRightOnly)
          keptRight_[k].push_back(e);
      }
    }
    for (uint32_t prim : straddlers_) {
      Bounds3f bl = prims_.clippedBounds(prim, leftBox);
      if (!bl.empty()) addEvents(newLeft_, prim, bl), ++nl;
      Bounds3f br = prims_.clippedBounds(prim, rightBox);
      if (!br.empty()) addEvents(newRight_, prim, br), ++nr;
    }
    for (int k = 0; k < 3; ++k) {
      std::sort(newLeft_[k].begin(), newLeft_[k].end());
      std::sort(newRight_[k].begin(), newRight_[k].end());
      mergeInto(keptLeft_[k], newLeft_[k], &left->axis[k]);
      mergeInto(keptRight_[k], newRight_[k], &right->axis[k]);
    }
    left->count = nl;
    right->count = nr;
  }

  static void mergeInto(const std::vector<Event>& a, const std::vector<Event>& b,
                        std::vector<Event>* out) {
    out->resize(a.size() + b.size());
    std::merge(a.begin(), a.end(), b.begin(), b.end(), out->begin());
  }

  // ---- The parallel top: a plan of the first levels' splits, and the cells left as tasks.
  static constexpr int kTaskDepth = 4;             // up to 16 tasks: balance on a few cores
  static constexpr uint32_t kMinTaskPrims = 4096;  // smaller cells are not worth a split here

  struct Task {
    std::unique_ptr<EventLists> events;
    Bounds3f box;
    int depth = 0;
    KdTree tree;
  };
  struct PlanNode {
    int task = -1;  // a task's subtree, or a split with the two plan children below
    int axis = 0;
    float pos = 0;
    int below = -1, above = -1;
    Bounds3f box;
    int depth = 0;
  };

  // Splits the top levels exactly as buildNode would, recording them; returns the plan node.
  int plan(std::unique_ptr<EventLists> ev, const Bounds3f& box, int depth) {
    PlanNode node;
    node.box = box;
    node.depth = depth;
    SplitPlane split;
    bool deep = depth >= kTaskDepth || ev->count < kMinTaskPrims;
    if (!deep && depth < maxDepth_ && ev->count > 0) split = findPlane(*ev, box);
    if (deep || split.axis < 0 || !(split.cost < double(cost_.intersection) * ev->count)) {
      // The task's builder repeats this node's decision itself (leaf or split).
      node.task = int(tasks_.size());
      tasks_.push_back(Task{std::move(ev), box, depth, KdTree{}});
      plan_.push_back(node);
      return int(plan_.size() - 1);
    }
    Bounds3f leftBox = box, rightBox = box;
    leftBox.upper[split.axis] = split.pos;
    rightBox.lower[split.axis] = split.pos;
    auto left = acquire(), right = acquire();
    classify(*ev, split);
    splice(*ev, split.axis, leftBox, rightBox, left.get(), right.get());
    release(std::move(ev));
    node.axis = split.axis;
    node.pos = split.pos;
    int index = int(plan_.size());
    plan_.push_back(node);
    int below = plan(std::move(left), leftBox, depth + 1);
    int above = plan(std::move(right), rightBox, depth + 1);
    plan_[size_t(index)].below = below;
    plan_[size_t(index)].above = above;
    return index;
  }

  // Writes the planned top and the tasks' subtrees in depth-first order.
  void emit(int p) {
    const PlanNode& node = plan_[size_t(p)];
    if (node.task >= 0) {
      tree_.append(tasks_[size_t(node.task)].tree);
      return;
    }
    const uint32_t index = tree_.addInterior(node.box, node.depth);
    emit(node.below);
    tree_.setInterior(index, node.axis, node.pos);
    emit(node.above);
  }

  const KdPrimitives& prims_;
  KdTree& tree_;
  const KdCostModel& cost_;
  int maxDepth_ = 0;
  std::vector<Task> tasks_;
  std::vector<PlanNode> plan_;
  std::vector<uint8_t> side_;  // per primitive, valid for the node being split
  std::vector<uint32_t> straddlers_, leafBuffer_;
  std::vector<Event> keptLeft_[3], keptRight_[3], newLeft_[3], newRight_[3];
  std::vector<std::unique_ptr<EventLists>> pool_;
};

}  // namespace

void buildSahKdTree(const KdPrimitives& prims, const KdCostModel& cost, KdTree* tree) {
  tree->cost = cost;
  SahBuilder(prims, tree).build();
  tree->finish();
}

// ---------------------------------------------------------------------------------------------
// Traversal
// ---------------------------------------------------------------------------------------------

namespace {

// The ray's interval inside `b`, pbrt-v3's Bounds3::IntersectP: the far slab distances are
// widened by 2 gamma(3) so rounding never drops a ray that grazes the box. A slab distance
// that is NaN (origin on the slab plane, direction 0 on that axis: 0 * inf) fails both
// comparisons and so leaves the interval alone: the ray lies in the slab's face.
bool clipToBox(const Ray& ray, const Vec3f& invDir, const Bounds3f& b, float* t0, float* t1) {
  float lo = ray.tMin, hi = ray.tMax;
  for (int k = 0; k < 3; ++k) {
    float tNear = (b.lower[k] - ray.o[k]) * invDir[k];
    float tFar = (b.upper[k] - ray.o[k]) * invDir[k];
    if (tNear > tFar) std::swap(tNear, tFar);
    tFar *= 1 + 2 * gamma(3);
    lo = tNear > lo ? tNear : lo;
    hi = tFar < hi ? tFar : hi;
    if (lo > hi) return false;
  }
  *t0 = lo, *t1 = hi;
  return true;
}

// Per-ray set-up of the watertight ray/triangle test (Woop, Benthin & Wald 2013, as in
// pbrt-v3): permute so the ray's largest direction component is z, then shear to +z.
struct WatertightRay {
  Vec3f o;
  int kx, ky, kz;
  float sx, sy, sz;
  explicit WatertightRay(const Ray& ray) : o(ray.o) {
    Vec3f a = abs(ray.d);
    kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    sx = -ray.d[kx] / ray.d[kz];
    sy = -ray.d[ky] / ray.d[kz];
    sz = 1 / ray.d[kz];
  }
};

// A hit with tMin < t <= tMax: t and Embree-convention barycentrics (with kAny, only whether
// there is one: a shadow ray needs neither t nor u, v). Edges are shared watertightly; a
// zero-area triangle has det == 0 and is never hit.
template <bool kAny>
bool intersectTriangle(const std::array<Vec3f, 3>& tri, const WatertightRay& r, float tMin,
                       float tMax, float* t, float* u, float* v) {
  Vec3f p[3];
  for (int i = 0; i < 3; ++i) {
    // A plain array: Vec3f's operator[] would branch on the ray's axes, three times a vertex.
    const float q[3] = {tri[i].x - r.o.x, tri[i].y - r.o.y, tri[i].z - r.o.z};
    p[i] = {q[r.kx] + r.sx * q[r.kz], q[r.ky] + r.sy * q[r.kz], q[r.kz]};
  }
  float e0 = p[1].x * p[2].y - p[1].y * p[2].x;
  float e1 = p[2].x * p[0].y - p[2].y * p[0].x;
  float e2 = p[0].x * p[1].y - p[0].y * p[1].x;
  if (e0 == 0 || e1 == 0 || e2 == 0) {  // on an edge in float: decide it in double
    e0 = float(double(p[1].x) * p[2].y - double(p[1].y) * p[2].x);
    e1 = float(double(p[2].x) * p[0].y - double(p[2].y) * p[0].x);
    e2 = float(double(p[0].x) * p[1].y - double(p[0].y) * p[1].x);
  }
  if ((e0 < 0 || e1 < 0 || e2 < 0) && (e0 > 0 || e1 > 0 || e2 > 0)) return false;
  const float det = e0 + e1 + e2;
  if (det == 0) return false;
  // t = (e0 z0 + e1 z1 + e2 z2) / det, written relative to z0 (det = e0 + e1 + e2): when the
  // vertices share their z (a face perpendicular to the ray's main axis, an axis-aligned ray
  // onto an axis-aligned face) the correction is exactly 0 and t is exact.
  const float invDet = 1 / det;
  const float dz = e1 * (p[1].z - p[0].z) + e2 * (p[2].z - p[0].z);
  const float tt = (p[0].z + dz * invDet) * r.sz;
  if (!(tt > tMin && tt <= tMax)) return false;
  // t must be certainly greater than tMin, beyond its own rounding error (pbrt-v3's bound
  // on t, section 3.9.6): a ray leaving a surface never re-hits it at t = 0 + rounding.
  const float maxZ =
      std::max({std::abs(p[0].z), std::abs(p[1].z), std::abs(p[2].z)}) * std::abs(r.sz);
  const float maxX = std::max({std::abs(p[0].x), std::abs(p[1].x), std::abs(p[2].x)});
  const float maxY = std::max({std::abs(p[0].y), std::abs(p[1].y), std::abs(p[2].y)});
  const float deltaX = gamma(5) * (maxX + maxZ), deltaY = gamma(5) * (maxY + maxZ);
  const float deltaZ = gamma(3) * maxZ;
  const float deltaE = 2 * (gamma(2) * maxX * maxY + deltaY * maxX + deltaX * maxY);
  const float maxE = std::max({std::abs(e0), std::abs(e1), std::abs(e2)});
  const float deltaT =
      3 * (gamma(3) * maxE * maxZ + deltaE * maxZ + deltaZ * maxE) * std::abs(invDet);
  if (!(tt - tMin > deltaT)) return false;
  if constexpr (!kAny) {
    *t = tt;
    *u = e1 * invDet;
    *v = e2 * invDet;
  }
  return true;
}

// Whether a single-sided triangle is seen from behind along d (`cull` as KdPrimitives::triCull,
// nonzero). A ray grazing the plane (dot exactly 0) is not culled: it cannot hit anyway.
bool isCulled(const std::array<Vec3f, 3>& tri, Vec3f d, int cull) {
  const float side = dot(cross(tri[1] - tri[0], tri[2] - tri[0]), d);
  return cull > 0 ? side > 0 : side < 0;
}

}  // namespace

KdTreeAccelerator::KdTreeAccelerator(const GeometryScene& scene, KdSplitMethod method,
                                     const KdCostModel& cost)
    : method_(method) {
  unbounded_.build(scene);
  prims_.gather(scene, unbounded_);
  if (method == KdSplitMethod::Sah)
    buildSahKdTree(prims_, cost, &tree_);
  else
    buildMedianKdTree(prims_, cost, &tree_);
  tree_.packLeaves(prims_);

  // Moving instances stay out of the tree (their world-space triangles change with time).
  std::vector<int> meshTree(scene.meshes.size(), -1);
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const bool deforms = !inst.isShape() && scene.meshes[inst.mesh].deforms();
    if ((!inst.moves() && !deforms) || unbounded_.contains(i)) continue;
    if (inst.isShape()) {
      movingShapes_.push_back({scene.shapes[inst.shape].get(), &inst.motion, i});
      continue;
    }
    const TriangleMesh& mesh = scene.meshes[inst.mesh];
    if (mesh.triangleCount() == 0) continue;
    int& tree = meshTree[inst.mesh];
    if (tree < 0 && mesh.deforms()) {
      // Its triangles change with time: a tree over their bounds swept over the shutter,
      // whose leaves blend each triangle's time steps at the ray's time.
      tree = int(meshTrees_.size());
      meshTrees_.push_back(
          std::unique_ptr<KdTreeAccelerator>(new KdTreeAccelerator(mesh, method, cost)));
    } else if (tree < 0) {
      // A tree over the mesh alone, in object space: what is traced is the ray taken to
      // object space at its time. Only positions, indices and sidedness are needed.
      GeometryScene alone;
      TriangleMesh shape;
      shape.positions = mesh.positions;
      shape.indices = mesh.indices;
      shape.singleSided = mesh.singleSided;
      alone.meshes.push_back(std::move(shape));
      alone.instances.push_back(Instance{0, Transform()});
      tree = int(meshTrees_.size());
      meshTrees_.push_back(std::make_unique<KdTreeAccelerator>(alone, method, cost));
    }
    movingMeshes_.push_back({meshTrees_[size_t(tree)].get(), &inst, i});
  }
}

KdTreeAccelerator::KdTreeAccelerator(const TriangleMesh& deforming, KdSplitMethod method,
                                     const KdCostModel& cost)
    : method_(method) {
  prims_.gatherDeforming(deforming);
  if (method == KdSplitMethod::Sah)
    buildSahKdTree(prims_, cost, &tree_);
  else
    buildMedianKdTree(prims_, cost, &tree_);
  tree_.packLeaves(prims_);
}

Ray KdTreeAccelerator::MovingMesh::objectRay(const Ray& ray) const {
  if (!placement->moves() && placement->worldFromObject.isIdentity()) return ray;
  const Transform objectFromWorld = placement->worldFromObjectAt(ray.time).inverse();
  return {objectFromWorld.point(ray.o), objectFromWorld.vector(ray.d), ray.tMin, ray.tMax,
          ray.time};
}

bool KdTreeAccelerator::closestMoving(const Ray& ray, Hit* hit) const {
  Ray r = ray;
  bool found = false;
  for (const MovingShape& m : movingShapes_) {
    ShapeHit sh;
    if (!PlacedShape(m.shape, m.motion->at(ray.time)).intersect(r, &sh)) continue;
    r.tMax = sh.t;
    *hit = {sh.t, m.instance, sh.part, 0, 0};
    found = true;
  }
  for (const MovingMesh& m : movingMeshes_) {
    // An affine map keeps t (d is mapped, not normalized) and barycentrics: Embree's object
    // space hit, as a motion instance gives it.
    const Ray local = m.objectRay(r);
    Hit h;
    if (!m.tree->closestHit(local, &h)) continue;
    r.tMax = h.t;
    *hit = {h.t, m.instance, h.prim, h.u, h.v};
    found = true;
  }
  return found;
}

bool KdTreeAccelerator::anyMoving(const Ray& ray) const {
  for (const MovingShape& m : movingShapes_)
    if (PlacedShape(m.shape, m.motion->at(ray.time)).occluded(ray)) return true;
  for (const MovingMesh& m : movingMeshes_)
    if (m.tree->anyHit(m.objectRay(ray))) return true;
  return false;
}

// Front-to-back traversal (pbrt-v3's KdTreeAccel::Intersect), with these rules:
//   * Order by direction, not by origin: for d[axis] > 0 (sign bit clear) the below child
//     is the near one. An origin exactly on a split plane thus needs no tie rule: the plane
//     is crossed at t = 0 and the near cell gets [tMin, 0], which is visited only when
//     tMin <= 0.
//   * Parallel rays (d[axis] == +-0, reciprocal +-inf, plane distance +-inf) visit the child
//     on their origin's side; a ray lying exactly in the split plane (plane distance 0 * inf,
//     NaN) visits both, since primitives lying in the plane went to one side only.
//   * A cell is skipped only when the plane is strictly outside the ray's interval, and only
//     by more than the rounding of the plane distance: flat cells (zero-thickness, from
//     planar events) have an interval [t, t] and are visited.
//   * Stop only when the closest hit so far is nearer than the next cell's entry: primitives
//     are tested over the whole ray, so a hit found in one cell may lie beyond it, and a
//     nearer one may still wait in the next.
template <bool kAny, bool kCount>
bool KdTreeAccelerator::trace(const Ray& ray, Hit* hit, KdTraversalCounts* counts) const {
  if constexpr (kCount) ++counts->rays;
  if (tree_.nodes.empty()) return false;
  const Vec3f invDir{1 / ray.d.x, 1 / ray.d.y, 1 / ray.d.z};
  float t0, t1;
  if (!clipToBox(ray, invDir, tree_.bounds, &t0, &t1)) return false;
  const WatertightRay wray(ray);
  constexpr float kSlack = 2 * gamma(3);

  struct Todo {
    uint32_t node;
    float tMin, tMax;
  };
  Todo todo[KdTree::kMaxDepth + 2];
  int top = 0;
  float closest = ray.tMax;
  bool found = false;
  const KdNode* nodes = tree_.nodes.data();
  const KdLeafPrim* records = tree_.leafRecords.data();
  const uint32_t triCount = uint32_t(prims_.triangles.size());
  const bool deforming = prims_.timeSteps > 1;
  // The ray as plain arrays: Vec3f's operator[] is a chain of conditionals, a branch on the
  // node's axis. `down`: per axis, whether the ray runs downwards (the sign bit, so that -0
  // counts: a parallel ray's reciprocal is then -inf and the rules above need no case of
  // their own).
  const float org[3] = {ray.o.x, ray.o.y, ray.o.z};
  const float inv[3] = {invDir.x, invDir.y, invDir.z};
  const bool down[3] = {std::signbit(ray.d.x), std::signbit(ray.d.y), std::signbit(ray.d.z)};
  float tMin = t0, tMax = t1;
  // The skip thresholds of the interval, widened by the plane distance's rounding; they
  // change only where tMin or tMax does, not at every node.
  auto lowered = [&](float t) { return t - std::abs(t) * kSlack; };
  auto raised = [&](float t) { return t + std::abs(t) * kSlack; };
  float tMinLo = lowered(tMin), tMaxHi = raised(tMax);
  std::array<Vec3f, 3> blended;  // a deforming triangle at the ray's time
  uint32_t index = 0;
  [[maybe_unused]] uintptr_t lastLine = 0;  // kCount
  for (;;) {
    const KdNode node = nodes[index];
    if constexpr (kCount) {
      ++counts->nodes;
      counts->nodeLines += (reinterpret_cast<uintptr_t>(&nodes[index]) / 64) != lastLine;
      lastLine = reinterpret_cast<uintptr_t>(&nodes[index]) / 64;
    }
    if (!node.isLeaf()) {
      // Branches, not selects: a branch-free step (children and interval picked with bit
      // masks, the far child always written to the stack) took a fifth of the branch
      // mispredictions in cachegrind's model but ran slower, occlusion 0.21 -> 0.18 of
      // Embree and camera rays 0.61 -> 0.32: it makes each node load wait for the previous
      // step's arithmetic, where a predicted branch lets the next load start at once.
      const int axis = node.axis();
      const float tPlane = (node.split() - org[axis]) * inv[axis];
      const uint32_t below = index + 1, above = node.aboveChild();
      const bool d = down[axis];
      const uint32_t nearChild = d ? above : below, farChild = d ? below : above;
      const bool nearEmpty = d ? node.aboveEmpty() : node.belowEmpty();
      const bool farEmpty = d ? node.belowEmpty() : node.aboveEmpty();
      // A NaN plane distance (a ray in the plane) fails both skip tests and every comparison
      // with tMin and tMax below, so both children are entered over the whole interval.
      // An empty child is never entered: nothing is there to hit.
      bool enter = true;
      if (tPlane > tMaxHi) {
        index = nearChild;
        enter = !nearEmpty;
      } else if (tPlane < tMinLo) {
        index = farChild;
        enter = !farEmpty;
      } else if (nearEmpty) {
        // Straight on to the far cell, over the part of the ray beyond the plane.
        tMin = tPlane > tMin ? tPlane : tMin;
        tMinLo = lowered(tMin);
        index = farChild;
        enter = !farEmpty && (kAny || !(closest < tMin));
      } else {
        if (!farEmpty) todo[top++] = {farChild, tPlane > tMin ? tPlane : tMin, tMax};
        tMax = tPlane < tMax ? tPlane : tMax;
        tMaxHi = raised(tMax);
        index = nearChild;
      }
      if (enter) continue;
    } else {
      // A leaf: test its primitives over the whole remaining ray.
      const uint32_t count = node.primCount();
      if constexpr (kCount) ++counts->leaves, counts->emptyLeaves += count == 0;
      const KdLeafPrim* run = records + node.word;
      for (uint32_t i = 0; i < count; ++i) {
        const KdLeafPrim& prim = run[i];
        const uint32_t id = prim.id();
        if constexpr (kCount) ++counts->primTests;
        if (id < triCount) {
          float t, u, v;
          // A deforming mesh's tree holds time steps: the triangle where it is at the ray's
          // time.
          const std::array<Vec3f, 3>& tri =
              deforming ? (blended = prims_.triangleAt(id, ray.time)) : prim.v;
          if (prim.cull() != 0 && isCulled(tri, ray.d, prim.cull())) continue;
          if (!intersectTriangle<kAny>(tri, wray, ray.tMin, closest, &t, &u, &v)) continue;
          if constexpr (kAny) {
            if constexpr (kCount) ++counts->hits;
            return true;
          }
          closest = t;
          found = true;
          *hit = {t, prims_.triInstance[id], prims_.triPrim[id], u, v};
        } else {
          const uint32_t s = id - triCount;
          Ray r = ray;
          r.tMax = closest;
          if constexpr (kAny) {
            if (prims_.shapes[s].occluded(r)) {
              if constexpr (kCount) ++counts->hits;
              return true;
            }
          } else {
            ShapeHit sh;
            if (!prims_.shapes[s].intersect(r, &sh)) continue;
            closest = sh.t;
            found = true;
            *hit = {sh.t, prims_.shapeInstance[s], sh.part, 0, 0};
          }
        }
      }
    }
    // Next cell, unless the closest hit is already nearer than where it begins (an any-hit
    // query has returned at its first hit, so it takes every cell left).
    for (;;) {
      if (top == 0) {
        if constexpr (kCount) counts->hits += found;
        return found;
      }
      const Todo& next = todo[--top];
      if (!kAny && closest < next.tMin) continue;
      index = next.node, tMin = next.tMin, tMax = next.tMax;
      tMinLo = lowered(tMin), tMaxHi = raised(tMax);
      break;
    }
  }
}

bool KdTreeAccelerator::closestHit(const Ray& ray, Hit* hit) const {
  if (!closestHitUnrefined(ray, hit)) return false;
  refineFarHit(ray, hit, [this](const Ray& r, Hit* h) { return closestHitUnrefined(r, h); });
  return true;
}

bool KdTreeAccelerator::closestHitUnrefined(const Ray& ray, Hit* hit) const {
  const bool moving = !movingShapes_.empty() || !movingMeshes_.empty();
  if (unbounded_.empty() && !moving) return trace<false>(ray, hit);
  // The nearest plane or moving object shortens the ray the tree traces (as the Embree
  // backend does with planes).
  Hit direct;
  Ray shorter = ray;
  bool found = false;
  if (!unbounded_.empty() && unbounded_.closestHit(ray, &direct)) {
    shorter.tMax = direct.t;
    found = true;
  }
  if (moving && closestMoving(shorter, &direct)) {
    shorter.tMax = direct.t;
    found = true;
  }
  if (!found) return trace<false>(ray, hit);
  if (trace<false>(shorter, hit) && hit->t < direct.t) return true;
  *hit = direct;
  return true;
}

bool KdTreeAccelerator::countedTrace(const Ray& ray, bool any, KdTraversalCounts* counts) const {
  Hit hit;
  return any ? trace<true, true>(ray, nullptr, counts) : trace<false, true>(ray, &hit, counts);
}

bool KdTreeAccelerator::anyHit(const Ray& ray) const {
  if (!unbounded_.empty() && unbounded_.anyHit(ray)) return true;
  if ((!movingShapes_.empty() || !movingMeshes_.empty()) && anyMoving(ray)) return true;
  return trace<true>(ray, nullptr);
}

}  // namespace glint
