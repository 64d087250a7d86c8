// glint — the in-house kd-tree backends: "kdtree" (SAH, built in O(N log N) after Wald &
// Havran 2006) and "kdtree-median" (the spatial-median baseline).
//
// Both trees share one compact node format (8 bytes, pbrt-v3's KdAccelNode layout), one leaf
// format (records holding the triangles themselves, KdLeafPrim) and one robust front-to-back
// traversal; they differ only in where they split. They hold every mesh triangle of the scene,
// flattened into world space (the vertices of each instance are transformed once at build
// time; barycentrics are invariant under the affine placement, so Hit.u, v match Embree's
// object-space ones), and every bounded analytic shape instance. Unbounded shapes (infinite
// planes) stay out of the tree, in an UnboundedShapes list tested first, as in the Embree
// backend.
//
// Motion blur: moving instances (Instance::motion animated) stay out of the tree too, so a
// static scene builds and traces exactly as before. A moving shape is placed at the ray's time
// and tested directly; a moving mesh gets a tree of its own in object space (one per mesh,
// shared by its moving placements), traced with the ray taken to object space by the inverse
// of the transform at the ray's time. Each query tests them all in a linear list: right for a
// few moving objects, slow for thousands (use Embree, whose BVH holds them). A deforming mesh
// (TriangleMesh::positionSteps) joins that list with a tree of its own over its triangles'
// bounds swept over the shutter (no perfect splits: a sweep is not a triangle), whose leaves
// blend each triangle's two nearest time steps at the ray's time, as Embree does.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "geometry/accel/accelerator.h"
#include "geometry/accel/unbounded.h"

namespace glint {

// ---------------------------------------------------------------------------------------------
// Node format
// ---------------------------------------------------------------------------------------------

// One kd-tree node in 8 bytes. `bits` holds the kind in its low 2 bits (0, 1, 2 = split
// axis of an interior node, 3 = leaf). Above them, for a leaf, its primitive count (30
// bits); for an interior node two flags, whether its below and its above child are empty
// leaves (set by KdTree::markEmptyChildren, so a traversal skips them without reading them),
// and the index of its above child (28 bits; the below child is the next node, depth-first
// layout). `word` is the split position (a float's bits) of an interior node. For a leaf, as
// the builders make it, `word` is the primitive itself when the leaf holds exactly one, else
// the offset of the leaf's run in the leaf primitive-index array; once the leaves are packed
// (KdTree::packLeaves) it is the offset of its run of KdLeafPrim records, whatever the count.
struct KdNode {
  static constexpr uint32_t kLeaf = 3;
  static constexpr uint32_t kMaxPayload = (1u << 30) - 1;  // primitives and their counts
  static constexpr uint32_t kMaxNodes = (1u << 28) - 1;    // child indices
  static constexpr uint32_t kBelowEmpty = 4, kAboveEmpty = 8;

  uint32_t word = 0;
  uint32_t bits = kLeaf;

  static KdNode interior(int axis, float split, uint32_t aboveChild) {
    return {std::bit_cast<uint32_t>(split), (aboveChild << 4) | uint32_t(axis)};
  }
  // `first` is the primitive (count == 1) or the offset into the leaf array (count > 1).
  static KdNode leaf(uint32_t count, uint32_t first) { return {first, (count << 2) | kLeaf}; }

  bool isLeaf() const { return (bits & 3) == kLeaf; }
  int axis() const { return int(bits & 3); }
  float split() const { return std::bit_cast<float>(word); }
  uint32_t aboveChild() const { return bits >> 4; }
  bool belowEmpty() const { return bits & kBelowEmpty; }
  bool aboveEmpty() const { return bits & kAboveEmpty; }
  uint32_t primCount() const { return bits >> 2; }
};
static_assert(sizeof(KdNode) == 8, "kd-tree nodes must stay 8 bytes (cache-line density)");

// A leaf's primitive as the traversal reads it: the records of one leaf are consecutive, and a
// triangle's carries its world-space vertices and culling code, where a primitive id, then the
// vertices it names, then its culling flag were three dependent loads from three arrays
// (measured: shadow rays 6-11% faster, benchmarks/README.md, issue 27). The price is memory:
// a triangle in k leaves (perfect splits cut triangles into several cells) is stored k times,
// 40 bytes each, which triples the dragon's tree.
struct KdLeafPrim {
  std::array<Vec3f, 3> v{};  // a static triangle's vertices; unused for shapes and for the
                             // triangles of a deforming mesh (placed at the ray's time)
  uint32_t bits = 0;         // the primitive id (30 bits) and the culling code above it

  static KdLeafPrim make(uint32_t id, int8_t cull, const std::array<Vec3f, 3>& v) {
    return {v, id | uint32_t(cull == 0 ? 0 : cull > 0 ? 1 : 2) << 30};
  }
  uint32_t id() const { return bits & KdNode::kMaxPayload; }
  // As KdPrimitives::triCull: 0, +1 or -1.
  int cull() const { return int(bits >> 30 == 2 ? -1 : bits >> 30); }
};
static_assert(sizeof(KdLeafPrim) == 40, "leaf records: three vertices and one word");

// The cost model of the SAH build (Wald & Havran, section 3). KT = 15, KI = 20 are the
// paper's constants (section 3.1); a triangle test and a node step cost about the same in
// our traversal, and these favour slightly deeper trees, which the paper found best. The
// empty-space bonus scales the cost of a split that cuts off an empty cell (section 3.2).
struct KdCostModel {
  float traversal = 15;     // KT
  float intersection = 20;  // KI
  float emptyBonus = 0.8f;  // lambda when one child is empty
};

// ---------------------------------------------------------------------------------------------
// Primitives: world-space triangles, then bounded shapes, numbered 0..size()-1
// ---------------------------------------------------------------------------------------------

struct KdPrimitives {
  std::vector<std::array<Vec3f, 3>> triangles;  // world-space vertices
  std::vector<uint32_t> triInstance, triPrim;   // Hit.instance, Hit.prim of each triangle
  // Per triangle: 0 when both sides are seen; +1 when a ray with dot(n, d) > 0 (n the normal
  // of `triangles`' world-space winding) passes through (a single-sided mesh's back face);
  // -1 for the opposite (the mesh's placement mirrors, which turns the winding over).
  std::vector<int8_t> triCull;
  std::vector<PlacedShape> shapes;  // bounded shape instances
  std::vector<uint32_t> shapeInstance;
  std::vector<Bounds3f> bounds;  // per primitive id (triangles first)
  // A deforming mesh's own tree (gatherDeforming): every triangle at `timeSteps` shutter
  // times (TriangleMesh::positionSteps), timeSteps consecutive entries per triangle, and
  // `bounds` swept over them. 1 and empty otherwise.
  uint32_t timeSteps = 1;
  std::vector<std::array<Vec3f, 3>> triangleSteps;

  // Collects the scene's static triangles and bounded shapes (`unbounded` lists the shapes to
  // leave out; moving instances are left out too). Triangles with non-finite vertices are
  // dropped: they cannot be bounded.
  void gather(const GeometryScene& scene, const UnboundedShapes& unbounded);
  // Collects a deforming mesh's triangles alone, in its object space (instance 0).
  void gatherDeforming(const TriangleMesh& mesh);
  // Triangle `id` of a deforming mesh at normalised shutter time `time` (its two nearest
  // steps blended as TriangleMesh::positionAt blends them).
  std::array<Vec3f, 3> triangleAt(uint32_t id, float time) const;
  uint32_t size() const { return uint32_t(bounds.size()); }
  bool isTriangle(uint32_t id) const { return id < triangles.size(); }
  // Conservative bounds of the part of primitive `id` inside `box` (empty when none): the
  // triangle polygon clipped to the box ("perfect splits", Wald & Havran section 4.3), or a
  // shape's bounds intersected with the box.
  Bounds3f clippedBounds(uint32_t id, const Bounds3f& box) const;
};

// ---------------------------------------------------------------------------------------------
// The flattened tree, and the bookkeeping both builders share
// ---------------------------------------------------------------------------------------------

struct KdTree {
  std::vector<KdNode> nodes;            // depth-first; the root is nodes[0]
  std::vector<uint32_t> leafPrims;      // runs of primitive ids of leaves holding > 1 (the
                                        // builders' output; emptied by packLeaves)
  std::vector<KdLeafPrim> leafRecords;  // what the traversal reads (packLeaves)
  Bounds3f bounds;                      // the root cell
  AccelStats stats;                     // filled in by addLeaf/addInterior/finish
  KdCostModel cost;                     // the model sahCost is evaluated with

  // The deepest tree a build may make: 8 + 1.3 log2 N (pbrt-v3's rule, also Wald & Havran's
  // safety net), capped by the traversal stack.
  static int maxDepthFor(uint32_t primCount);
  static constexpr int kMaxDepth = 62;

  // Appends a leaf holding `prims[0..count)` for the cell `box` at `depth`.
  void addLeaf(const uint32_t* prims, uint32_t count, const Bounds3f& box, int depth);
  // Appends a placeholder for an interior node and returns its index; set it with
  // setInterior once the below subtree is built.
  uint32_t addInterior(const Bounds3f& box, int depth);
  void setInterior(uint32_t node, int axis, float split);  // above child = nodes.size()
  // Appends a subtree built on its own (a parallel build's task) as the next nodes: its
  // child and leaf-array indices are shifted, its statistics merged.
  void append(const KdTree& sub);
  // Normalizes the SAH cost by the root area, fills the byte and mean counts and marks the
  // empty children.
  void finish();
  // Sets the interior nodes' empty-child flags.
  void markEmptyChildren();
  // Replaces the leaves' primitive ids by records holding the primitives (leafRecords, in
  // node order), points every leaf at its run and recounts the bytes. Same tree, same leaves.
  void packLeaves(const KdPrimitives& prims);

 private:
  double areaCost_ = 0;  // sum of cost * surface area over all nodes
  uint64_t leafPrimRefs_ = 0;
};

// The builders. Both fill `tree` (empty on entry) from `prims`.
void buildSahKdTree(const KdPrimitives& prims, const KdCostModel& cost, KdTree* tree);
void buildMedianKdTree(const KdPrimitives& prims, const KdCostModel& cost, KdTree* tree);

// ---------------------------------------------------------------------------------------------
// The accelerator
// ---------------------------------------------------------------------------------------------

enum class KdSplitMethod { Sah, Median };

// What one traversal did, summed over rays (`glint bench-accel --traversal-counts`): the
// numbers that say whether a ray rate is set by node steps, leaf visits or primitive tests.
struct KdTraversalCounts {
  uint64_t rays = 0;
  uint64_t nodes = 0;      // every node visited, interior and leaf
  uint64_t nodeLines = 0;  // visits to a node in another 64-byte line than the last one
  uint64_t leaves = 0;     // leaves visited, empty ones included
  uint64_t emptyLeaves = 0;
  uint64_t primTests = 0;  // primitives tested (culled triangles included)
  uint64_t hits = 0;       // rays with an answer of true
  KdTraversalCounts& operator+=(const KdTraversalCounts& o) {
    rays += o.rays, nodes += o.nodes, nodeLines += o.nodeLines, leaves += o.leaves;
    emptyLeaves += o.emptyLeaves;
    primTests += o.primTests, hits += o.hits;
    return *this;
  }
};

class KdTreeAccelerator final : public Accelerator {
 public:
  KdTreeAccelerator(const GeometryScene& scene, KdSplitMethod method, const KdCostModel& cost = {});

  std::string name() const override {
    return method_ == KdSplitMethod::Sah ? "kdtree" : "kdtree-median";
  }
  AccelStats stats() const override { return tree_.stats; }
  bool closestHit(const Ray& ray, Hit* hit) const override;
  bool anyHit(const Ray& ray) const override;

  // For tests: the tree as built, its leaves packed.
  const KdTree& tree() const { return tree_; }
  // closestHit (any = false) or anyHit (any = true) of the tree alone (no planes, no moving
  // objects), adding what the traversal did to `counts`. The same code as the plain queries,
  // compiled with counters; slower, so only for diagnosis.
  bool countedTrace(const Ray& ray, bool any, KdTraversalCounts* counts) const;

 private:
  bool closestHitUnrefined(const Ray& ray, Hit* hit) const;  // without refineFarHit
  // Front-to-back traversal; with kAny it returns at the first hit and leaves `hit` alone.
  // With kCount it adds its work to `counts`.
  template <bool kAny, bool kCount = false>
  bool trace(const Ray& ray, Hit* hit, KdTraversalCounts* counts = nullptr) const;
  // The moving instances, tested one by one at the ray's time.
  bool closestMoving(const Ray& ray, Hit* hit) const;
  bool anyMoving(const Ray& ray) const;

  struct MovingShape {
    const Shape* shape;
    const AnimatedTransform* motion;
    uint32_t instance;
  };
  struct MovingMesh {
    const KdTreeAccelerator* tree;  // of the mesh alone, in object space
    const Instance* placement;
    uint32_t instance;
    // The ray in the mesh's object space at its time.
    Ray objectRay(const Ray& ray) const;
  };
  // The tree of a deforming mesh alone (see KdPrimitives::gatherDeforming).
  KdTreeAccelerator(const TriangleMesh& deforming, KdSplitMethod method, const KdCostModel& cost);

  KdSplitMethod method_;
  KdPrimitives prims_;
  KdTree tree_;
  UnboundedShapes unbounded_;
  std::vector<MovingShape> movingShapes_;
  std::vector<std::unique_ptr<KdTreeAccelerator>> meshTrees_;  // per mesh that moves
  std::vector<MovingMesh> movingMeshes_;
};

}  // namespace glint
