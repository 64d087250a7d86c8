// glint — keyframed animation: tracks of (time, value) keys, the node hierarchy glTF animates,
// and their evaluation at any time.
//
// Times are seconds. A frame f of a sequence is at time f / fps; a ray's time inside the
// shutter maps to frameTime + open + rayTime · (close - open). Everything that moves is
// evaluated here, from the description; scenes/build samples transforms over the shutter
// into geometry/motion.h's AnimatedTransform keys.
#pragma once

#include <string>
#include <vector>

#include "geometry/math.h"
#include "geometry/motion.h"
#include "scenes/errors.h"

namespace glint {

enum class Interpolation {
  Step,         // the value of the last key at or before t (glTF STEP)
  Linear,       // linear; slerp for rotations (glTF LINEAR)
  CubicSpline,  // Hermite with per-key in/out tangents (glTF CUBICSPLINE)
  Smooth,       // Catmull-Rom through the keys (sidecar "smooth"): C1, passes every key
};

// Keys sorted by strictly increasing time. Before the first key the first value holds, after
// the last the last. CubicSpline stores three values per key: in-tangent, value, out-tangent
// (glTF's layout); the others one.
template <class T>
struct Track {
  Interpolation interpolation = Interpolation::Linear;
  std::vector<float> times;
  std::vector<T> values;
  SourceLocation where;

  bool empty() const { return times.empty(); }
  float startTime() const { return times.empty() ? 0.0f : times.front(); }
  float endTime() const { return times.empty() ? 0.0f : times.back(); }
};

// Evaluation (scenes/animation.cpp). Rotations are unit quaternions: Linear is slerp, cubic
// and smooth results are renormalised.
float evaluate(const Track<float>& track, double time);
Vec3f evaluate(const Track<Vec3f>& track, double time);
Quaternion evaluate(const Track<Quaternion>& track, double time);

// A node of the transform hierarchy. Its local transform is `matrix` when the file gave a
// matrix (glTF forbids animating those), else T · R · S from the rest values, each replaced
// by its track where one exists.
struct NodeDesc {
  std::string name;
  int parent = -1;  // index into SceneDescription::nodes
  bool hasMatrix = false;
  Transform matrix;
  Vec3f translation{0, 0, 0};
  Quaternion rotation;
  Vec3f scale{1, 1, 1};
  Track<Vec3f> translationTrack;
  Track<Quaternion> rotationTrack;
  Track<Vec3f> scaleTrack;
  SourceLocation where;

  bool hasTracks() const {
    return !translationTrack.empty() || !rotationTrack.empty() || !scaleTrack.empty();
  }
  Transform localAt(double time) const;
};

// Whether node `node` or any of its ancestors has a track.
bool isAnimated(const std::vector<NodeDesc>& nodes, int node);
// parent chain: world-from-node at `time`.
Transform worldFromNode(const std::vector<NodeDesc>& nodes, int node, double time);
// The time span covered by all tracks of all nodes, {0, 0} when nothing is keyed.
std::pair<double, double> animationRange(const std::vector<NodeDesc>& nodes);

}  // namespace glint
