// glint — constructive solid geometry: a tree of set operations over convex solids, hosted as
// one analytic shape (and so as one Embree user primitive).
//
// Every leaf reports the span of the ray's whole line inside it (Shape::span); operators
// combine their children's sorted span lists with a sweep over the boundary crossings. Working
// on whole lines rather than on [tMin, tMax] makes rays that start inside a solid, nested trees
// and any-hit queries correct by construction.
//
// Tie rule (coincident surfaces: A - B sharing a face, A u A, touching spheres). Crossings of
// different children that lie on one surface (their normals parallel) and whose t values differ
// by no more than the sum of their widths are one event: the operator's inside/outside state is
// evaluated only before and after the whole group, so the result is a regularized set
// operation. A shared face of A - B is removed (no zero-thickness skin), A u A is A, touching
// solids merge without an inner wall. When a group changes the result, the boundary is
// attributed to the left-most child that has a crossing in the group.
//
// A crossing's width is its t's rounding-error bound plus its tie width: how far t moves when
// the leaf's surface moves within the leaf's tolerance (SurfaceTolerance: per axis, linear in
// the point), the distance between the surface as stored and the surface its author meant.
// The tolerance is the leaf's float placement against the same operations composed in double
// (MeantTransform: measured, so a rotation undone after a stretch costs what its rounding
// really was), plus the written precision of numbers of seven or more digits (0.3333333 * 3
// is 1), plus the rounding of the ray's own trip into the leaf. Faces that coincide as meant
// therefore tie however their leaves were written, and rounding can never make the decision
// flip from pixel to pixel. Faces further apart than the widths are real geometry: a 1e-4 skin
// on a unit solid is some 30 times wider than the widths of leaves written with 7-digit scale
// factors (about 3e-6 of the coordinates).
//
// Where a ray passes within the tolerances of an edge (at grazing angles, a long stretch of
// it), the leaves sharing a face must classify its crossings alike (issue 49, item 3):
//  * Crossings of two faces that meet at an edge never tie, however near the edge: they are two
//    events in the order of their t. (Tying them by t alone removed a leaf's corner sliver
//    against its twin's other face and left the twin's remaining sliver floating in the air.)
//  * Leaves keep their slivers, and report a line that misses them by less than their tolerance
//    as a span of zero length with both faces (leafSpan, geometry/shapes/primitive_math.h); a
//    face the line runs along within the tolerance does not bound a leaf's span. Dropped at
//    the leaf, a union's half lost the outer face a ray entered by at the seam, and the seam's
//    inner face bounded the result.
//  * An event takes at most one crossing of each child, pairing a joining crossing with its
//    nearer twin (combineSpans).
//  * The result is regularized once, at the root: a gap between two spans, then a span, whose
//    two crossings cannot be told apart by rounding, or come from two different leaves and tie
//    (the leaves' faces meet within their tolerances there), goes. A span between two faces of
//    one leaf (a ray clipping its corner) is as real as the plain solid's and stays.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/shape.h"

namespace glint {

enum class CsgOperation { Union, Intersection, Difference };

class CsgShape final : public Shape {
 public:
  static constexpr uint32_t kNone = ~0u;

  // ---- Building (the scene builder calls these, then finish()).
  // A leaf: a solid (shape->isSolid()) placed in tree space. Returns the node index. Leaves
  // are numbered in the order they are added: leaf k is material slot k. `placementError`
  // bounds treeFromLeaf against the transform its author meant (see the tie rule).
  uint32_t addLeaf(std::unique_ptr<Shape> shape, const Transform& treeFromLeaf,
                   const TransformError& placementError = {});
  // An operation over two or more nodes (difference: the first minus all the others).
  uint32_t addOperation(CsgOperation op, std::vector<uint32_t> children);
  // Fixes the root, computes bounds and the leaves' normal orientation. Every node must be
  // reachable from the root exactly once (a tree, not a DAG).
  void finish(uint32_t root);

  // ---- Shape
  const char* typeName() const override { return "csg"; }
  std::unique_ptr<Shape> clone() const override;  // a deep copy: each leaf cloned
  Bounds3f bounds() const override { return bounds_; }
  bool intersect(const Ray& ray, ShapeHit* hit) const override;
  ShapeSurface surface(const Ray& ray, const ShapeHit& hit, SurfaceDetails details) const override;
  uint32_t materialSlot(uint32_t part) const override { return part >> 3; }
  uint32_t materialSlotCount() const override { return uint32_t(leaves_.size()); }

  size_t leafCount() const { return leaves_.size(); }
  // Leaf k's surface tolerance (object space), for tests and `glint info`.
  const SurfaceTolerance& leafTolerance(size_t k) const { return leaves_[k].tolerance; }
  // All boundary crossings of the ray's whole line with the solid, as sorted spans in tree
  // space (for tests and nested use). Each Crossing::part is (leaf << 3) | leaf part.
  std::vector<Span> spans(const Ray& ray) const;

 private:
  struct Leaf {
    std::unique_ptr<Shape> shape;
    PlacedShape placed;
    SurfaceTolerance tolerance;  // in the leaf's object space
    bool flipNormal = false;     // under an odd number of difference right-hand sides
  };
  struct Node {
    CsgOperation op = CsgOperation::Union;
    std::vector<uint32_t> children;
    uint32_t leaf = kNone;  // set for leaves
  };

  // Per-query storage: the span lists, and the stretch of the line [tLo, tHi] the query needs
  // right (subtrees whose boxes miss it are skipped).
  struct Scratch {
    std::vector<Span> spans;
    float tLo = -kInfinity, tHi = kInfinity;
    Vec3f invD;  // 1 / the ray's direction, per axis (0 where it is 0)
  };
  // The query ray moved to where its line enters the root box (t shifted by `shift`, the move's
  // own rounding within `shiftError` along the ray), or the ray itself when it starts inside
  // or past the box. A ray from 300 units away carries t errors of some 300 ulps, as wide as
  // a 4e-5 wall of the tree: crossings of the wall's two faces would tie, and the wall would
  // vanish. From the box's entry the errors are those of the tree's own size.
  struct Reorigined {
    Ray ray;
    float shift, shiftError;
  };
  Reorigined reoriginate(const Ray& ray) const;
  // Appends the spans of `node` to scratch.spans; returns how many.
  size_t evaluate(uint32_t node, const Ray& ray, Scratch& scratch) const;
  // The whole tree's spans in scratch.spans (returns how many), without the slivers and cracks
  // below the tree's resolution (see the tie rule above).
  size_t evaluateRoot(const Ray& ray, float tLo, float tHi, Scratch& scratch) const;
  // `padded`: each leaf's box grown by its tolerance, for culling subtrees (a line that misses a
  // leaf by less is a near miss, whose crossings the operators need); the tree's own bounds are
  // not padded (a near miss alone is never a hit).
  Bounds3f nodeBounds(uint32_t node, bool padded) const;
  void orient(uint32_t node, bool flip);

  std::vector<Leaf> leaves_;
  std::vector<Node> nodes_;
  std::vector<Bounds3f> nodeBounds_;  // per node, padded, for culling subtrees the line misses
  uint32_t root_ = kNone;
  Bounds3f bounds_;
};

// Combines two sorted, disjoint span lists with `op` under the tie rule above (exposed for
// tests). `out` receives the result, sorted and disjoint.
void combineSpans(CsgOperation op, const Span* a, size_t na, const Span* b, size_t nb,
                  std::vector<Span>& out);

}  // namespace glint
