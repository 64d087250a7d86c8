// glint — the spatial-median kd-tree builder: the course's baseline against which the SAH
// build (kdtree.cpp) is measured. Same nodes, same leaves, same traversal.
//
// Each cell is halved at the middle of its longest axis; a primitive goes to every side its
// bounds reach (flat ones lying in the plane go below). Recursion stops at few primitives, at
// the maximum depth, or when a split would copy every primitive into both children (a heap
// of duplicated or huge triangles, which halving can never separate).
#include "geometry/accel/kdtree.h"

namespace glint {

namespace {

class MedianBuilder {
 public:
  static constexpr uint32_t kMaxLeafPrims = 4;  // "a few": deeper only multiplies nodes

  MedianBuilder(const KdPrimitives& prims, KdTree* tree) : prims_(prims), tree_(*tree) {}

  void build() {
    for (uint32_t id = 0; id < prims_.size(); ++id) {
      tree_.bounds.extend(prims_.bounds[id]);
      stack_.push_back(id);
    }
    maxDepth_ = KdTree::maxDepthFor(prims_.size());
    buildNode(0, stack_.size(), tree_.bounds, 0);
  }

 private:
  // The node's primitives are stack_[begin, end); children's lists are appended at the top
  // of the stack and dropped once built, so the one vector is the only allocation.
  void buildNode(size_t begin, size_t end, const Bounds3f& box, int depth) {
    const size_t top = stack_.size();
    const uint32_t n = uint32_t(end - begin);
    const Vec3f d = box.diagonal();
    const int axis = d.x >= d.y ? (d.x >= d.z ? 0 : 2) : (d.y >= d.z ? 1 : 2);
    const float split = box.lower[axis] + d[axis] * 0.5f;
    const bool splittable = n > kMaxLeafPrims && depth < maxDepth_ && split > box.lower[axis] &&
                            split < box.upper[axis];
    size_t leftEnd = top, rightEnd = top;
    if (splittable) {
      for (size_t i = begin; i < end; ++i) {
        const Bounds3f& b = prims_.bounds[stack_[i]];
        if (b.lower[axis] < split || (b.lower[axis] == split && b.upper[axis] == split))
          stack_.push_back(stack_[i]);
      }
      leftEnd = stack_.size();
      for (size_t i = begin; i < end; ++i)
        if (prims_.bounds[stack_[i]].upper[axis] > split) stack_.push_back(stack_[i]);
      rightEnd = stack_.size();
    }
    if (!splittable || (leftEnd - top == n && rightEnd - leftEnd == n)) {
      tree_.addLeaf(stack_.data() + begin, n, box, depth);
      stack_.resize(top);
      return;
    }
    Bounds3f leftBox = box, rightBox = box;
    leftBox.upper[axis] = split;
    rightBox.lower[axis] = split;
    const uint32_t node = tree_.addInterior(box, depth);
    buildNode(top, leftEnd, leftBox, depth + 1);
    tree_.setInterior(node, axis, split);
    buildNode(leftEnd, rightEnd, rightBox, depth + 1);
    stack_.resize(top);
  }

  const KdPrimitives& prims_;
  KdTree& tree_;
  int maxDepth_ = 0;
  std::vector<uint32_t> stack_;
};

}  // namespace

void buildMedianKdTree(const KdPrimitives& prims, const KdCostModel& cost, KdTree* tree) {
  tree->cost = cost;
  MedianBuilder(prims, tree).build();
  tree->finish();
}

}  // namespace glint
